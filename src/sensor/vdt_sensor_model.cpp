#include "vdtnav/sensor/vdt_sensor_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

template <int Dim>
VdtSensorModelT<Dim>::VdtSensorModelT(const Map& map, const VdtSensorModelOptions& options)
    : map_(&map), options_(options) {
  VDTNAV_CHECK(std::isfinite(options.gate) && options.gate >= 0.0,
               "sensor model: gate must be >= 0");
  map_sigma_ = options.map_sigma >= 0.0 ? options.map_sigma : map.resolution() / std::sqrt(12.0);
  VDTNAV_CHECK(std::isfinite(options.map_correlation_length) &&
                   options.map_correlation_length >= 0.0 && std::isfinite(options.map_pose_sigma),
               "sensor model: map_correlation_length must be >= 0 and map_pose_sigma finite");
  VDTNAV_CHECK(Dim == 2 || options.map_uncertainty == nullptr,
               "sensor model: map_uncertainty is supported in 2D only");
  if (options.map_correlation_length > 0.0) {
    const double res = map.resolution();
    const double pose = options.map_pose_sigma >= 0.0 ? options.map_pose_sigma : 0.5 * res;
    map_sigma_correlated_ = std::sqrt(res * res / 12.0 + pose * pose);
  }
}

template <int Dim>
std::int64_t VdtSensorModelT<Dim>::map_error_group(const Vector& world_point) const noexcept {
  // 21 bits per axis: +-10^6 squares, +-2000 km at 2 m.
  std::int64_t key = 0;
  for (int c = 0; c < Dim; ++c) {
    const double q = std::floor(world_point[c] / options_.map_correlation_length);
    const auto cell = static_cast<std::int64_t>(std::max(-1e6, std::min(1e6, q))) + (1 << 20);
    key = (key << 21) | cell;
  }
  return key;
}

template <int Dim>
bool VdtSensorModelT<Dim>::passes_gate(const Vector& d) const noexcept {
  switch (options_.gate_mode) {
    case GateMode::kComponents:
      return (d.array().abs() < options_.gate).all();
    case GateMode::kNorm:
      return d.squaredNorm() < options_.gate * options_.gate;
    case GateMode::kNone:
      return true;
  }
  return true;
}

template <int Dim>
typename VdtSensorModelT<Dim>::Disparity VdtSensorModelT<Dim>::from_sample(
    const VdtSample<Dim>& sample, const Rotation& r, const Vector& rp, const Vector& u) const {
  Disparity b;
  b.d = sample.value;
  b.inside = sample.inside;
  b.inlier = b.inside && passes_gate(b.d);
  b.d_pose = Traits::pose_jacobian(sample.jacobian, rp);  // J dq/dX
  b.d_point.noalias() = sample.jacobian * r;
  b.d_range.noalias() = b.d_point * u;  // J R u
  return b;
}

template <int Dim>
void VdtSensorModelT<Dim>::disparities(const Rotation& r, const Vector& t,
                                       const Observations& observations,
                                       const std::vector<int>* beams, std::vector<Disparity>* out,
                                       DisparityParts parts) const {
  const std::size_t n = beams != nullptr ? beams->size() : observations.size();
  const int* index = beams != nullptr ? beams->data() : nullptr;
  const auto reading = [index](std::size_t k) {
    return index != nullptr ? static_cast<std::size_t>(index[k]) : k;
  };
  // Scratch of this thread: the estimators call this once per pass over a scan. The loops below
  // run on plain pointers: a thread_local vector reached inside a loop is looked up again at each
  // access (its address through the TLS block, its data pointer through memory).
  thread_local std::vector<Vector> rotated_tl, endpoints_tl;  // R p_i (for d_pose) and R p_i + t
  thread_local std::vector<VdtSample<Dim>> samples_tl;
  rotated_tl.resize(n);
  endpoints_tl.resize(n);
  samples_tl.resize(n);
  out->resize(n);
  Vector* const rotated = rotated_tl.data();
  Vector* const endpoints = endpoints_tl.data();
  VdtSample<Dim>* const samples = samples_tl.data();
  Disparity* const result = out->data();
  const Vector* const points = observations.points.data();
  for (std::size_t k = 0; k < n; ++k) {
    rotated[k] = r * points[reading(k)];
    endpoints[k] = rotated[k] + t;
  }
  if (options_.residual == ResidualMode::kNearestPoint) {
    for (std::size_t k = 0; k < n; ++k) samples[k] = map_->nearest_point_query(endpoints[k]);
  } else {
    map_->evaluate(endpoints, n, samples, parts != DisparityParts::kValue);
  }
  if (parts == DisparityParts::kAll) {
    const Vector* const directions = observations.directions.data();
    for (std::size_t k = 0; k < n; ++k) {
      result[k] = from_sample(samples[k], r, rotated[k], directions[reading(k)]);
    }
    return;
  }
  for (std::size_t k = 0; k < n; ++k) {
    Disparity& b = result[k];
    b.d = samples[k].value;
    b.inside = samples[k].inside;
    b.inlier = b.inside && passes_gate(b.d);
    if (parts == DisparityParts::kPose) {
      b.d_pose = Traits::pose_jacobian(samples[k].jacobian, rotated[k]);
    }
  }
}

