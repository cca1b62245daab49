#include "vdtnav/estimation/bearing_update.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"

namespace vdtnav {

double predicted_bearing(const Pose2& x, const Eigen::Vector2d& l,
                         const Eigen::Vector2d& sensor_offset, Eigen::RowVector3d* jacobian) {
  const double c = std::cos(x[2]), s = std::sin(x[2]);
  const Eigen::Vector2d rs(c * sensor_offset.x() - s * sensor_offset.y(),
                           s * sensor_offset.x() + c * sensor_offset.y());  // R(phi) s
  const Eigen::Vector2d q = l - x.head<2>() - rs;
  if (jacobian != nullptr) {
    const double n2 = q.squaredNorm();
    const Eigen::Vector2d drs(-rs.y(), rs.x());  // R'(phi) s
    // d atan2(q_y, q_x) = (q_x dq_y - q_y dq_x) / |q|^2 with dq = -(dx, dy) - R' s dphi.
    (*jacobian) << q.y() / n2, -q.x() / n2, -1.0 + (q.y() * drs.x() - q.x() * drs.y()) / n2;
  }
  return wrap_angle(std::atan2(q.y(), q.x()) - x[2]);
}

BearingUpdateResult ekf_bearing_update(const std::vector<BearingDetection>& detections,
                                       const std::vector<Landmark2>& landmarks,
                                       const BearingUpdateOptions& options, Pose2& x,
                                       Eigen::Matrix3d& p) {
  VDTNAV_CHECK(options.gate > 0.0, "bearing update: the gate must be > 0");
  BearingUpdateResult out;
  out.landmark.assign(detections.size(), -1);
  struct Candidate {
    double mahalanobis = std::numeric_limits<double>::infinity();
    Eigen::RowVector3d h = Eigen::RowVector3d::Zero();
    double nu = 0.0;
  };
  std::vector<Candidate> chosen(detections.size());
  const Eigen::Vector2d sensor = x.head<2>() + Eigen::Rotation2Dd(x[2]) * options.sensor_offset;
  for (std::size_t k = 0; k < detections.size(); ++k) {
    const BearingDetection& z = detections[k];
    VDTNAV_CHECK(z.sigma > 0.0 && std::isfinite(z.sigma) && std::isfinite(z.bearing),
                 "bearing update: a detection needs a finite bearing and a sigma > 0");
    // Nearest landmark of the reported class in the Mahalanobis sense, S = H P H^T + sigma^2.
    double best = std::numeric_limits<double>::infinity();
    Eigen::RowVector3d best_h = Eigen::RowVector3d::Zero();
    double best_nu = 0.0;
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      if (z.label >= 0 && landmarks[i].label != z.label) continue;
      if ((landmarks[i].position - sensor).norm() < options.min_range) continue;
      Eigen::RowVector3d h;
      const double nu = wrap_angle(
          z.bearing - predicted_bearing(x, landmarks[i].position, options.sensor_offset, &h));
      const double s = (h * p * h.transpose())(0, 0) + z.sigma * z.sigma;
      const double m = nu * nu / s;
      if (m < best) {
        best = m;
        best_h = h;
        best_nu = nu;
        out.landmark[k] = static_cast<int>(i);
      }
    }
    if (!(best <= options.gate)) {
      out.landmark[k] = -1;
      continue;
    }
    chosen[k] = {best, best_h, best_nu};
  }
  // One detection per landmark and frame: when several claim one landmark, the closest in the
  // Mahalanobis sense keeps it (the others are false positives beside a true detection).
  std::vector<int> owner(landmarks.size(), -1);
  for (std::size_t k = 0; k < detections.size(); ++k) {
    if (out.landmark[k] < 0) continue;
    int& o = owner[static_cast<std::size_t>(out.landmark[k])];
    if (o < 0 || chosen[k].mahalanobis < chosen[static_cast<std::size_t>(o)].mahalanobis) {
      o = static_cast<int>(k);
    }
  }
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < detections.size(); ++k) {
    if (out.landmark[k] < 0 ||
        owner[static_cast<std::size_t>(out.landmark[k])] != static_cast<int>(k)) {
      out.landmark[k] = -1;
      ++out.rejected;
      continue;
    }
    ++out.accepted;
    const double w = 1.0 / (detections[k].sigma * detections[k].sigma);
    info.noalias() += w * chosen[k].h.transpose() * chosen[k].h;
    b.noalias() += (w * chosen[k].nu) * chosen[k].h.transpose();
  }
  if (out.accepted == 0) return out;
  // Information form of the batch update (vdt_ekf.hpp): P+ = (P^-1 + H^T R^-1 H)^-1.
  const Eigen::LLT<Eigen::Matrix3d> prior(p);
  VDTNAV_CHECK(prior.info() == Eigen::Success,
               "bearing update: the prior covariance is not positive definite");
  info += prior.solve(Eigen::Matrix3d::Identity());
  ekf_apply_information(info, b, x, p);
  return out;
}

}  // namespace vdtnav
