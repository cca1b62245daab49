#include "vdtnav/sensor/imu.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

using Matrix96d = Eigen::Matrix<double, 9, 6>;

/// The right Jacobian of SO(3) (Forster et al. 2017, Sec. II), Exp(φ + δφ) ≈ Exp(φ) Exp(J_r(φ) δφ).
Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d k = skew(phi);
  if (theta < 1e-6) return Eigen::Matrix3d::Identity() - 0.5 * k + k * k / 6.0;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(theta)) / t2 * k +
         (theta - std::sin(theta)) / (t2 * theta) * k * k;
}

std::string imu_seconds(double t) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.6f", t);
  return buf;
}

/// The measurement at time t, linear between two samples: weight w0 on sample k0, w1 on k1
/// (w1 = 0, k1 = k0 on a sample).
struct ImuEndpoint {
  std::size_t k0 = 0, k1 = 0;
  double w0 = 1.0, w1 = 0.0;
  Eigen::Vector3d gyro, accel;  // bias subtracted
};

ImuEndpoint imu_endpoint(const std::vector<ImuSample>& s, std::size_t k, double t,
                         const ImuNoise& n) {
  ImuEndpoint e;
  e.k0 = e.k1 = k;
  if (s[k].t != t) {  // t in (t_k, t_{k+1})
    e.k1 = k + 1;
    e.w1 = (t - s[k].t) / (s[k + 1].t - s[k].t);
    e.w0 = 1.0 - e.w1;
  }
  e.gyro = e.w0 * s[e.k0].gyro + e.w1 * s[e.k1].gyro - n.gyro_bias;
  e.accel = e.w0 * s[e.k0].accel + e.w1 * s[e.k1].accel - n.accel_bias;
  return e;
}

/// The period a sample stands for: the mean of its two neighbouring gaps (one at either end).
double imu_sample_period(const std::vector<ImuSample>& s, std::size_t k) {
  if (k == 0) return s[1].t - s[0].t;
  if (k + 1 == s.size()) return s[k].t - s[k - 1].t;
  return 0.5 * (s[k + 1].t - s[k - 1].t);
}

/// One interval's linearised error recursion, e_b = A e_a + B n_a + C n_b, n = (δω, δf) the
/// measurement errors at the interval's ends.
struct ImuStep {
  Matrix9d a;
  Matrix96d b, c;
};

}  // namespace

void ImuNoise::validate() const {
  const auto non_negative = [](double x) { return std::isfinite(x) && x >= 0.0; };
  VDTNAV_CHECK(non_negative(gyro_noise_density) && non_negative(accel_noise_density),
               "ImuNoise: the noise densities must be finite and >= 0");
  VDTNAV_CHECK(non_negative(gyro_bias_sigma) && non_negative(accel_bias_sigma),
               "ImuNoise: the bias sigmas must be finite and >= 0");
  VDTNAV_CHECK(gyro_bias.allFinite() && accel_bias.allFinite(),
               "ImuNoise: the biases must be finite");
  VDTNAV_CHECK(std::isfinite(gravity) && gravity > 0.0, "ImuNoise: gravity must be > 0 (m/s^2)");
}

bool imu_covers(const std::vector<ImuSample>& samples, double t0, double t1) {
  if (samples.empty()) return false;
  return samples.front().t <= t0 && samples.back().t >= t1;
}

