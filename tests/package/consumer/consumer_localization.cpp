// A user's program against the installed vdtnav::localization: one scan matched on a VDT map,
// and an uncertain map fitted to the same scan.
#include <vdtnav/estimation/vdt_optimizer.hpp>
#include <vdtnav/mapping/uncertain_vdt_map.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  // A 4 m x 3 m box room.
  OccupancyGrid<2> occ(Eigen::Vector2i(80, 60), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int i = 0; i < 80; ++i) occ(Eigen::Vector2i(i, 5)) = occ(Eigen::Vector2i(i, 54)) = 1;
  for (int j = 0; j < 60; ++j) occ(Eigen::Vector2i(5, j)) = occ(Eigen::Vector2i(74, j)) = 1;
  const auto map = VdtMap2::build(occ);
  // Beams from (2.0, 1.5, 0) to the walls' centre lines (x = 0.275, 3.725; y = 0.275, 2.725).
  LaserScan scan;
  scan.angle_min = -M_PI;
  scan.angle_increment = 2 * M_PI / 360;
  for (int k = 0; k < 360; ++k) {
    const double a = scan.angle(k), c = std::cos(a), s = std::sin(a);
    const double tx = c > 0 ? (3.725 - 2.0) / c : c < 0 ? (0.275 - 2.0) / c : 1e9;
    const double ty = s > 0 ? (2.725 - 1.5) / s : s < 0 ? (0.275 - 1.5) / s : 1e9;
    scan.ranges.push_back(std::min(tx, ty));
  }
  const VdtOptimizer opt(map);
  const auto r = opt.solve(scan_points(scan), Pose2(2.05, 1.46, 0.03));
  mapping::MapScan ms;
  ms.pose = Pose2(2.0, 1.5, 0.0);
  ms.pose_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  ms.points = scan_points(scan);
  const auto um = mapping::UncertainVdtMap::fit({ms}, mapping::UncertainMapOptions{});
  const auto wall = um.evaluate(Eigen::Vector2d(2.0, 2.725));
  const bool map_ok = wall.inside && std::abs(wall.value.y()) < 0.01 &&
                      wall.covariance(1, 1) > 0.0 && std::isfinite(wall.covariance(1, 1));
  std::printf("uncertain map: DT_y %g, sigma %g at a wall %s\n", wall.value.y(),
              std::sqrt(wall.covariance(1, 1)), map_ok ? "ok" : "WRONG");
  const bool ok = map_ok && r.has_covariance && (r.pose - Pose2(2.0, 1.5, 0.0)).norm() < 2e-3;
  std::printf("pose (%g, %g, %g) %s: %s\n", r.pose[0], r.pose[1], r.pose[2], to_string(r.status),
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
