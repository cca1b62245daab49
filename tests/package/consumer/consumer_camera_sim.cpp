// A user's program against the installed vdtnav::camera_sim: the PMD study's generated park.
#include <vdtnav/camera_sim/park_scene.hpp>

#include <cstdio>

int main() {
  using namespace vdtnav::rgbd_ground;
  const ParkScene park = generate_park();
  // The paved loop's centre line is pavement; the park's corner, far from every path, is grass.
  const bool on_loop = park.surface_at(park.loop.at(0)) == Surface::kPavement;
  const bool corner = park.surface_at(Eigen::Vector2d(0.3, 0.3)) == Surface::kGrass;
  const bool ok = on_loop && corner && !park.lamp_posts.empty();
  std::printf("park: %zu obstacles, %zu lamp posts: %s\n", park.obstacles.size(),
              park.lamp_posts.size(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
