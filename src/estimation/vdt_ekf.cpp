#include "vdtnav/estimation/vdt_ekf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

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
  map_term_.setZero();
  cross_.clear();
}

LocalizationResult VdtEkfLocalizer::update(const OdometryStep& odometry, const ScanPoints& pts) {
  Eigen::Matrix3d f;
  ekf_predict(options_.motion, options_.noise, odometry, x_, p_, &f);
  for (auto& [key, c] : cross_) c = f * c;  // cov(X, e_k) moves with X
  LocalizationResult result;
  const int valid = static_cast<int>(pts.size());
  const int invalid = static_cast<int>(pts.dropped_not_finite + pts.dropped_out_of_range);
  const GuessSearchOptions& so = options_.search;
  // The iterations start at the prediction, or, when the map explains the scan poorly there, at
  // the best pose of a window search around it.
  Pose2 xi = x_;
  thread_local std::vector<BeamDisparity> disparities;  // scratch: no allocation per update
  // The disparities at the prediction serve both the test below and the first iteration when it
  // starts there (the explained fraction of guess_search.hpp from the same lookups).
  bool at_xi = false;
  if (so.enabled) {
    model_.disparities(PoseTraits<2>::rotation(x_), x_.head<2>(), pts, nullptr, &disparities);
    const double d2 = so.explained_distance * so.explained_distance;
    std::size_t n = 0;
    for (const BeamDisparity& b : disparities) n += b.inlier && b.d.squaredNorm() < d2;
    const double explained =
        pts.size() > 0 ? static_cast<double>(n) / static_cast<double>(pts.size()) : 0.0;
    if (explained < so.search_below) {
      xi = search_guess(model_, pts, x_, so, &p_);
    } else {
      at_xi = true;
    }
  }
  if (start_ != nullptr) {
    const LocalizationResult r = start_->solve(pts, xi);
    if ((r.status == LocalizationStatus::kConverged ||
         r.status == LocalizationStatus::kNotConverged) &&
        explained_fraction(model_, pts, r.pose, so.explained_distance) >
            explained_fraction(model_, pts, xi, so.explained_distance)) {
      xi = r.pose;
      at_xi = false;
    }
  }
  // Errors every point shares (a camera's roll, pitch, altitude: ObservationSet) are not
  // independent per point. They are *considered*, not estimated (a Schmidt update): the pose is
  // updated with theta at its mean 0, and its covariance gains the common-mode term
  // S cov(theta) S^T with S = dX+/dtheta = Pi_x sum_i J_i^T R_i^-1 d_point_i G_i, the same
  // treatment as the optimizer's (vdt_optimizer.hpp). Estimating theta jointly instead would let
  // the frame's perspective (how a roll bends the ground mapping across the image) separate roll
  // from translation: exact in the model, but edge and map biases of a few centimetres make that
  // separation wrong by several sigma on rendered frames.
  //
  // Map errors shared per square (VdtSensorModelOptions::map_correlation_length) are considered
  // the same way. By default the scan's own sensitivity to them is reported on top (below). With
  // options_.schmidt_map_errors they persist: the robot sees one square in many scans, so the
  // filter keeps cov(X, e_k) = C_k for every square k it has seen (Schmidt-Kalman). The iterations
  // solve for y = (X, e_k of the squares in view) under the prior
  //   Sigma = [P C; C^T sigma_c^2 I]
  // with reading i's disparity d_i(X) - d_point_i e_k (a map drawn off by e_k); the pose takes the
  // joint optimum, the squares' errors stay unestimated (mean 0, variance sigma_c^2), and
  // P+ = Pi_xx, C_k+ = Pi_xk for the squares in view, C_h+ = (Pi Sigma^-1)_xx C_h for the others
  // (Pi the joint posterior covariance): the covariance is the error against the world, and a
  // square seen again adds no information about the pose beyond what its error allows.
  const int k = pts.num_shared();
  const bool point_cov = !pts.point_covariances.empty();
  const double sigma_c = model_.map_sigma_correlated();
  // The joint (Schmidt-Kalman) iterations: options_.schmidt_map_errors.
  const bool joint = sigma_c > 0.0 && options_.schmidt_map_errors;
  const double inv_c2 = joint ? 1.0 / (sigma_c * sigma_c) : 0.0;
  // Reading i's disparity covariance (point covariances: a camera's; else the range's).
  const auto noise_of = [&](const BeamDisparity& bd, std::size_t i) {
    return point_cov ? model_.disparity_covariance_point(bd, pts.point_covariances[i])
                     : model_.disparity_covariance(bd, pts.sigma_range);
  };
  using Matrix32 = Eigen::Matrix<double, 3, 2>;
  // Per square in view: sum H^T R^-1 d_point (3x2), d_point^T R^-1 d_point (2x2),
  // d_point^T R^-1 d (2), d_point^T R^-1 d_point G (2 x k), and the iterate of its error.
  struct Square {
    std::int64_t key = 0;
    Matrix32 hp = Matrix32::Zero();
    Eigen::Matrix2d pp = Eigen::Matrix2d::Zero();
    Eigen::Vector2d pd = Eigen::Vector2d::Zero();
    Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, ScanPoints::kMaxShared> pg;
    Eigen::Vector2d error = Eigen::Vector2d::Zero();
  };
  thread_local std::vector<Square> squares;
  thread_local std::unordered_map<std::int64_t, int> square_index;
  squares.clear();
  square_index.clear();
  Eigen::Matrix3d info;         // pose block of the joint information
  Eigen::MatrixXd joint_info;   // (3 + 2G)^2, joint only
  Eigen::MatrixXd prior_joint;  // Sigma^-1 of the last iteration, joint only
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> cross(3, k);
  const Eigen::Matrix3d prior_info = p_.inverse();
  for (int it = 0; it < std::max(1, options_.max_iterations); ++it) {
    // Gauss-Newton step on (y - y_pred)^T Sigma^-1 (y - y_pred) + sum r^T R^-1 r from the
    // iterate; at X_i = X_pred without map errors this is the information-form update
    // (3.13)-(3.21).
    // Without the joint iterations, info and b start from the prior (P^-1, -P^-1 (X_i - X_pred));
    // the joint iterations add the prior of y below and need the scan's sums alone.
    const Eigen::Vector3d e = pose_error(xi, x_);
    info = joint ? Eigen::Matrix3d::Zero().eval() : prior_info;
    Eigen::Vector3d b = joint ? Eigen::Vector3d::Zero().eval() : (-prior_info * e).eval();
    cross.setZero();
    for (Square& s : squares) {
      s.hp.setZero();
      s.pp.setZero();
      s.pd.setZero();
      s.pg.setZero(2, k);
    }
    int used = 0;
    if (!(it == 0 && at_xi)) {
      model_.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, &disparities);
    }
    const Eigen::Rotation2Dd rot(xi[2]);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const BeamDisparity& bd = disparities[i];
      if (!bd.inlier) continue;
      ++used;
      const Eigen::Matrix2d r_inv = noise_of(bd, i).inverse();
      const Eigen::Matrix<double, 3, 2> htri = bd.d_pose.transpose() * r_inv;
      info.noalias() += htri * bd.d_pose;
      b.noalias() -= htri * bd.d;  // (3.12) corrected: innovation -d, the expected disparity is 0
      if (k > 0) cross.noalias() += htri * (bd.d_point * pts.shared_jacobians[i]);
      if (joint) {
        const std::int64_t key = model_.map_error_group(rot * pts.points[i] + xi.head<2>());
        auto [found, fresh] = square_index.try_emplace(key, static_cast<int>(squares.size()));
        if (fresh) {
          squares.emplace_back();
          squares.back().key = key;
          squares.back().pg.setZero(2, k);
        }
        Square& s = squares[static_cast<std::size_t>(found->second)];
        const Eigen::Matrix2d ptri = bd.d_point.transpose() * r_inv;
        s.hp.noalias() += htri * bd.d_point;
        s.pp.noalias() += ptri * bd.d_point;
        s.pd.noalias() += ptri * bd.d;
        if (k > 0) s.pg.noalias() += ptri * (bd.d_point * pts.shared_jacobians[i]);
      }
    }
    result.inliers = used;
    if (result.inliers < options_.min_inliers) break;
    Eigen::Vector3d step;
    if (!joint) {
      step = info.ldlt().solve(b);
    } else {
      // Sigma^-1 through the Schur complement Pc = P - C C^T / sigma_c^2 (X given the squares'
      // errors): [Pc^-1, -Pc^-1 C / s2; -C^T Pc^-1 / s2, I / s2 + C^T Pc^-1 C / s2^2].
      const int g = static_cast<int>(squares.size()), n = 3 + 2 * g;
      Eigen::Matrix<double, 3, Eigen::Dynamic> c(3, 2 * g);
      for (int j = 0; j < g; ++j) {
        const auto found = cross_.find(squares[static_cast<std::size_t>(j)].key);
        c.middleCols<2>(2 * j) = found == cross_.end() ? Matrix32::Zero() : found->second;
      }
      Eigen::Matrix3d pc = p_ - inv_c2 * c * c.transpose();
      pc = 0.5 * (pc + pc.transpose());
      const Eigen::Matrix3d pc_inv = pc.inverse();
      const Eigen::Matrix<double, 3, Eigen::Dynamic> a = pc_inv * c * inv_c2;  // Pc^-1 C / s2
      prior_joint.setZero(n, n);
      prior_joint.topLeftCorner<3, 3>() = pc_inv;
      prior_joint.topRightCorner(3, 2 * g) = -a;
      prior_joint.bottomLeftCorner(2 * g, 3) = -a.transpose();
      prior_joint.bottomRightCorner(2 * g, 2 * g) = c.transpose() * a * inv_c2;
      prior_joint.bottomRightCorner(2 * g, 2 * g).diagonal().array() += inv_c2;
      // The scan's information in y: H_x = d_pose, H_e = -d_point.
      joint_info = prior_joint;
      joint_info.topLeftCorner<3, 3>() += info;
      Eigen::VectorXd y(n), grad(n);
      y.head<3>() = e;
      grad.head<3>() = -b;  // sum H^T R^-1 d
      for (int j = 0; j < g; ++j) {
        const Square& s = squares[static_cast<std::size_t>(j)];
        joint_info.block<3, 2>(0, 3 + 2 * j) -= s.hp;
        joint_info.block<2, 3>(3 + 2 * j, 0) -= s.hp.transpose();
        joint_info.block<2, 2>(3 + 2 * j, 3 + 2 * j) += s.pp;
        y.segment<2>(3 + 2 * j) = s.error;
        // The residual at the iterate is d - d_point e: the gradient of its cost in X and e.
        grad.head<3>() -= s.hp * s.error;
        grad.segment<2>(3 + 2 * j) = s.pp * s.error - s.pd;
      }
      grad.noalias() += prior_joint * y;
      const Eigen::VectorXd delta = joint_info.ldlt().solve(-grad);
      step = delta.head<3>();
      for (int j = 0; j < g; ++j) {
        squares[static_cast<std::size_t>(j)].error += delta.segment<2>(3 + 2 * j);
      }
    }
    xi += step;
    xi[2] = wrap_angle(xi[2]);
    result.iterations = it + 1;
    if (step.head<2>().norm() < 1e-5 && std::abs(step[2]) < 1e-5) break;
  }
  result.dropped = valid + invalid - result.inliers;
  const double explained = result.inliers < options_.min_inliers
                               ? 0.0
                               : explained_fraction(model_, pts, xi, so.explained_distance);
  if (result.inliers < options_.min_inliers ||
      explained * static_cast<double>(valid) < options_.min_inliers) {
    result.status = LocalizationStatus::kTooFewObservations;  // prediction only
  } else if (so.enabled && explained < so.accept_fraction) {
    result.status = LocalizationStatus::kRefused;  // the map does not explain the scan
  } else {
    x_ = xi;
    Eigen::Matrix3d pn;
    if (!joint) {
      const Eigen::Matrix3d info_inv = info.inverse();
      pn = info_inv;
      if (k > 0) {
        const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> sens =
            info_inv * cross;  // dX+/dtheta (sign irrelevant in the product below)
        pn.noalias() += sens * pts.shared_covariance * sens.transpose();
      }
      p_ = 0.5 * (pn + pn.transpose());
      Eigen::Matrix3d map_term = Eigen::Matrix3d::Zero();
      if (model_.map_sigma_correlated() > 0.0) {
        // Map errors shared by the readings of one square of the map (VdtSensorModelOptions::
        // map_correlation_length), considered like the shared errors above: per group k,
        // S_k = info^-1 sum_{i in k} H_i^T R_i^-1 d_point_i and P+ gains S_k sigma_c^2 S_k^T.
        const Eigen::Rotation2Dd rot(xi[2]);
        std::unordered_map<std::int64_t, Eigen::Matrix<double, 3, 2>> groups;
        model_.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, &disparities);
        for (std::size_t i = 0; i < pts.size(); ++i) {
          const BeamDisparity& bd = disparities[i];
          if (!bd.inlier) continue;
          const Eigen::Matrix2d r_inv = noise_of(bd, i).inverse();
          const Eigen::Vector2d world = rot * pts.points[i] + xi.head<2>();
          auto [it, fresh] = groups.try_emplace(model_.map_error_group(world));
          if (fresh) it->second.setZero();
          it->second.noalias() += bd.d_pose.transpose() * r_inv * bd.d_point;
        }
        // A shift of the map moves everything localized on it, the filter's past included: the
        // term is the scan's own sensitivity (its information without the prior), reported on top
        // of the filter's covariance relative to the map, not fed back into the filter.
        const Eigen::Matrix3d scan_info = info - prior_info;
        const Eigen::LDLT<Eigen::Matrix3d> scan_ldlt(scan_info);
        const double s2 = model_.map_sigma_correlated() * model_.map_sigma_correlated();
        for (const auto& [key, c] : groups) {
          const Eigen::Matrix<double, 3, 2> sens = scan_ldlt.solve(c);
          map_term.noalias() += s2 * sens * sens.transpose();
        }
      }
      map_term_ = 0.5 * (map_term + map_term.transpose());
    } else {
      const int g = static_cast<int>(squares.size()), n = 3 + 2 * g;
      // The first three columns of Pi = joint_info^-1: Pi_xx and Pi_ex.
      const Eigen::LDLT<Eigen::MatrixXd> ldlt(joint_info);
      const Eigen::MatrixXd pi = ldlt.solve(Eigen::MatrixXd::Identity(n, 3));
      pn = pi.topRows<3>();
      if (k > 0) {
        Eigen::MatrixXd cross_joint(n, k);
        cross_joint.topRows(3) = cross;
        for (int j = 0; j < g; ++j) {
          cross_joint.middleRows(3 + 2 * j, 2) = -squares[static_cast<std::size_t>(j)].pg;
        }
        const Eigen::MatrixXd sens = pi.transpose() * cross_joint;  // dX+/dtheta
        pn.noalias() += sens * pts.shared_covariance * sens.transpose();
      }
      // The squares out of view: C_h+ = (I - K H)_xx C_h = (Pi Sigma^-1)_xx C_h.
      const Eigen::Matrix3d t = pi.transpose() * prior_joint.leftCols<3>();
      for (auto& [key, ch] : cross_) ch = t * ch;
      for (int j = 0; j < g; ++j) {
        cross_[squares[static_cast<std::size_t>(j)].key] = pi.middleRows<2>(3 + 2 * j).transpose();
      }
      prune_cross();
      p_ = 0.5 * (pn + pn.transpose());
      map_term_.setZero();
    }
    result.covariance = p_ + map_term_;
    result.status = LocalizationStatus::kConverged;
  }
  result.pose = x_;
  if (result.status != LocalizationStatus::kConverged) {
    map_term_.setZero();
    result.covariance = p_;
  }
  result.has_covariance = true;
  return result;
}