template <int Dim>
typename VdtSensorModelT<Dim>::Disparity VdtSensorModelT<Dim>::disparity(
    const Rotation& r, const Vector& t, const Vector& p, const Vector& u,
    Curvature* curvature) const {
  const Vector rp = r * p;  // R p
  const Vector q = rp + t;
  VdtSample<Dim> smp;
  std::array<Matrix, Dim> hess;
  for (Matrix& h : hess) h.setZero();
  if (options_.residual == ResidualMode::kNearestPoint) {
    smp = map_->nearest_point_query(q);  // Jacobian identity, Hessians zero
  } else if (curvature != nullptr) {
    const auto with_hessian = map_->evaluate_with_hessian(q);
    smp = with_hessian;
    hess = with_hessian.hessian;
  } else {
    smp = map_->evaluate(q);
  }
  const Disparity b = from_sample(smp, r, rp, u);
  const Matrix& jac = smp.jacobian;

  if (curvature != nullptr) {
    // |d|^2 / 2 with d = DT_v(q(X, r)):
    //   d^2/dX^2  = D^T D + Q^T (sum_c d_c H_c) Q + sum_k g_k d^2 q_k/dX^2
    //   d^2/dXdr  = D^T (J R u) + Q^T (sum_c d_c H_c) R u + (d Q/dr)^T g
    // with D = dd/dX, Q = dq/dX, H_c the Hessian of component c, g = J^T d the gradient of |d|^2/2
    // with respect to q (Gauss-Newton term + map curvature + curvature of the pose action).
    Matrix hd = b.d[0] * hess[0];
    for (int c = 1; c < Dim; ++c) hd += b.d[c] * hess[c];
    const Vector g = jac.transpose() * b.d;
    const auto dq_dx = Traits::pose_jacobian(Matrix::Identity(), rp);
    curvature->hessian.noalias() = b.d_pose.transpose() * b.d_pose;
    curvature->hessian.noalias() += dq_dx.transpose() * hd * dq_dx;
    curvature->hessian += Traits::point_hessian(g, rp);
    //   d^2/dXdp  = D^T (J R) + Q^T (sum_c d_c H_c) R + [(dQ/dp_k)^T g]_k   (column k: along e_k)
    curvature->cross_point.noalias() = b.d_pose.transpose() * b.d_point;
    curvature->cross_point.noalias() += dq_dx.transpose() * (hd * r);
    for (int k = 0; k < Dim; ++k) {
      curvature->cross_point.col(k) +=
          Traits::rotation_jacobian(Matrix::Identity(), r.col(k)).transpose() * g;
    }
    curvature->cross.noalias() = curvature->cross_point * u;
  }
  return b;
}

template <int Dim>
typename VdtSensorModelT<Dim>::Vector VdtSensorModelT<Dim>::disparity_value(
    const Rotation& r, const Vector& t, const Vector& p, bool* inlier, bool* in_map) const {
  const Vector q = r * p + t;
  bool inside = false;
  Vector d;
  if (options_.residual == ResidualMode::kNearestPoint) {
    const auto smp = map_->nearest_point_query(q);
    d = smp.value;
    inside = smp.inside;
  } else {
    d = map_->value(q, &inside);
  }
  if (inlier != nullptr) *inlier = inside && passes_gate(d);
  if (in_map != nullptr) *in_map = inside;
  return d;
}

template <int Dim>
typename VdtSensorModelT<Dim>::Matrix VdtSensorModelT<Dim>::disparity_covariance(
    const Disparity& b, double sigma_range) const {
  const double s2 = sigma_range * sigma_range;
  Matrix cov;
  if (options_.covariance == DisparityCovariance::kExactRankOne) {
    cov = s2 * b.d_range * b.d_range.transpose();  // every component shares one range error
  } else {
    cov = (s2 * b.d_range.array().square()).matrix().asDiagonal();  // (2.13)-(2.15)
  }
  cov.diagonal().array() += map_sigma_ * map_sigma_;
  return cov;
}

template <int Dim>
typename VdtSensorModelT<Dim>::Matrix VdtSensorModelT<Dim>::disparity_covariance_point(
    const Disparity& b, const Matrix& point_cov) const {
  Matrix cov = b.d_point * point_cov * b.d_point.transpose();
  if (options_.covariance == DisparityCovariance::kDiagonal) {
    cov = Matrix(cov.diagonal().asDiagonal());  // (2.13)-(2.15): correlations dropped
  }
  cov.diagonal().array() += map_sigma_ * map_sigma_;
  return cov;
}

template <int Dim>
double VdtSensorModelT<Dim>::vector_chamfer_distance(const Pose& pose,
                                                     const Observations& observations,
                                                     int* inliers) const {
  double vcd = 0.0;
  int n = 0;
  const Rotation r = Traits::rotation(pose);
  const Vector t = Traits::translation(pose);
  for (std::size_t i = 0; i < observations.size(); ++i) {
    bool inlier = false;
    const Vector d = disparity_value(r, t, observations.points[i], &inlier);
    if (!inlier) continue;
    vcd += d.squaredNorm();  // (2.17)
    ++n;
  }
  if (inliers != nullptr) *inliers = n;
  return vcd;
}

template class VdtSensorModelT<2>;
template class VdtSensorModelT<3>;

}  // namespace vdtnav
