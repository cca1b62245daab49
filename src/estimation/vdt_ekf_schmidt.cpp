// The VDT EKF with VdtEkfOptions::schmidt_map_errors: the joint Schmidt-Kalman iterations over
// the pose and the errors of the map's squares in view, and the pruning of the cross-covariances
// cov(X, e_k) the filter carries.
#include "vdt_ekf_schmidt.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <unordered_map>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "scan_lm.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"

namespace vdtnav {

void VdtEkfLocalizer::prune_cross() {
  // A square whose cross-covariance explains less than 1e-9 of P's trace no longer matters.
  const double sigma_c = model_.map_sigma_correlated();
  const double floor = 1e-9 * p_.trace() * sigma_c * sigma_c;
  for (auto it = cross_.begin(); it != cross_.end();) {
    it = it->second.squaredNorm() < floor ? cross_.erase(it) : std::next(it);
  }
}

namespace detail {

// Documented at its declaration in vdt_ekf_schmidt.hpp.
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
      // (R_i / w_i)^-1 with the robust loss's IRLS weight w_i (VdtEkfOptions::loss).
      const Eigen::Matrix2d r_inv =
          detail::robust_weight(options.loss, options.loss_scale, bd.d.squaredNorm()) *
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

}  // namespace detail

}  // namespace vdtnav
