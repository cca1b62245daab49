// The pose covariance of VdtOptimizerT from the implicit function theorem, (3.4)-(3.6) as
// corrected in SPEC, with shared, correlated-map and prior terms (see vdt_optimizer.hpp).
#include "vdtnav/estimation/vdt_optimizer.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Cholesky>

#include "lookup_order.hpp"
#include "scan_lm.hpp"

namespace vdtnav {
namespace {

using detail::lookup_order;
using detail::robust_weight;

}  // namespace

template <int Dim>
bool VdtOptimizerT<Dim>::covariance(const Observations& scan, const Pose& pose,
                                    const std::vector<char>& inliers, Covariance* cov) const {
  return covariance(scan, pose, inliers, lookup_order<Dim>(model_.map(), scan, pose), nullptr, 0.0,
                    cov);
}

template <int Dim>
bool VdtOptimizerT<Dim>::covariance(const Observations& scan, const Pose& pose,
                                    const std::vector<char>& inliers, const std::vector<int>& order,
                                    const Covariance* prior_information, double prior_s2,
                                    Covariance* cov) const {
  using Vector = typename Traits::Vector;
  using Rotation = typename Traits::Rotation;
  constexpr int kDoF = Traits::kDoF;
  const double s2 = scan.sigma_range * scan.sigma_range;
  const double m2 = model_.map_sigma() * model_.map_sigma();
  const Rotation r = Traits::rotation(pose);
  const Vector t = Traits::translation(pose);
  Covariance h = Covariance::Zero(), middle = Covariance::Zero();
  // Points with a covariance of their own (camera points) instead of one range error each, and
  // errors every point shares (a camera's roll, pitch and altitude): their sensitivity
  // S = sum_i d^2(d_VCD/2)/dX dp_i G_i adds the common-mode term S cov(theta) S^T to (3.4), not a
  // sum of independent per-point terms.
  const bool point_cov = !scan.point_covariances.empty();
  const int k_shared = scan.num_shared();
  Eigen::Matrix<double, kDoF, Eigen::Dynamic> shared =
      Eigen::Matrix<double, kDoF, Eigen::Dynamic>::Zero(kDoF, k_shared);
  // Map errors shared by the readings of one square (cube) of the map (VdtSensorModelOptions::
  // map_correlation_length): group k's sensitivity S_k = sum_{i in k} d^2(d_VCD/2)/dX dp_i (a
  // common shift of its endpoints) adds S_k sigma_c^2 S_k^T, like the shared errors above.
  const double c2 = model_.map_sigma_correlated() * model_.map_sigma_correlated();
  using GroupSensitivity = Eigen::Matrix<double, kDoF, Dim>;
  std::unordered_map<std::int64_t, GroupSensitivity> groups;
  const auto add_to_group_at = [&](const Vector& q, const GroupSensitivity& s) {
    auto [it, fresh] = groups.try_emplace(model_.map_error_group(q));
    if (fresh) it->second.setZero();
    it->second.noalias() += s;
  };
  // A map that knows its own covariance (VdtSensorModelOptions::map_uncertainty, 2D): the
  // endpoints' errors e_i of DT_v, correlated as the map says, enter through the sensitivity
  // d^2(d_VCD/2)/dX de_i = w_i d_pose_i^T; the squares above take the endpoints it does not know.
  const MapUncertainty2* map_uncertainty = Dim == 2 ? model_.options().map_uncertainty : nullptr;
  std::vector<Vector> map_points;
  std::vector<GroupSensitivity> map_sens, map_groups;
  const auto add_to_group = [&](int i, const GroupSensitivity& s, const BeamDisparityT<Dim>& b,
                                double w) {
    const Vector q = r * scan.points[i] + t;
    if (map_uncertainty != nullptr) {
      map_points.push_back(q);
      map_sens.push_back(w * b.d_pose.transpose());
      map_groups.push_back(s);
      return;
    }
    if (c2 > 0.0) add_to_group_at(q, s);
  };
  for (const int i : order) {
    if (!inliers[i]) continue;
    if (options_.covariance == CovarianceMethod::kImplicitFunction) {
      BeamCurvatureT<Dim> c;
      const BeamDisparityT<Dim> b = model_.disparity(r, t, scan.points[i], scan.directions[i], &c);
      const double w = robust_weight(options_.loss, options_.loss_scale, b.d.squaredNorm());
      h += w * c.hessian;  // (3.6), of d_VCD / 2
      if (point_cov) {
        middle.noalias() += (w * w) * c.cross_point * scan.point_covariances[i] *
                            c.cross_point.transpose();  // point noise via (3.5)
      } else {
        middle.noalias() += (w * w * s2) * c.cross * c.cross.transpose();  // range noise via (3.5)
      }
      middle.noalias() += (w * w * m2) * b.d_pose.transpose() * b.d_pose;  // map-noise floor
      if (k_shared > 0) shared.noalias() += w * c.cross_point * scan.shared_jacobians[i];
      add_to_group(i, w * c.cross_point, b, w);
    } else {
      const BeamDisparityT<Dim> b = model_.disparity(r, t, scan.points[i], scan.directions[i]);
      const double w = robust_weight(options_.loss, options_.loss_scale, b.d.squaredNorm());
      h.noalias() += w * b.d_pose.transpose() * b.d_pose;
      const auto cov_d = point_cov ? model_.disparity_covariance_point(b, scan.point_covariances[i])
                                   : model_.disparity_covariance(b, scan.sigma_range);
      middle.noalias() += (w * w) * b.d_pose.transpose() * cov_d * b.d_pose;
      if (k_shared > 0) {
        shared.noalias() += w * b.d_pose.transpose() * b.d_point * scan.shared_jacobians[i];
      }
      add_to_group(i, w * b.d_pose.transpose() * b.d_point, b, w);
    }
  }
  if (k_shared > 0) middle.noalias() += shared * scan.shared_covariance * shared.transpose();
  if constexpr (Dim == 2) {
    if (map_uncertainty != nullptr) {
      std::vector<char> known;
      middle.noalias() += map_uncertainty->propagate(map_points, map_sens, &known);
      for (std::size_t n = 0; c2 > 0.0 && n < map_points.size(); ++n) {
        if (!known[n]) add_to_group_at(map_points[n], map_groups[n]);
      }
    }
  }
  for (const auto& [key, s] : groups) middle.noalias() += c2 * s * s.transpose();
  if (prior_information != nullptr) {
    // A maximum a posteriori estimate: the prior's curvature joins H, and the noise of its mean
    // joins the middle term. In VCD units the prior is s^2 I (see solve()); its mean's covariance
    // I^-1 enters through the gradient s^2 I e: (s^2 I) I^-1 (s^2 I) = s^2 (s^2 I).
    h += *prior_information;
    middle += prior_s2 * *prior_information;
  }
  // Held components (4-DOF mode): the estimate does not move along them, so they drop out of H
  // and of the noise term; the unit diagonal keeps H invertible and their rows of cov zero.
  int free = 0;
  for (int k = 0; k < kDoF; ++k) {
    if (is_free(k)) {
      ++free;
      continue;
    }
    h.row(k).setZero();
    h.col(k).setZero();
    h(k, k) = 1.0;
    middle.row(k).setZero();
    middle.col(k).setZero();
  }
  const Eigen::LLT<Covariance> llt(h);
  if (llt.info() != Eigen::Success) return false;
  const Covariance h_inv = llt.solve(Covariance::Identity());
  *cov = h_inv * middle * h_inv;  // (3.4) with J = -H^{-1} d^2(d_VCD/2)/dX dr
  *cov = 0.5 * (*cov + cov->transpose());
  if (options_.variance_factor && m2 > 0.0) {
    // A posteriori variance factor of the weighted residuals (chi^2 / degrees of freedom).
    double chi2 = 0.0;
    int n = 0;
    for (const int i : order) {
      if (!inliers[i]) continue;
      const BeamDisparityT<Dim> b = model_.disparity(r, t, scan.points[i], scan.directions[i]);
      const auto cov_d = point_cov ? model_.disparity_covariance_point(b, scan.point_covariances[i])
                                   : model_.disparity_covariance(b, scan.sigma_range);
      chi2 += b.d.dot(cov_d.ldlt().solve(b.d));
      ++n;
    }
    const int dof = Dim * n - free;
    const double factor = dof > 0 ? chi2 / dof : 1.0;
    if (factor > 1.0) *cov *= factor;
  }
  return cov->allFinite();
}

template bool VdtOptimizerT<2>::covariance(const Observations&, const Pose&,
                                           const std::vector<char>&, Covariance*) const;
template bool VdtOptimizerT<2>::covariance(const Observations&, const Pose&,
                                           const std::vector<char>&, const std::vector<int>&,
                                           const Covariance*, double, Covariance*) const;
template bool VdtOptimizerT<3>::covariance(const Observations&, const Pose&,
                                           const std::vector<char>&, Covariance*) const;
template bool VdtOptimizerT<3>::covariance(const Observations&, const Pose&,
                                           const std::vector<char>&, const std::vector<int>&,
                                           const Covariance*, double, Covariance*) const;

}  // namespace vdtnav