ImuIncrement integrate_imu(const std::vector<ImuSample>& s, double t0, double t1,
                           const ImuNoise& noise) {
  noise.validate();
  VDTNAV_CHECK(
      std::isfinite(t0) && std::isfinite(t1) && t0 < t1,
      "integrate_imu: expected t0 < t1, got [" + imu_seconds(t0) + ", " + imu_seconds(t1) + "]");
  if (!imu_covers(s, t0, t1)) {
    if (s.empty())
      throw ConfigError("integrate_imu: no IMU samples for [" + imu_seconds(t0) + ", " +
                        imu_seconds(t1) + "] s");
    const double first = s.front().t, last = s.back().t;
    std::string missing;
    if (first > t0) missing = "[" + imu_seconds(t0) + ", " + imu_seconds(std::min(first, t1)) + ")";
    if (last < t1) {
      missing += (missing.empty() ? "" : " and ") + std::string("(") +
                 imu_seconds(std::max(last, t0)) + ", " + imu_seconds(t1) + "]";
    }
    throw ConfigError("integrate_imu: the samples span [" + imu_seconds(first) + ", " +
                      imu_seconds(last) + "] s, not [" + imu_seconds(t0) + ", " + imu_seconds(t1) +
                      "]: missing " + missing);
  }
  const auto by_time = [](double t, const ImuSample& x) { return t < x.t; };
  // lo: the last sample at or before t0; hi: the first at or after t1.
  const std::size_t lo =
      static_cast<std::size_t>(std::upper_bound(s.begin(), s.end(), t0, by_time) - s.begin()) - 1;
  const std::size_t hi = static_cast<std::size_t>(
      std::lower_bound(s.begin(), s.end(), t1,
                       [](const ImuSample& x, double t) { return x.t < t; }) -
      s.begin());
  ImuIncrement inc;
  inc.t0 = t0;
  inc.t1 = t1;
  inc.dt = t1 - t0;
  inc.samples_used = hi - lo + 1;
  for (std::size_t k = lo; k < hi; ++k) {
    const double gap = s[k + 1].t - s[k].t;
    VDTNAV_CHECK(gap > 0.0, "integrate_imu: the samples at " + imu_seconds(s[k].t) + " and " +
                                imu_seconds(s[k + 1].t) + " s are not in increasing time");
    inc.max_gap = std::max(inc.max_gap, gap);
  }

  // The interval ends: t0, the samples strictly inside, t1.
  std::vector<double> tau;
  tau.reserve(hi - lo + 1);
  tau.push_back(t0);
  for (std::size_t k = lo + 1; k < hi; ++k) tau.push_back(s[k].t);
  tau.push_back(t1);
  const auto endpoint_at = [&](std::size_t i) {
    if (i == 0) return imu_endpoint(s, lo, t0, noise);
    if (i + 1 == tau.size()) return imu_endpoint(s, s[hi].t == t1 ? hi : hi - 1, t1, noise);
    return imu_endpoint(s, lo + i, tau[i], noise);
  };

  // Forward: the increment, second order (file comment), and each interval's error recursion.
  std::vector<ImuStep> steps(tau.size() - 1);
  std::vector<ImuEndpoint> ends;
  ends.reserve(tau.size());
  for (std::size_t i = 0; i < tau.size(); ++i) ends.push_back(endpoint_at(i));
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero(), p = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d eye = Eigen::Matrix3d::Identity();
  for (std::size_t j = 0; j + 1 < tau.size(); ++j) {
    const ImuEndpoint& ea = ends[j];
    const ImuEndpoint& eb = ends[j + 1];
    const double h = tau[j + 1] - tau[j];
    const Eigen::Vector3d rho = 0.5 * h * (ea.gyro + eb.gyro);
    const Eigen::Matrix3d rb = r * so3_exp(rho);
    const Eigen::Vector3d aa = r * ea.accel, ab = rb * eb.accel;
    // Linearisation (left perturbation): δθ_b = δθ_a + K (δω_a + δω_b), K = R_b J_r(ρ) h / 2;
    // δ(R_a f_a) = -[R_a f_a]x δθ_a + R_a δf_a, δ(R_b f_b) = -[R_b f_b]x δθ_b + R_b δf_b.
    const Eigen::Matrix3d k = 0.5 * h * rb * so3_right_jacobian(rho);
    const Eigen::Matrix3d sa = skew(aa), sb = skew(ab);
    ImuStep& st = steps[j];
    st.a.setIdentity();
    st.a.block<3, 3>(3, 0) = -0.5 * h * (sa + sb);
    st.a.block<3, 3>(6, 0) = -h * h * (sa / 3.0 + sb / 6.0);
    st.a.block<3, 3>(6, 3) = h * eye;
    st.b.setZero();
    st.c.setZero();
    for (Matrix96d* m : {&st.b, &st.c}) {
      m->block<3, 3>(0, 0) = k;
      m->block<3, 3>(3, 0) = -0.5 * h * sb * k;
      m->block<3, 3>(6, 0) = -h * h / 6.0 * sb * k;
    }
    st.b.block<3, 3>(3, 3) = 0.5 * h * r;
    st.b.block<3, 3>(6, 3) = h * h / 3.0 * r;
    st.c.block<3, 3>(3, 3) = 0.5 * h * rb;
    st.c.block<3, 3>(6, 3) = h * h / 6.0 * rb;
    p += h * v + h * h * (aa / 3.0 + ab / 6.0);
    v += 0.5 * h * (aa + ab);
    r = rb;
  }
  inc.delta_R = r;
  inc.delta_v = v;
  inc.delta_p = p;

  // Backward: G_k = d e(t1) / d(measurement k) = sum over the intervals whose ends weigh sample
  // k of Φ(t1, end of interval) (B or C) times the weight.
  std::vector<Matrix96d> g(hi - lo + 1, Matrix96d::Zero());
  Matrix9d phi = Matrix9d::Identity();
  for (std::size_t j = steps.size(); j-- > 0;) {
    const Matrix96d pb = phi * steps[j].b, pc = phi * steps[j].c;
    for (const auto& [e, m] : {std::pair{&ends[j], &pb}, std::pair{&ends[j + 1], &pc}}) {
      g[e->k0 - lo] += e->w0 * *m;
      if (e->w1 != 0.0) g[e->k1 - lo] += e->w1 * *m;
    }
    phi = phi * steps[j].a;
  }
  const double gd2 = noise.gyro_noise_density * noise.gyro_noise_density;
  const double ad2 = noise.accel_noise_density * noise.accel_noise_density;
  Matrix96d sum = Matrix96d::Zero();
  for (std::size_t k = lo; k <= hi; ++k) {
    const Matrix96d& gk = g[k - lo];
    const double period = imu_sample_period(s, k);
    // Discrete white noise: σ_d² = density² / Δt_k.
    inc.covariance += (gd2 / period) * gk.leftCols<3>() * gk.leftCols<3>().transpose() +
                      (ad2 / period) * gk.rightCols<3>() * gk.rightCols<3>().transpose();
    sum += gk;
  }
  // The bias is subtracted: the increment moves by -sum(G_k) per unit of bias.
  inc.bias_jacobian = -sum;
  const Matrix96d& jb = inc.bias_jacobian;
  inc.covariance += noise.gyro_bias_sigma * noise.gyro_bias_sigma * jb.leftCols<3>() *
                        jb.leftCols<3>().transpose() +
                    noise.accel_bias_sigma * noise.accel_bias_sigma * jb.rightCols<3>() *
                        jb.rightCols<3>().transpose();
  inc.covariance = 0.5 * (inc.covariance + inc.covariance.transpose()).eval();
  return inc;
}

