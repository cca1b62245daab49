#include "vdtnav/sensor/sweep_motion.hpp"

#include <cmath>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

SweepMotion SweepMotion::from_increment(const Pose3& increment, double dt) {
  VDTNAV_CHECK(std::isfinite(dt) && dt > 0.0, "SweepMotion: the increment's dt must be > 0");
  SweepMotion m;
  m.velocity = increment.translation() / dt;
  m.rates = so3_log(increment.linear()) / dt;
  return m;
}

std::size_t deskew(ObservationSet3& o, const SweepMotion& motion) {
  if (o.times.empty()) return 0;
  VDTNAV_CHECK(o.times.size() == o.points.size(),
               "deskew: " + std::to_string(o.times.size()) + " times for " +
                   std::to_string(o.points.size()) + " readings");
  for (std::size_t i = 0; i < o.points.size(); ++i) {
    const double tau = o.times[i];
    VDTNAV_CHECK(std::isfinite(tau),
                 "deskew: reading " + std::to_string(i) + "'s time is not finite");
    const Pose3 t = motion.at(tau);
    o.points[i] = t * o.points[i];
    o.directions[i] = t.linear() * o.directions[i];
    if (!o.point_covariances.empty())
      o.point_covariances[i] = t.linear() * o.point_covariances[i] * t.linear().transpose();
    if (!o.shared_jacobians.empty()) o.shared_jacobians[i] = t.linear() * o.shared_jacobians[i];
  }
  return o.points.size();
}

}  // namespace vdtnav
