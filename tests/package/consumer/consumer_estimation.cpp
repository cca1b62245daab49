// A user's program against the installed vdtnav::estimation: one scan matched on a VDT map.
#include <vdtnav/estimation/vdt_optimizer.hpp>

#include <cstdio>

#include "box_room_scan.hpp"

int main() {
  using namespace vdtnav;
  const auto map = VdtMap2::build(box_room());
  const VdtOptimizer opt(map);
  const auto r = opt.solve(scan_points(box_room_scan()), Pose2(2.05, 1.46, 0.03));
  const bool ok = r.has_covariance && (r.pose - Pose2(2.0, 1.5, 0.0)).norm() < 2e-3;
  std::printf("pose (%g, %g, %g) %s: %s\n", r.pose[0], r.pose[1], r.pose[2], to_string(r.status),
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