Pose3 predict_with_imu(const Pose3& pose_t0, const Eigen::Vector3d& velocity_world_t0,
                       const ImuIncrement& inc, double gravity,
                       Eigen::Vector3d* velocity_world_t1) {
  const Eigen::Vector3d g(0.0, 0.0, -gravity);
  const Eigen::Matrix3d& r0 = pose_t0.linear();
  const double dt = inc.dt;
  Pose3 t1 = Pose3::Identity();
  t1.linear() = r0 * inc.delta_R;
  t1.translation() =
      pose_t0.translation() + velocity_world_t0 * dt + 0.5 * g * dt * dt + r0 * inc.delta_p;
  if (velocity_world_t1 != nullptr)
    *velocity_world_t1 = velocity_world_t0 + g * dt + r0 * inc.delta_v;
  return t1;
}

ImuRelativePose imu_relative_pose(const Pose3& pose_t0, const Eigen::Vector3d& velocity_world_t0,
                                  const Eigen::Matrix3d& velocity_covariance,
                                  const ImuIncrement& inc, double gravity) {
  ImuRelativePose out;
  const Pose3 t1 =
      predict_with_imu(pose_t0, velocity_world_t0, inc, gravity, &out.velocity_world_t1);
  out.delta = pose_t0.inverse() * t1;
  // t_D = R0^T (v0 Δt + ½ g Δt²) + Δp, R_D = ΔR: dt = Δt R0^T δv0 + δp, dθ = δθ.
  const Eigen::Matrix3d rt = pose_t0.linear().transpose();
  const Matrix9d& c = inc.covariance;  // (δθ, δv, δp)
  out.covariance.topLeftCorner<3, 3>() =
      c.block<3, 3>(6, 6) + inc.dt * inc.dt * rt * velocity_covariance * rt.transpose();
  out.covariance.topRightCorner<3, 3>() = c.block<3, 3>(6, 0);
  out.covariance.bottomLeftCorner<3, 3>() = c.block<3, 3>(0, 6);
  out.covariance.bottomRightCorner<3, 3>() = c.block<3, 3>(0, 0);
  return out;
}

