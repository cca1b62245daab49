// A user's program against the installed vdtnav::estimation: one scan matched on a VDT map.
// `consumer_estimation no-ceres` (an installation built without Ceres): the same with the default
// dense solver, and the solver 'ceres' refused with a message that names Ceres.
#include <vdtnav/core/error.hpp>
#include <vdtnav/estimation/vdt_optimizer.hpp>

#include <cstdio>
#include <cstring>
#include <string>

#include "box_room_scan.hpp"

int main(int argc, char** argv) {
  using namespace vdtnav;
  const bool without_ceres = argc > 1 && std::strcmp(argv[1], "no-ceres") == 0;
  const auto map = VdtMap2::build(box_room());
  const VdtOptimizer opt(map);
  const auto r = opt.solve(scan_points(box_room_scan()), Pose2(2.05, 1.46, 0.03));
  const bool ok = r.has_covariance && (r.pose - Pose2(2.0, 1.5, 0.0)).norm() < 2e-3;
  std::printf("pose (%g, %g, %g) %s: %s\n", r.pose[0], r.pose[1], r.pose[2], to_string(r.status),
              ok ? "ok" : "WRONG");
  bool refused = true;
  if (without_ceres) {
    VdtOptimizerOptions with_ceres;
    with_ceres.solver = ScanSolver::kCeres;
    refused = false;
    try {
      const VdtOptimizer no(map, with_ceres);
    } catch (const ConfigError& e) {
      refused = std::string(e.what()).find("Ceres") != std::string::npos;
      std::printf("solver ceres without Ceres: %s\n", e.what());
    }
    if (!refused) std::printf("solver ceres without Ceres: NOT REFUSED\n");
  }
  return ok && refused ? 0 : 1;
}
