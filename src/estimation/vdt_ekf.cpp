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
#include "vdtnav/map/map_uncertainty.hpp"

namespace vdtnav {

void ekf_apply_information(const Eigen::Matrix3d& info, const Eigen::Vector3d& b, Pose2& x,
                           Eigen::Matrix3d& p) {
  p = info.inverse();
  p = 0.5 * (p + p.transpose());
  const Eigen::Vector3d dx = p * b;
  x = Pose2(x[0] + dx[0], x[1] + dx[1], wrap_angle(x[2] + dx[2]));
}

namespace {

using Matrix32 = Eigen::Matrix<double, 3, 2>;

/// What the joint iterations of a Schmidt-Kalman update found (VdtEkfOptions::schmidt_map_errors).
struct SchmidtStep {
  Pose2 pose = Pose2::Zero();
  int inliers = 0, iterations = 0;
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();             ///< Pi_xx (+ the frame's shared errors)
  Eigen::Matrix3d out_of_view = Eigen::Matrix3d::Zero();   ///< (Pi Sigma^-1)_xx
  std::vector<std::pair<std::int64_t, Matrix32>> in_view;  ///< Pi_xk per square in view
};

/// Map errors shared per square (VdtSensorModelOptions::map_correlation_length) persist: the
/// robot sees one square in many scans, so the filter keeps cov(X, e_k) = C_k for every square k
/// it has seen (Schmidt-Kalman). The iterations solve for y = (X, e_k of the squares in view)
/// under the prior
///   Sigma = [P C; C^T sigma_c^2 I]
/// with reading i's disparity d_i(X) - d_point_i e_k (a map drawn off by e_k), by Gauss-Newton
/// on (y - y_pred)^T Sigma^-1 (y - y_pred) + sum r^T R^-1 r. The pose takes the joint optimum,
/// the squares' errors stay unestimated (mean 0, variance sigma_c^2), and P+ = Pi_xx,
/// C_k+ = Pi_xk for the squares in view, C_h+ = (Pi Sigma^-1)_xx C_h for the others (Pi the
/// joint posterior covariance; (I - K H) = Pi Sigma^-1): P is the error against the world, and a
/// square seen again adds no information about the pose beyond what its error allows. Errors
/// every point of the frame shares (theta) are considered as in the update: P+ gains
/// S cov(theta) S^T, S = Pi_x sum_i J_i^T R_i^-1 d_point_i G_i (J_i the reading's Jacobian in y).
SchmidtStep schmidt_iterations(const VdtSensorModel& model, const VdtEkfOptions& options,
                               const Pose2& x_pred, const Eigen::Matrix3d& p,
                               const std::unordered_map<std::int64_t, Matrix32>& cross,
                               const ScanPoints& pts, Pose2 xi);

}  // namespace

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
  if (cross_.empty()) {
    ekf_predict(options_.motion, options_.noise, odometry, x_, p_);
  } else {
    Eigen::Matrix3d f;
    ekf_predict(options_.motion, options_.noise, odometry, x_, p_, &f);
    for (auto& [key, c] : cross_) c = f * c;  // cov(X, e_k) moves with X
  }
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
  // S cov(theta) S^T with S = dX+/dtheta = info^-1 sum_i H_i^T R_i^-1 d_point_i G_i, the same
  // treatment as the optimizer's (vdt_optimizer.hpp). Estimating theta jointly instead would let
  // the frame's perspective (how a roll bends the ground mapping across the image) separate roll
  // from translation: exact in the model, but edge and map biases of a few centimetres make that
  // separation wrong by several sigma on rendered frames.
  const int k = pts.num_shared();
  const bool point_cov = !pts.point_covariances.empty();
  // Reading i's disparity covariance (point covariances: a camera's; else the range's).
  const auto noise_of = [&](const BeamDisparity& bd, std::size_t i) {
    return point_cov ? model_.disparity_covariance_point(bd, pts.point_covariances[i])
                     : model_.disparity_covariance(bd, pts.sigma_range);
  };
  const Eigen::Matrix3d prior_info = p_.inverse();
  Eigen::Matrix3d info = prior_info;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> cross(3, k);
  // With options_.schmidt_map_errors the iterations run jointly over the pose and the errors of
  // the squares in view (schmidt_iterations() above); otherwise below.
  const bool joint = model_.map_sigma_correlated() > 0.0 && options_.schmidt_map_errors &&
                     model_.options().map_uncertainty == nullptr;
  SchmidtStep schmidt;
  if (joint) {
    schmidt = schmidt_iterations(model_, options_, x_, p_, cross_, pts, xi);
    xi = schmidt.pose;
    result.inliers = schmidt.inliers;
    result.iterations = schmidt.iterations;
  }
  for (int it = 0; !joint && it < std::max(1, options_.max_iterations); ++it) {
    // Gauss-Newton step on (X - X_pred)^T P^-1 (X - X_pred) + sum d^T R^-1 d from the iterate
    // X_i; at X_i = X_pred this is the information-form update (3.13)-(3.21).
    info = prior_info;
    Eigen::Vector3d b = -prior_info * pose_error(xi, x_);
    cross.setZero();
    int used = 0;
    if (!(it == 0 && at_xi)) {
      model_.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, &disparities);
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const BeamDisparity& bd = disparities[i];
      if (!bd.inlier) continue;
      ++used;
      const Eigen::Matrix2d r_inv = noise_of(bd, i).inverse();
      const Eigen::Matrix<double, 3, 2> htri = bd.d_pose.transpose() * r_inv;
      info.noalias() += htri * bd.d_pose;
      b.noalias() -= htri * bd.d;  // (3.12) corrected: innovation -d, the expected disparity is 0
      if (k > 0) cross.noalias() += htri * (bd.d_point * pts.shared_jacobians[i]);
    }
    result.inliers = used;
    if (result.inliers < options_.min_inliers) break;
    const Eigen::Vector3d step = info.ldlt().solve(b);
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
  } else if (joint) {
    x_ = xi;
    for (auto& [key, ch] : cross_) ch = schmidt.out_of_view * ch;
    for (const auto& [key, c] : schmidt.in_view) cross_[key] = c;
    p_ = schmidt.p;
    prune_cross();
    map_term_.setZero();
    result.covariance = p_;
    result.status = LocalizationStatus::kConverged;
  } else {
    x_ = xi;
    const Eigen::Matrix3d info_inv = info.inverse();
    Eigen::Matrix3d pn = info_inv;
    if (k > 0) {
      const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> sens =
          info_inv * cross;  // dX+/dtheta (sign irrelevant in the product below)
      pn.noalias() += sens * pts.shared_covariance * sens.transpose();
    }
    p_ = 0.5 * (pn + pn.transpose());
    Eigen::Matrix3d map_term = Eigen::Matrix3d::Zero();
    if (model_.options().map_uncertainty != nullptr) {
      map_term = map_covariance(info - prior_info, xi, pts, &disparities);
    } else if (model_.map_sigma_correlated() > 0.0) {
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

Eigen::Matrix3d VdtEkfLocalizer::map_covariance(const Eigen::Matrix3d& scan_info, const Pose2& xi,
                                                const ScanPoints& pts,
                                                std::vector<BeamDisparity>* disparities) const {
  // As for the squares above, the term is the scan's own sensitivity to the map, reported on top
  // of the filter's covariance: reading i's sensitivity to an error e_i of DT_v at its endpoint
  // is S_i = scan_info^-1 H_i^T R_i^-1, and the map knows cov(sum_i S_i e_i) with every
  // correlation between its endpoints (MapUncertainty::propagate). Endpoints it does not know
  // fall back on the squares of map_correlation_length (a common shift, S_i d_point_i).
  const Eigen::LDLT<Eigen::Matrix3d> scan_ldlt(scan_info);
  const Eigen::Rotation2Dd rot(xi[2]);
  model_.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, disparities);
  const bool point_cov = !pts.point_covariances.empty();
  std::vector<std::size_t> inliers;
  std::vector<Eigen::Vector2d> world;
  std::vector<MapUncertainty2::Sensitivity> sens;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const BeamDisparity& bd = (*disparities)[i];
    if (!bd.inlier) continue;
    const Eigen::Matrix2d r = point_cov
                                  ? model_.disparity_covariance_point(bd, pts.point_covariances[i])
                                  : model_.disparity_covariance(bd, pts.sigma_range);
    inliers.push_back(i);
    world.push_back(rot * pts.points[i] + xi.head<2>());
    sens.push_back(scan_ldlt.solve(bd.d_pose.transpose() * r.inverse()));
  }
  std::vector<char> known;
  Eigen::Matrix3d term = model_.options().map_uncertainty->propagate(world, sens, &known);
  if (model_.map_sigma_correlated() > 0.0) {
    std::unordered_map<std::int64_t, Eigen::Matrix<double, 3, 2>> groups;
    for (std::size_t n = 0; n < inliers.size(); ++n) {
      if (known[n]) continue;
      auto [it, fresh] = groups.try_emplace(model_.map_error_group(world[n]));
      if (fresh) it->second.setZero();
      it->second.noalias() += sens[n] * (*disparities)[inliers[n]].d_point;
    }
    const double s2 = model_.map_sigma_correlated() * model_.map_sigma_correlated();
    for (const auto& [key, c] : groups) term.noalias() += s2 * c * c.transpose();
  }
  return term;
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

namespace {

// Documented at its declaration above.
SchmidtStep schmidt_iterations(const VdtSensorModel& model, const VdtEkfOptions& options,
                               const Pose2& x_pred, const Eigen::Matrix3d& p,
                               const std::unordered_map<std::int64_t, Matrix32>& cross,
                               const ScanPoints& pts, Pose2 xi) {
  const int k = pts.num_shared();
  const bool point_cov = !pts.point_covariances.empty();
  const double sigma_c = model.map_sigma_correlated();
  const double inv_c2 = 1.0 / (sigma_c * sigma_c);
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
  std::vector<Square> squares;
  std::unordered_map<std::int64_t, int> square_index;
  thread_local std::vector<BeamDisparity> disparities;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> cross_theta(3, k);
  Eigen::MatrixXd joint_info, prior_joint;
  SchmidtStep out;
  for (int it = 0; it < std::max(1, options.max_iterations); ++it) {
    Eigen::Matrix3d info = Eigen::Matrix3d::Zero();  // sum H^T R^-1 H
    Eigen::Vector3d hd = Eigen::Vector3d::Zero();    // sum H^T R^-1 d
    cross_theta.setZero();
    for (Square& s : squares) {
      s.hp.setZero();
      s.pp.setZero();
      s.pd.setZero();
      s.pg.setZero(2, k);
    }
    model.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, &disparities);
    const Eigen::Rotation2Dd rot(xi[2]);
    int used = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const BeamDisparity& bd = disparities[i];
      if (!bd.inlier) continue;
      ++used;
      const Eigen::Matrix2d r_inv =
          (point_cov ? model.disparity_covariance_point(bd, pts.point_covariances[i])
                     : model.disparity_covariance(bd, pts.sigma_range))
              .inverse();
      const Matrix32 htri = bd.d_pose.transpose() * r_inv;
      info.noalias() += htri * bd.d_pose;
      hd.noalias() += htri * bd.d;
      if (k > 0) cross_theta.noalias() += htri * (bd.d_point * pts.shared_jacobians[i]);
      const std::int64_t key = model.map_error_group(rot * pts.points[i] + xi.head<2>());
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
    out.inliers = used;
    if (used < options.min_inliers) break;
    // Sigma^-1 through the Schur complement Pc = P - C C^T / sigma_c^2 (X given the squares'
    // errors): [Pc^-1, -Pc^-1 C / s2; -C^T Pc^-1 / s2, I / s2 + C^T Pc^-1 C / s2^2].
    const int g = static_cast<int>(squares.size()), n = 3 + 2 * g;
    Eigen::Matrix<double, 3, Eigen::Dynamic> c(3, 2 * g);
    for (int j = 0; j < g; ++j) {
      const auto found = cross.find(squares[static_cast<std::size_t>(j)].key);
      c.middleCols<2>(2 * j) = found == cross.end() ? Matrix32::Zero() : found->second;
    }
    Eigen::Matrix3d pc = p - inv_c2 * c * c.transpose();
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
    y.head<3>() = pose_error(xi, x_pred);
    grad.head<3>() = hd;
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
    for (int j = 0; j < g; ++j) {
      squares[static_cast<std::size_t>(j)].error += delta.segment<2>(3 + 2 * j);
    }
    xi += delta.head<3>();
    xi[2] = wrap_angle(xi[2]);
    out.iterations = it + 1;
    if (delta.head<2>().norm() < 1e-5 && std::abs(delta[2]) < 1e-5) break;
  }
  out.pose = xi;
  if (out.inliers < options.min_inliers) return out;
  // The first three columns of Pi = joint_info^-1: Pi_xx and Pi_ex.
  const int g = static_cast<int>(squares.size()), n = 3 + 2 * g;
  const Eigen::MatrixXd pi = joint_info.ldlt().solve(Eigen::MatrixXd::Identity(n, 3));
  out.p = pi.topRows<3>();
  if (k > 0) {
    Eigen::MatrixXd cross_joint(n, k);
    cross_joint.topRows(3) = cross_theta;
    for (int j = 0; j < g; ++j) {
      cross_joint.middleRows(3 + 2 * j, 2) = -squares[static_cast<std::size_t>(j)].pg;
    }
    const Eigen::MatrixXd sens = pi.transpose() * cross_joint;  // dX+/dtheta
    out.p.noalias() += sens * pts.shared_covariance * sens.transpose();
  }
  out.p = 0.5 * (out.p + out.p.transpose());
  out.out_of_view = pi.transpose() * prior_joint.leftCols<3>();
  for (int j = 0; j < g; ++j) {
    out.in_view.emplace_back(squares[static_cast<std::size_t>(j)].key,
                             pi.middleRows<2>(3 + 2 * j).transpose());
  }
  return out;
}

}  // namespace

}  // namespace vdtnav
