#include "vdtnav/estimation/vdt_ekf.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

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
  if (options.optimizer_start) start_ = std::make_unique<VdtOptimizer>(map, options.start);
}

void VdtEkfLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  x_ = pose;
  p_ = covariance;
}

LocalizationResult VdtEkfLocalizer::update(const OdometryStep& odometry, const ScanPoints& pts) {
  ekf_predict(options_.motion, options_.noise, odometry, x_, p_);
  LocalizationResult result;
  const int valid = static_cast<int>(pts.size());
  const int invalid = static_cast<int>(pts.dropped_not_finite + pts.dropped_out_of_range);
  const GuessSearchOptions& so = options_.search;
  // The iterations start at the prediction, or, when the map explains the scan poorly there, at
  // the best pose of a window search around it.
  Pose2 xi = x_;
  if (so.enabled && explained_fraction(model_, pts, x_, so.explained_distance) < so.search_below) {
    xi = search_guess(model_, pts, x_, so, &p_);
  }
  if (start_ != nullptr) {
    const LocalizationResult r = start_->solve(pts, xi);
    if ((r.status == LocalizationStatus::kConverged ||
         r.status == LocalizationStatus::kNotConverged) &&
        explained_fraction(model_, pts, r.pose, so.explained_distance) >
            explained_fraction(model_, pts, xi, so.explained_distance)) {
      xi = r.pose;
    }
  }
  // Errors every point shares (a camera's roll, pitch, altitude: ObservationSet) are not
  // independent per point: they join the state for this update as theta ~ N(0, cov(theta)), each
  // point's disparity moving with d_point G_i theta, and are marginalised out afterwards (the pose
  // block of the joint covariance). Without them the state is the pose alone.
  const int k = pts.num_shared();
  const int n = 3 + k;
  using Info = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3 + ScanPoints::kMaxShared,
                             3 + ScanPoints::kMaxShared>;
  using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3 + ScanPoints::kMaxShared, 1>;
  Info prior_info = Info::Zero(n, n);
  prior_info.topLeftCorner<3, 3>() = p_.inverse();
  if (k > 0) prior_info.bottomRightCorner(k, k) = pts.shared_covariance.inverse();
  const bool point_cov = !pts.point_covariances.empty();
  Vec theta = Vec::Zero(n - 3);
  Info info = prior_info;
  Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, 3 + ScanPoints::kMaxShared> hi(2, n);
  for (int it = 0; it < std::max(1, options_.max_iterations); ++it) {
    // Gauss-Newton step on (z - z_pred)^T P_z^-1 (z - z_pred) + sum d^T R^-1 d from the iterate
    // z_i = (X_i, theta_i); at z_i = z_pred this is the information-form update (3.13)-(3.21).
    info = prior_info;
    Vec b = Vec::Zero(n);
    b.head<3>() = -p_.inverse() * pose_error(xi, x_);
    if (k > 0) b.tail(k) = -prior_info.bottomRightCorner(k, k) * theta;
    int used = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      // The point moved by the current estimate of the shared errors, p_i + G_i theta: the map is
      // relinearised there (a 0.2 degree roll moves ground points by 5 cm at 15 m, about the
      // width of a painted line, far beyond where the VDT is linear).
      const Eigen::Vector2d p =
          k > 0 ? Eigen::Vector2d(pts.points[i] + pts.shared_jacobians[i] * theta) : pts.points[i];
      const BeamDisparity bd = model_.disparity(xi, p, pts.directions[i]);
      if (!bd.inlier) continue;
      ++used;
      hi.leftCols<3>() = bd.d_pose;
      const Eigen::Vector2d d = bd.d;
      if (k > 0) hi.rightCols(k) = bd.d_point * pts.shared_jacobians[i];
      const Eigen::Matrix2d r_inv =
          (point_cov ? model_.disparity_covariance_point(bd, pts.point_covariances[i])
                     : model_.disparity_covariance(bd, pts.sigma_range))
              .inverse();
      const Eigen::Matrix<double, Eigen::Dynamic, 2, 0, 3 + ScanPoints::kMaxShared, 2> htri =
          hi.transpose() * r_inv;
      info.noalias() += htri * hi;
      b.noalias() -= htri * d;  // (3.12) corrected: innovation -d, the expected disparity is zero
    }
    result.inliers = used;
    if (result.inliers < options_.min_inliers) break;
    const Vec step = info.ldlt().solve(b);
    xi += step.head<3>();
    xi[2] = wrap_angle(xi[2]);
    if (k > 0) theta += step.tail(k);
    result.iterations = it + 1;
    if (step.head<2>().norm() < 1e-5 && std::abs(step[2]) < 1e-5) break;
  }
  result.dropped = valid + invalid - result.inliers;
  double explained = 0.0;
  if (result.inliers >= options_.min_inliers) {
    if (k > 0) {  // the points as the shared errors' estimate places them
      ScanPoints moved = pts;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        moved.points[i] += pts.shared_jacobians[i] * theta;
      }
      explained = explained_fraction(model_, moved, xi, so.explained_distance);
    } else {
      explained = explained_fraction(model_, pts, xi, so.explained_distance);
    }
  }
  if (result.inliers < options_.min_inliers ||
      explained * static_cast<double>(valid) < options_.min_inliers) {
    result.status = LocalizationStatus::kTooFewObservations;  // prediction only
  } else if (so.enabled && explained < so.accept_fraction) {
    result.status = LocalizationStatus::kNotConverged;  // the map does not explain the scan
  } else {
    x_ = xi;
    // The pose block of the joint covariance: theta marginalised out.
    const Eigen::Matrix3d pn = Info(info.inverse()).topLeftCorner<3, 3>();
    p_ = 0.5 * (pn + pn.transpose());
    result.status = LocalizationStatus::kConverged;
  }
  result.pose = x_;
  result.covariance = p_;
  result.has_covariance = true;
  return result;
}

}  // namespace vdtnav