void VdtEkfLocalizer::prune_cross() {
  // A square whose cross-covariance explains less than 1e-9 of P's trace no longer matters.
  const double sigma_c = model_.map_sigma_correlated();
  const double floor = 1e-9 * p_.trace() * sigma_c * sigma_c;
  for (auto it = cross_.begin(); it != cross_.end();) {
    it = it->second.squaredNorm() < floor ? cross_.erase(it) : std::next(it);
  }
}

BearingUpdateResult VdtEkfLocalizer::update_bearings(
    const std::vector<BearingDetection>& detections, const std::vector<Landmark2>& landmarks,
    const BearingUpdateOptions& options) {
  // A bearing measures the pose in the world, whose error includes the map's share M: gate and
  // update with P + M, then split the result. With A = I - K H = (P + M)+ (P + M)^-1 (information
  // form), (P + M)+ = A P A^T + K R K^T + A M A^T: the map's share becomes A M A^T, the rest is
  // the filter's. The Schmidt filter's P is already the error against the world (M = 0); its
  // squares' cross-covariances follow the correction, C_k+ = A C_k.
  const Eigen::Matrix3d prior = p_ + map_term_;
  Eigen::Matrix3d total = prior;
  const BearingUpdateResult r = ekf_bearing_update(detections, landmarks, options, x_, total);
  if (r.accepted == 0) return r;
  const Eigen::Matrix3d a = total * prior.inverse();
  map_term_ = a * map_term_ * a.transpose();
  map_term_ = 0.5 * (map_term_ + map_term_.transpose());
  p_ = total - map_term_;
  p_ = 0.5 * (p_ + p_.transpose());
  for (auto& [key, c] : cross_) c = a * c;
  return r;
}

}  // namespace vdtnav
