#include "vdtnav/estimation/vdt_ekf.hpp"

#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

void ekf_predict(MotionModelKind kind, const MotionNoise& noise, const OdometryStep& odo, Pose2& x,
                 Eigen::Matrix3d& p) {
  const double c = std::cos(x[2]), s = std::sin(x[2]);
  if (kind == MotionModelKind::kVelocity) {
    const double dt = odo.dt;
    Eigen::Matrix3d gx = Eigen::Matrix3d::Identity();  // (3.9)
    gx(0, 2) = -dt * odo.v * s;
    gx(1, 2) = dt * odo.v * c;
    Eigen::Matrix<double, 3, 2> gu = Eigen::Matrix<double, 3, 2>::Zero();  // (3.10)
    gu(0, 0) = dt * c;
    gu(1, 0) = dt * s;
    gu(2, 1) = dt;
    const Eigen::Vector2d q(noise.sigma_v * noise.sigma_v, noise.sigma_w * noise.sigma_w);
    x = Pose2(x[0] + dt * odo.v * c, x[1] + dt * odo.v * s,
              wrap_angle(x[2] + dt * odo.w));                            // (3.7)
    p = gx * p * gx.transpose() + gu * q.asDiagonal() * gu.transpose();  // (3.8)
    // Random-walk floor: variance grows linearly with time.
    p.diagonal() += dt * Eigen::Vector3d(noise.floor_xy_rate * noise.floor_xy_rate,
                                         noise.floor_xy_rate * noise.floor_xy_rate,
                                         noise.floor_yaw_rate * noise.floor_yaw_rate);
  } else {
    const Pose2& d = odo.delta;
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();  // d(x (+) d)/dx
    f(0, 2) = -s * d[0] - c * d[1];
    f(1, 2) = c * d[0] - s * d[1];
    Eigen::Matrix3d g = Eigen::Matrix3d::Identity();  // d(x (+) d)/dd
    g(0, 0) = c;
    g(0, 1) = -s;
    g(1, 0) = s;
    g(1, 1) = c;
    const double t = std::hypot(d[0], d[1]), rot = std::abs(d[2]);
    const double st = noise.a_tt * t + noise.a_tr * rot + noise.floor_t;
    const double sr = noise.a_rr * rot + noise.a_rt * t + noise.floor_r;
    const Eigen::Vector3d q(st * st, st * st, sr * sr);
    x = compose(x, d);
    p = f * p * f.transpose() + g * q.asDiagonal() * g.transpose();
  }
  p = 0.5 * (p + p.transpose());
}

void ekf_update_batch(const std::vector<Eigen::Vector2d>& innovation,
                      const std::vector<Eigen::Matrix<double, 2, 3>>& h,
                      const std::vector<Eigen::Matrix2d>& r, Pose2& x, Eigen::Matrix3d& p) {
  const int n = static_cast<int>(innovation.size());
  Eigen::MatrixXd hh(2 * n, 3), rr = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  Eigen::VectorXd nu(2 * n);
  for (int i = 0; i < n; ++i) {
    hh.middleRows<2>(2 * i) = h[i];
    rr.block<2, 2>(2 * i, 2 * i) = r[i];
    nu.segment<2>(2 * i) = innovation[i];
  }
  const Eigen::MatrixXd s = hh * p * hh.transpose() + rr;      // (3.13)
  const Eigen::MatrixXd k = p * hh.transpose() * s.inverse();  // (3.19), K = P H^T S^-1
  const Eigen::Vector3d dx = k * nu;                           // (3.20)
  x = Pose2(x[0] + dx[0], x[1] + dx[1], wrap_angle(x[2] + dx[2]));
  p = p - k * s * k.transpose();  // (3.21)
  p = 0.5 * (p + p.transpose());
}

void ekf_update_information(const std::vector<Eigen::Vector2d>& innovation,
                            const std::vector<Eigen::Matrix<double, 2, 3>>& h,
                            const std::vector<Eigen::Matrix2d>& r, Pose2& x, Eigen::Matrix3d& p) {
  Eigen::Matrix3d info = p.inverse();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < innovation.size(); ++i) {
    const Eigen::Matrix2d r_inv = r[i].inverse();
    const Eigen::Matrix<double, 3, 2> ht_rinv = h[i].transpose() * r_inv;
    info.noalias() += ht_rinv * h[i];
    b.noalias() += ht_rinv * innovation[i];
  }
  ekf_apply_information(info, b, x, p);
}

void ekf_apply_information(const Eigen::Matrix3d& info, const Eigen::Vector3d& b, Pose2& x,
                           Eigen::Matrix3d& p) {
  p = info.inverse();
  p = 0.5 * (p + p.transpose());
  const Eigen::Vector3d dx = p * b;
  x = Pose2(x[0] + dx[0], x[1] + dx[1], wrap_angle(x[2] + dx[2]));
}

VdtEkfLocalizer::VdtEkfLocalizer(const VdtMap2& map, const VdtEkfOptions& options, std::string name)
    : model_(map, options.sensor), options_(options), name_(std::move(name)) {
  VDTNAV_CHECK(options.min_inliers >= 1, "EKF: min_inliers must be >= 1");
  VDTNAV_CHECK(
      model_.map_sigma() > 0.0 || options.sensor.covariance == DisparityCovariance::kDiagonal,
      "EKF: the exact rank-one disparity covariance needs a map-noise floor > 0 to be invertible");
}

void VdtEkfLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  x_ = pose;
  p_ = covariance;
}

LocalizationResult VdtEkfLocalizer::update(const OdometryStep& odometry, const LaserScan& scan) {
  ekf_predict(options_.motion, options_.noise, odometry, x_, p_);
  const ScanPoints pts = scan_points(scan);
  thread_local std::vector<Eigen::Vector2d> nu;
  thread_local std::vector<Eigen::Matrix<double, 2, 3>> h;
  thread_local std::vector<Eigen::Matrix2d> r;
  nu.clear();
  h.clear();
  r.clear();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const BeamDisparity b = model_.disparity(x_, pts.points[i], pts.directions[i]);
    if (!b.inlier) continue;
    nu.push_back(-b.d);  // (3.12) corrected: the expected disparity is zero
    h.push_back(b.d_pose);
    r.push_back(model_.disparity_covariance(b, pts.sigma_range));
  }
  LocalizationResult result;
  result.inliers = static_cast<int>(nu.size());
  result.dropped =
      static_cast<int>(pts.size() + pts.dropped_not_finite + pts.dropped_out_of_range) -
      result.inliers;
  if (result.inliers < options_.min_inliers) {
    result.status = LocalizationStatus::kTooFewObservations;
  } else {
    ekf_update_information(nu, h, r, x_, p_);
    result.status = LocalizationStatus::kConverged;
    result.iterations = 1;
  }
  result.pose = x_;
  result.covariance = p_;
  result.has_covariance = true;
  return result;
}

}  // namespace vdtnav
