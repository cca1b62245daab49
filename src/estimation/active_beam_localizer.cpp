#include "vdtnav/estimation/active_beam_localizer.hpp"

#include <cmath>
#include <utility>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

ActiveBeamLocalizer::ActiveBeamLocalizer(const VdtMap2& map,
                                         const ActiveBeamLocalizerOptions& options,
                                         std::string name)
    : options_(options),
      ekf_(map, options.ekf),
      selector_(map, options.beam, options.ekf.sensor),
      beam_(options.beam, options.strategy),
      name_(std::move(name)) {
  VDTNAV_CHECK(std::isfinite(options.bearing_tolerance) && options.bearing_tolerance > 0.0,
               "active beam localizer: bearing_tolerance must be > 0");
}

void ActiveBeamLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  ekf_.reset(pose, covariance);
  pose_ = pose;
  covariance_ = covariance;
  beam_ = RotatingBeamController(options_.beam, options_.strategy);
}

LocalizationResult ActiveBeamLocalizer::update(const OdometryStep& odometry,
                                               const ScanPoints& observations) {
  if (odometry.dt > 0.0) beam_.advance(odometry.dt);
  // The reading along the beam's bearing: the scan's nearest in bearing, within the tolerance.
  const double theta = beam_.bearing();
  ScanPoints one;
  one.sigma_range = observations.sigma_range;
  one.range_max = observations.range_max;
  std::size_t best = observations.size();
  double best_gap = options_.bearing_tolerance;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const Eigen::Vector2d& p = observations.points[i];
    const double gap = std::abs(wrap_angle(std::atan2(p.y(), p.x()) - theta));
    const double r = observations.ranges.empty() ? p.norm() : observations.ranges[i];
    if (gap <= best_gap && r >= options_.beam.range_min && r < options_.beam.range_max) {
      best_gap = gap;
      best = i;
    }
  }
  // Data association: the reading must agree with the ray cast from the prediction.
  if (best < observations.size()) {
    // The endpoint as seen from the robot's origin, where the ray cast starts.
    const Eigen::Vector2d& p = observations.points[best];
    if (!selector_.consistent(compose(pose_, odometry.delta), covariance_, std::atan2(p.y(), p.x()),
                              p.norm())) {
      best = observations.size();
    }
  }
  if (best < observations.size()) {
    one.points.push_back(observations.points[best]);
    one.directions.push_back(observations.directions[best]);
    one.ranges.push_back(observations.ranges.empty() ? observations.points[best].norm()
                                                     : observations.ranges[best]);
    one.beam.push_back(observations.beam.empty() ? best : observations.beam[best]);
    if (!observations.point_covariances.empty()) {
      one.point_covariances.push_back(observations.point_covariances[best]);
    }
  }
  LocalizationResult result = ekf_.update(odometry, one);
  pose_ = result.pose;
  covariance_ = result.covariance;
  if (beam_.needs_goal()) {
    const BeamSelection s = selector_.select(result.pose, result.covariance,
                                             selector_.segment_of(theta), options_.strategy);
    beam_.set_goal(s.segment, selector_);
  }
  return result;
}

}  // namespace vdtnav
