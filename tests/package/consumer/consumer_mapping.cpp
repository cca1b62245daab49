// A user's program against the installed vdtnav::mapping: an uncertain map (thesis ch. 5) fitted
// to one scan of a box room, saved to an uncertain map file and mapped back.
// `consumer_mapping no-ceres` (an installation built without Ceres): the fit is refused with a
// message that names Ceres.
#include <vdtnav/core/error.hpp>
#include <vdtnav/mapping/uncertain_map_file.hpp>
#include <vdtnav/mapping/uncertain_vdt_map.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "box_room_scan.hpp"

int main(int argc, char** argv) {
  using namespace vdtnav;
  mapping::MapScan ms;
  ms.pose = Pose2(2.0, 1.5, 0.0);
  ms.pose_covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-5).asDiagonal();
  ms.points = scan_points(box_room_scan());
  if (argc > 1 && std::strcmp(argv[1], "no-ceres") == 0) {
    try {
      (void)mapping::UncertainVdtMap::fit({ms}, mapping::UncertainMapOptions{});
    } catch (const ConfigError& e) {
      std::printf("uncertain map fit without Ceres: %s\n", e.what());
      return std::string(e.what()).find("Ceres") != std::string::npos ? 0 : 1;
    }
    std::printf("uncertain map fit without Ceres: NOT REFUSED\n");
    return 1;
  }
  const auto um = mapping::UncertainVdtMap::fit({ms}, mapping::UncertainMapOptions{});
  const auto wall = um.evaluate(Eigen::Vector2d(2.0, 2.725));
  const bool ok = wall.inside && std::abs(wall.value.y()) < 0.01 && wall.covariance(1, 1) > 0.0 &&
                  std::isfinite(wall.covariance(1, 1));
  mapping::save_uncertain_map("consumer.umap", um,
                              Grid<std::int8_t, 2>(Eigen::Vector2i(2, 2), GridFrame<2>(0.05, {})));
  const mapping::UncertainMapFile file = mapping::load_uncertain_map("consumer.umap");
  const auto again = file.map.evaluate(Eigen::Vector2d(2.0, 2.725));
  const bool same =
      again.inside && again.value == wall.value && again.covariance == wall.covariance;
  std::printf("uncertain map: DT_y %g, sigma %g at a wall %s; from consumer.umap %s\n",
              wall.value.y(), std::sqrt(wall.covariance(1, 1)), ok ? "ok" : "WRONG",
              same ? "the same" : "DIFFERENT");
  return ok && same ? 0 : 1;
}
