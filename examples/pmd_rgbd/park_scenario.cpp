// The PMD study's scenario: a generated park, its map of the boundaries between ground surfaces
// and the scooter's drive along its paths.
#include <algorithm>
#include <cstdio>
#include <utility>

#include "pmd_study.hpp"

namespace pmd_study {

using namespace vdtnav;
using namespace vdtnav::rgbd_ground;

Scenario make_scenario(std::uint64_t seed, std::size_t frames) {
  ParkSceneOptions po;
  po.seed = seed;
  ParkScene scene = generate_park(po);
  const double resolution = 0.05;
  OccupancyGrid<2> boundaries = scene.boundary_map(resolution);
  VdtMap2 map = VdtMap2::build(boundaries);
  std::printf("[park] %.0f x %.0f m, map %d x %d cells at %.2f m, %zu lamp posts, %zu obstacles\n",
              po.width, po.depth, boundaries.size().x(), boundaries.size().y(), resolution,
              scene.lamp_posts.size(), scene.obstacles.size());
  ScooterDriveOptions dopt;
  dopt.seed = seed;
  ScooterDrive drive = simulate_scooter_drive(scene, dopt);
  std::size_t n = drive.truth.size();
  if (frames > 0) n = std::min(n, frames);
  std::printf("[drive] %zu frames at %.0f Hz (%.0f s)\n", n, dopt.frame_rate, drive.time[n - 1]);
  return Scenario{std::move(scene), resolution, std::move(boundaries), std::move(map), dopt,
                  std::move(drive), n};
}

}  // namespace pmd_study
