// A user's program against the installed vdtnav::core (header-only): SE(2) composition.
#include <vdtnav/core/pose2.hpp>

#include <cmath>
#include <cstdio>

int main() {
  using namespace vdtnav;
  // Facing +y at (1, 0), one metre forward lands at (1, 1).
  const Pose2 a(1.0, 0.0, M_PI / 2), b(1.0, 0.0, 0.0);
  const Pose2 c = compose(a, b);
  const bool ok = (c - Pose2(1.0, 1.0, M_PI / 2)).norm() < 1e-12 &&
                  (between(a, c) - b).norm() < 1e-12 &&
                  std::abs(wrap_angle(3 * M_PI) - M_PI) < 1e-12;
  std::printf("compose (%g, %g, %g): %s\n", c.x(), c.y(), c.z(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
