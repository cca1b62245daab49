// A user's program against the installed vdtnav::sim: a noise-free LiDAR scan in a box.
#include <vdtnav/sim/lidar_simulator.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  // Walls through the cell centres x = 0.275 and 3.725, y = 0.275 and 2.725 (5 cm cells).
  OccupancyGrid<2> occ(Eigen::Vector2i(80, 60), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int i = 0; i < 80; ++i) occ(Eigen::Vector2i(i, 5)) = occ(Eigen::Vector2i(i, 54)) = 1;
  for (int j = 0; j < 60; ++j) occ(Eigen::Vector2i(5, j)) = occ(Eigen::Vector2i(74, j)) = 1;
  sim::TimedPose at;
  at.pose = Pose2(2.0, 1.5, 0.0);
  sim::LidarOptions lidar;
  lidar.fov = M_PI;
  lidar.angular_resolution = M_PI / 2;  // three beams: right, ahead, left
  const auto run = sim::simulate_run(occ, {at}, lidar, sim::NoiseProfile::none(), 1);
  const auto& r = run.scans.at(0).ranges;
  const bool ok = r.size() == 3 && std::abs(r[0] - 1.225) < 1e-9 && std::abs(r[1] - 1.725) < 1e-9 &&
                  std::abs(r[2] - 1.225) < 1e-9;
  std::printf("ranges %g %g %g: %s\n", r.at(0), r.at(1), r.at(2), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
