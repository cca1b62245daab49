#include "vdtnav/estimation/udt_localizers.hpp"

#include <cmath>
#include <vector>

#include <Eigen/LU>

#include "ceres_backend.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {

UdtBeam udt_beam(const DistanceFieldMap<2>& udt, const Pose2& pose, double c, double s,
                 const Eigen::Vector2d& p, const Eigen::Vector2d& u, double gate) {
  UdtBeam b;
  const Eigen::Vector2d rp(c * p.x() - s * p.y(), s * p.x() + c * p.y());
  const Eigen::Vector2d ru(c * u.x() - s * u.y(), s * u.x() + c * u.y());
  const auto smp = udt.evaluate(Eigen::Vector2d(pose[0] + rp.x(), pose[1] + rp.y()));
  b.e = smp.value;
  b.e_pose << smp.gradient.x(), smp.gradient.y(),
      smp.gradient.dot(Eigen::Vector2d(-rp.y(), rp.x()));
  b.e_range = smp.gradient.dot(ru);
  b.e_point << smp.gradient.x() * c + smp.gradient.y() * s,
      -smp.gradient.x() * s + smp.gradient.y() * c;
  b.inlier = smp.inside && std::abs(smp.value) < gate;
  return b;
}

namespace {

OccupancyGrid<2> checked(const OccupancyGrid<2>& map) {
  bool any = false;
  for (auto v : map.values()) any |= v != 0;
  VDTNAV_CHECK(any, "UDT localizer: the map has no occupied cell");
  return map;
}

Grid<float, 2> udt_of(const OccupancyGrid<2>& map) {
  return unsigned_distance_transform(nearest_occupied_cells(checked(map)));
}

}  // namespace

UdtOptimizationLocalizer::UdtOptimizationLocalizer(const OccupancyGrid<2>& map,
                                                   const UdtOptions& options)
    : udt_(udt_of(map)), options_(options) {
  VDTNAV_CHECK(options.gate > 0.0 && options.min_inliers >= 3,
               "udt-opt: gate must be > 0, min_inliers >= 3");
  VDTNAV_CHECK(detail::ceres_backend_available(),
               "udt-opt: its chamfer solve needs Ceres, and this vdtnav was built without it "
               "(install libceres-dev and rebuild; vdt-opt, vdt-ekf and udt-ekf need no Ceres)");
}

void UdtOptimizationLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& /*covariance*/) {
  pose_ = pose;
}

LocalizationResult UdtOptimizationLocalizer::update(const OdometryStep& odometry,
                                                    const ScanPoints& pts) {
  const Pose2 guess = compose(pose_, odometry.delta);
  LocalizationResult r;
  r.pose = guess;
  std::vector<int> beams;
  const double c = std::cos(guess[2]), s = std::sin(guess[2]);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (udt_beam(udt_, guess, c, s, pts.points[i], pts.directions[i], options_.gate).inlier) {
      beams.push_back(static_cast<int>(i));
    }
  }
  r.inliers = static_cast<int>(beams.size());
  r.dropped =
      static_cast<int>(pts.size() + pts.dropped_not_finite + pts.dropped_out_of_range) - r.inliers;
  if (r.inliers < options_.min_inliers) {
    r.status = LocalizationStatus::kTooFewObservations;
    pose_ = guess;
    return r;
  }
  double x[3] = {guess[0], guess[1], guess[2]};
  const detail::ChamferSolve summary =
      detail::solve_chamfer(udt_, pts, beams, options_.max_iterations, x);
  r.iterations = summary.iterations;
  r.final_cost = 2.0 * summary.final_cost;
  if (summary.failed) {
    r.status = LocalizationStatus::kDiverged;
    pose_ = guess;
    return r;
  }
  r.status = summary.converged ? LocalizationStatus::kConverged : LocalizationStatus::kNotConverged;
  r.pose = Pose2(x[0], x[1], wrap_angle(x[2]));
  r.has_covariance = false;  // C-LOG reports no uncertainty (Table 3.3)
  pose_ = r.pose;
  return r;
}

UdtEkfLocalizer::UdtEkfLocalizer(const OccupancyGrid<2>& map, const UdtOptions& options)
    : udt_(udt_of(map)),
      options_(options),
      map_sigma_(options.map_sigma >= 0.0 ? options.map_sigma
                                          : map.resolution() / std::sqrt(12.0)) {
  VDTNAV_CHECK(options.gate > 0.0 && options.min_inliers >= 1,
               "udt-ekf: gate must be > 0, min_inliers >= 1");
  VDTNAV_CHECK(map_sigma_ > 0.0, "udt-ekf: the map-noise floor must be > 0");
}

void UdtEkfLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  x_ = pose;
  p_ = covariance;
}

LocalizationResult UdtEkfLocalizer::update(const OdometryStep& odometry, const ScanPoints& pts) {
  ekf_predict(options_.motion, options_.noise, odometry, x_, p_);
  Eigen::Matrix3d info = p_.inverse();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  int used = 0;
  const double c = std::cos(x_[2]), s = std::sin(x_[2]);
  const double s2 = pts.sigma_range * pts.sigma_range, m2 = map_sigma_ * map_sigma_;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const UdtBeam beam = udt_beam(udt_, x_, c, s, pts.points[i], pts.directions[i], options_.gate);
    if (!beam.inlier) continue;
    // Scalar observation noise: the range's, or a point covariance's (errors shared by every point
    // are not modelled by this baseline).
    const double r =
        (pts.point_covariances.empty()
             ? s2 * beam.e_range * beam.e_range
             : double(beam.e_point * pts.point_covariances[i] * beam.e_point.transpose())) +
        m2;
    info.noalias() += beam.e_pose.transpose() * beam.e_pose / r;
    b.noalias() += beam.e_pose.transpose() * (-beam.e) / r;  // innovation: expected DT_u is 0
    ++used;
  }
  LocalizationResult result;
  result.inliers = used;
  result.dropped =
      static_cast<int>(pts.size() + pts.dropped_not_finite + pts.dropped_out_of_range) - used;
  if (used < options_.min_inliers) {
    result.status = LocalizationStatus::kTooFewObservations;
  } else {
    ekf_apply_information(info, b, x_, p_);
    result.status = LocalizationStatus::kConverged;
    result.iterations = 1;
  }
  result.pose = x_;
  result.covariance = p_;
  result.has_covariance = true;
  return result;
}

}  // namespace vdtnav
