// The VDT EKF: prediction and the information-form scan update (3.13)-(3.21), corrected per
// SPEC, and the bearing correction; the Schmidt joint iterations are in vdt_ekf_schmidt.cpp,
// the map's own covariance term in vdt_ekf_map_term.cpp.
#include "vdtnav/estimation/vdt_ekf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "scan_lm.hpp"
#include "scan_scores.hpp"
#include "vdt_ekf_schmidt.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {

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
    // The start is the maximum a posteriori pose (the prediction as the solve's prior), where
    // the iterated update below linearizes: a solve of the scan alone lands at its own minimum,
    // which a sparse observation (a camera's few boundary points) can leave far along the
    // directions it hardly constrains.
    const Eigen::LLT<Eigen::Matrix3d> llt(p_);
    const LocalizationResult r =
        llt.info() == Eigen::Success
            ? start_->solve(pts, xi, PosePrior<2>{x_, llt.solve(Eigen::Matrix3d::Identity())})
            : start_->solve(pts, xi);
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
  // The robust loss's IRLS weight of a reading at the iterate (VdtEkfOptions::loss).
  const auto weight_of = [&](const BeamDisparity& bd) {
    return detail::robust_weight(options_.loss, options_.loss_scale, bd.d.squaredNorm());
  };
  const Eigen::Matrix3d prior_info = p_.inverse();
  Eigen::Matrix3d info = prior_info;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, ScanPoints::kMaxShared> cross(3, k);
  // With options_.schmidt_map_errors the iterations run jointly over the pose and the errors of
  // the squares in view (schmidt_iterations(), vdt_ekf_schmidt.cpp); otherwise below.
  const bool joint = model_.map_sigma_correlated() > 0.0 && options_.schmidt_map_errors &&
                     model_.options().map_uncertainty == nullptr;
  detail::SchmidtStep schmidt;
  if (joint) {
    schmidt = detail::schmidt_iterations(model_, options_, x_, p_, cross_, pts, xi);
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
      const Eigen::Matrix2d r_inv = weight_of(bd) * noise_of(bd, i).inverse();  // (R_i / w_i)^-1
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
  // The correlated squares' term below needs the disparities at the estimate with their Jacobians;
  // the explained fraction is counted from the same lookups (their values and gate are those of
  // explained_fraction's), one pass over the scan instead of two.
  const bool squares =
      !joint && model_.options().map_uncertainty == nullptr && model_.map_sigma_correlated() > 0.0;
  double explained = 0.0;
  if (result.inliers >= options_.min_inliers) {
    if (squares) {
      model_.disparities(PoseTraits<2>::rotation(xi), xi.head<2>(), pts, nullptr, &disparities);
      explained = detail::explained_fraction_of(disparities, so.explained_distance);
    } else {
      explained = explained_fraction(model_, pts, xi, so.explained_distance);
    }
  }
  if (result.inliers < options_.min_inliers ||
      explained * static_cast<double>(valid) < options_.min_inliers) {
    result.status = LocalizationStatus::kTooFewObservations;  // prediction only
  } else if (so.enabled && explained < so.accept_fraction) {
    result.status = LocalizationStatus::kRefused;  // the map does not explain the scan
  } else if (options_.correction_gate > 0.0 && [&] {
               const Eigen::Vector3d dx = pose_error(xi, x_);
               return dx.dot((p_ + map_term_).ldlt().solve(dx)) > options_.correction_gate;
             }()) {
    result.status = LocalizationStatus::kRefused;  // a jump the prior calls implausible
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
      map_term = map_covariance(info, xi, pts, &disparities);
    } else if (squares) {
      // Map errors shared by the readings of one square of the map (VdtSensorModelOptions::
      // map_correlation_length), considered like the shared errors above: per group k,
      // S_k = info^-1 sum_{i in k} H_i^T R_i^-1 d_point_i and P+ gains S_k sigma_c^2 S_k^T. The
      // disparities at xi are those the explained fraction was counted from.
      const Eigen::Rotation2Dd rot(xi[2]);
      std::unordered_map<std::int64_t, Eigen::Matrix<double, 3, 2>> groups;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const BeamDisparity& bd = disparities[i];
        if (!bd.inlier) continue;
        const Eigen::Matrix2d r_inv = weight_of(bd) * noise_of(bd, i).inverse();
        const Eigen::Vector2d world = rot * pts.points[i] + xi.head<2>();
        auto [it, fresh] = groups.try_emplace(model_.map_error_group(world));
        if (fresh) it->second.setZero();
        it->second.noalias() += bd.d_pose.transpose() * r_inv * bd.d_point;
      }
      // The term is the update's sensitivity to the squares in view, S_k = info^-1 c_k with the
      // update's information (the prior's included), reported on top of the filter's covariance
      // relative to the map, not fed back into the filter. (The scan's information alone, the
      // term until issue 35, meant a past localized on the same squares; where a frame observes a
      // direction barely (boundaries along the track), its inverse made S_k explode: on the PMD
      // study 90 of 1655 frames reported 2 sigma over 1 m, up to 4e8 m, and a bearing fused
      // against that moved the estimate 3 m.)
      const Eigen::LDLT<Eigen::Matrix3d> info_ldlt(info);
      const double s2 = model_.map_sigma_correlated() * model_.map_sigma_correlated();
      for (const auto& [key, c] : groups) {
        const Eigen::Matrix<double, 3, 2> sens = info_ldlt.solve(c);
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
