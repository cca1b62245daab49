// A user's program against the installed vdtnav::eval: a pose's NEES and its chi-square interval.
#include <vdtnav/eval/nees.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  using namespace vdtnav::eval;
  // e = (0.2, 0, 0) with sigma_x = 0.1: NEES = (0.2 / 0.1)^2 = 4.
  const Eigen::Matrix3d cov = Eigen::Vector3d(0.01, 0.01, 0.0001).asDiagonal();
  const double e = nees(Pose2(1.2, 2.0, 0.5), Pose2(1.0, 2.0, 0.5), cov);
  // The mean of 1000 NEES of 3 dof: 95 % interval about 3 +- 0.15.
  const auto interval = anees_interval(1000, 3);
  const bool ok = std::abs(e - 4.0) < 1e-9 && interval.contains(3.0) && !interval.contains(3.3) &&
                  !interval.contains(2.7);
  std::printf("NEES %g, interval [%g, %g]: %s\n", e, interval.lower, interval.upper,
              ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