GravityAttitude attitude_from_gravity(const std::vector<ImuSample>& s, double t0, double t1,
                                      const ImuNoise& noise, double accelerating_threshold) {
  noise.validate();
  VDTNAV_CHECK(std::isfinite(t0) && std::isfinite(t1) && t0 <= t1,
               "attitude_from_gravity: expected t0 <= t1, got [" + imu_seconds(t0) + ", " +
                   imu_seconds(t1) + "]");
  VDTNAV_CHECK(std::isfinite(accelerating_threshold) && accelerating_threshold >= 0.0,
               "attitude_from_gravity: the accelerating threshold must be >= 0 (m/s^2)");
  const auto first = std::lower_bound(s.begin(), s.end(), t0,
                                      [](const ImuSample& x, double t) { return x.t < t; });
  const auto last = std::upper_bound(s.begin(), s.end(), t1,
                                     [](double t, const ImuSample& x) { return t < x.t; });
  VDTNAV_CHECK(first < last, "attitude_from_gravity: no IMU sample in [" + imu_seconds(t0) + ", " +
                                 imu_seconds(t1) + "] s");
  GravityAttitude out;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double inverse_periods = 0.0;  // sum of 1 / Δt_k: Var(mean) = density² sum(1/Δt_k) / N²
  for (auto it = first; it != last; ++it) {
    sum += it->accel;
    if (s.size() > 1)
      inverse_periods += 1.0 / imu_sample_period(s, static_cast<std::size_t>(it - s.begin()));
  }
  out.samples_used = static_cast<std::size_t>(last - first);
  const double n = static_cast<double>(out.samples_used);
  const Eigen::Vector3d f = sum / n - noise.accel_bias;
  out.mean_specific_force = f;
  const double rho = std::hypot(f.y(), f.z());
  const double norm = f.norm();
  out.roll = std::atan2(f.y(), f.z());
  out.pitch = std::atan2(-f.x(), rho);
  // One sample alone has no period: its own white noise is then left out (the bias is not).
  const double var_f =
      noise.accel_noise_density * noise.accel_noise_density * inverse_periods / (n * n) +
      noise.accel_bias_sigma * noise.accel_bias_sigma;
  // J Σ_f J^T with Σ_f = var_f I: the rows of J are orthogonal with norms 1/ρ and 1/|f|.
  out.covariance(0, 0) = var_f / (rho * rho);
  out.covariance(1, 1) = var_f / (norm * norm);
  const double g = noise.gravity;
  out.gravity_deviation = std::abs(norm - g);
  out.accelerating = out.gravity_deviation > accelerating_threshold;
  if (out.accelerating) {
    const double across = std::sqrt(std::abs(norm * norm - g * g)) / g;  // a_n / g
    out.covariance.diagonal().array() += across * across;
  }
  out.sigma_roll = std::sqrt(out.covariance(0, 0));
  out.sigma_pitch = std::sqrt(out.covariance(1, 1));
  return out;
}

}  // namespace vdtnav
