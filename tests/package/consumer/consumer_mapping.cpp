// A user's program against the installed vdtnav::mapping: an uncertain map (thesis ch. 5) fitted
// to one scan of a box room.
#include <vdtnav/mapping/uncertain_vdt_map.hpp>

#include <cmath>
#include <cstdio>

#include "box_room_scan.hpp"

int main() {
  using namespace vdtnav;
  mapping::MapScan ms;
  ms.pose = Pose2(2.0, 1.5, 0.0);
  ms.pose_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  ms.points = scan_points(box_room_scan());
  const auto um = mapping::UncertainVdtMap::fit({ms}, mapping::UncertainMapOptions{});
  const auto wall = um.evaluate(Eigen::Vector2d(2.0, 2.725));
  const bool ok = wall.inside && std::abs(wall.value.y()) < 0.01 && wall.covariance(1, 1) > 0.0 &&
                  std::isfinite(wall.covariance(1, 1));
  std::printf("uncertain map: DT_y %g, sigma %g at a wall %s\n", wall.value.y(),
              std::sqrt(wall.covariance(1, 1)), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
