// A user's program against the installed vdtnav::sensor: a reading's disparity (2.12) on a wall.
#include <vdtnav/sensor/vdt_sensor_model.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  // A wall along the row j = 30 (y = 1.525 m, cell centres), robot at (1, 0.5) facing +y.
  OccupancyGrid<2> occ(Eigen::Vector2i(40, 40), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int i = 0; i < 40; ++i) occ(Eigen::Vector2i(i, 30)) = 1;
  const auto map = VdtMap2::build(occ);
  const VdtSensorModel model(map);
  const Pose2 pose(1.0, 0.5, M_PI / 2);
  const Eigen::Vector2d u(1.0, 0.0);  // the beam along the robot's x axis
  // A reading 0.1 m short of the wall: d = p - c(p) points 0.1 m away from it (along -y).
  const auto d = model.disparity(pose, 0.925 * u, u);
  const bool ok = d.inside && std::abs(d.d.y() + 0.1) < 1e-3 && std::abs(d.d.x()) < 1e-3;
  std::printf("d = (%g, %g): %s\n", d.d.x(), d.d.y(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
