// The VDT EKF's map term M with the map's own covariance (VdtSensorModelOptions::
// map_uncertainty): the scan's sensitivity to the map's errors, reported on top of the filter's
// covariance.
#include "vdtnav/estimation/vdt_ekf.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Cholesky>

#include "scan_lm.hpp"
#include "vdtnav/map/map_uncertainty.hpp"

namespace vdtnav {

Eigen::Matrix3d VdtEkfLocalizer::map_covariance(const Eigen::Matrix3d& info, const Pose2& xi,
                                                const ScanPoints& pts,
                                                std::vector<BeamDisparity>* disparities) const {
  // As for the squares in update() (vdt_ekf.cpp), the term is the update's sensitivity to the
  // map, reported on top of the filter's covariance: reading i's sensitivity to an error e_i of
  // DT_v at its endpoint is S_i = info^-1 H_i^T R_i^-1 (info: the update's, the prior's
  // included), and the map knows cov(sum_i S_i e_i) with every correlation between its endpoints
  // (MapUncertainty::propagate). Endpoints it does not know fall back on the squares of
  // map_correlation_length (a common shift, S_i d_point_i).
  const Eigen::LDLT<Eigen::Matrix3d> info_ldlt(info);
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
    const double w = detail::robust_weight(options_.loss, options_.loss_scale, bd.d.squaredNorm());
    sens.push_back(info_ldlt.solve(w * bd.d_pose.transpose() * r.inverse()));
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

}  // namespace vdtnav
