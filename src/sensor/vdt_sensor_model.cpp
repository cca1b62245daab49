#include "vdtnav/sensor/vdt_sensor_model.hpp"

#include <cmath>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

VdtSensorModel::VdtSensorModel(const VdtMap2& map, const VdtSensorModelOptions& options)
    : map_(&map), options_(options) {
  VDTNAV_CHECK(std::isfinite(options.gate) && options.gate >= 0.0,
               "sensor model: gate must be >= 0");
  map_sigma_ = options.map_sigma >= 0.0 ? options.map_sigma : map.resolution() / std::sqrt(12.0);
}

bool VdtSensorModel::passes_gate(const Eigen::Vector2d& d) const noexcept {
  switch (options_.gate_mode) {
    case GateMode::kComponents:
      return std::abs(d.x()) < options_.gate && std::abs(d.y()) < options_.gate;
    case GateMode::kNorm:
      return d.squaredNorm() < options_.gate * options_.gate;
    case GateMode::kNone:
      return true;
  }
  return true;
}

BeamDisparity VdtSensorModel::disparity(const Pose2& pose, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& u) const {
  return disparity(pose, p, u, nullptr);
}

BeamDisparity VdtSensorModel::disparity(const Pose2& pose, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& u, BeamCurvature* curvature) const {
  return disparity(pose, std::cos(pose[2]), std::sin(pose[2]), p, u, curvature);
}

BeamDisparity VdtSensorModel::disparity(const Pose2& pose, double c, double s,
                                        const Eigen::Vector2d& p, const Eigen::Vector2d& u,
                                        BeamCurvature* curvature) const {
  BeamDisparity b;
  const Eigen::Vector2d rp(c * p.x() - s * p.y(), s * p.x() + c * p.y());  // R p
  const Eigen::Vector2d ru(c * u.x() - s * u.y(), s * u.x() + c * u.y());  // R u = dq/dr
  const Eigen::Vector2d q(pose[0] + rp.x(), pose[1] + rp.y());
  const Eigen::Vector2d rp_perp(-rp.y(), rp.x());  // R' p = dq/dphi
  const Eigen::Vector2d ru_perp(-ru.y(), ru.x());  // R' u = d^2 q / dphi dr

  Eigen::Matrix2d jac;
  std::array<Eigen::Matrix2d, 2> hess{Eigen::Matrix2d::Zero(), Eigen::Matrix2d::Zero()};
  if (options_.residual == ResidualMode::kNearestPoint) {
    const auto smp = map_->nearest_point_query(q);
    b.d = smp.value;
    jac = smp.jacobian;  // identity, Hessians zero
    b.inside = smp.inside;
  } else if (curvature != nullptr) {
    const auto smp = map_->evaluate_with_hessian(q);
    b.d = smp.value;
    jac = smp.jacobian;
    hess = smp.hessian;
    b.inside = smp.inside;
  } else {
    const auto smp = map_->evaluate(q);
    b.d = smp.value;
    jac = smp.jacobian;
    b.inside = smp.inside;
  }
  b.inlier = b.inside && passes_gate(b.d);
  // dq/dX = [I | R'p]
  b.d_pose.leftCols<2>() = jac;
  b.d_pose.col(2) = jac * rp_perp;
  b.d_range = jac * ru;

  if (curvature != nullptr) {
    // |d|^2 / 2: Hessian = J^T J + sum_c d_c d^2 d_c/dX^2 (Gauss-Newton term + curvature term).
    Eigen::Matrix<double, 2, 3> dq_dx;
    dq_dx << 1.0, 0.0, rp_perp.x(), 0.0, 1.0, rp_perp.y();
    curvature->hessian = b.d_pose.transpose() * b.d_pose;
    curvature->cross = b.d_pose.transpose() * b.d_range;
    for (int comp = 0; comp < 2; ++comp) {
      const double dc = b.d[comp];
      // d^2 d_c/dX^2 = Q^T H_c Q + (grad_c . d^2q/dphi^2) e_phi e_phi^T, d^2q/dphi^2 = -R p
      Eigen::Matrix3d h2 = dq_dx.transpose() * hess[comp] * dq_dx;
      h2(2, 2) += jac.row(comp).dot(-rp);
      // d^2 d_c/dX dr = Q^T H_c (R u) + (grad_c . R'u) e_phi
      Eigen::Vector3d x2 = dq_dx.transpose() * (hess[comp] * ru);
      x2[2] += jac.row(comp).dot(ru_perp);
      curvature->hessian += dc * h2;
      curvature->cross += dc * x2;
    }
  }
  return b;
}

Eigen::Vector2d VdtSensorModel::disparity_value(const Pose2& pose, double c, double s,
                                                const Eigen::Vector2d& p, bool* inlier) const {
  const Eigen::Vector2d q(pose[0] + c * p.x() - s * p.y(), pose[1] + s * p.x() + c * p.y());
  bool inside = false;
  Eigen::Vector2d d;
  if (options_.residual == ResidualMode::kNearestPoint) {
    const auto smp = map_->nearest_point_query(q);
    d = smp.value;
    inside = smp.inside;
  } else {
    d = map_->value(q, &inside);
  }
  if (inlier != nullptr) *inlier = inside && passes_gate(d);
  return d;
}

Eigen::Matrix2d VdtSensorModel::disparity_covariance(const BeamDisparity& b,
                                                     double sigma_range) const {
  const double s2 = sigma_range * sigma_range;
  Eigen::Matrix2d cov;
  if (options_.covariance == DisparityCovariance::kExactRankOne) {
    cov = s2 * b.d_range * b.d_range.transpose();  // both components share one range error
  } else {
    cov = (s2 * b.d_range.array().square()).matrix().asDiagonal();  // (2.13)-(2.15)
  }
  cov.diagonal().array() += map_sigma_ * map_sigma_;
  return cov;
}

double VdtSensorModel::vector_chamfer_distance(const Pose2& pose, const ScanPoints& scan,
                                               int* inliers) const {
  double vcd = 0.0;
  int n = 0;
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const BeamDisparity b = disparity(pose, c, s, scan.points[i], scan.directions[i]);
    if (!b.inlier) continue;
    vcd += b.d.squaredNorm();  // (2.17)
    ++n;
  }
  if (inliers != nullptr) *inliers = n;
  return vcd;
}

}  // namespace vdtnav
