// A user's program against the installed vdtnav::map alone (no Ceres, OpenCV, PCL or simulators).
#include <vdtnav/map/map.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  OccupancyGrid<2> occ(Eigen::Vector2i(20, 20), GridFrame<2>(0.1, Eigen::Vector2d::Zero()), 0);
  occ(Eigen::Vector2i(10, 10)) = 1;
  const auto map = VdtMap2::build(occ);
  // DT_v = p - c(p): c is the centre of cell (10, 10) = (1.05, 1.05).
  const auto s = map.evaluate(Eigen::Vector2d(0.75, 1.05));
  const bool ok = std::abs(s.value.x() + 0.3) < 1e-4 && std::abs(s.value.y()) < 1e-4;
  std::printf("DT_v = (%g, %g): %s\n", s.value.x(), s.value.y(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
