#include "vdtnav/sim/imu_simulator.hpp"

#include <cmath>

#include "vdtnav/core/error.hpp"

namespace vdtnav::sim {
namespace {

constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

/// a sin(2π f t) and its first two derivatives.
Eigen::Vector3d sine(double a, double f, double t) {
  const double w = kTwoPi * f;
  return {a * std::sin(w * t), a * w * std::cos(w * t), -a * w * w * std::sin(w * t)};
}

}  // namespace

MotionState3 WavyCircle::at(double t) const {
  MotionState3 m;
  const double big_omega = speed / radius;
  const double c = std::cos(big_omega * t), s = std::sin(big_omega * t);
  const Eigen::Vector3d z = sine(height_amplitude, height_frequency, t);
  const Eigen::Vector3d roll = sine(roll_amplitude, roll_frequency, t);
  const Eigen::Vector3d pitch = sine(pitch_amplitude, pitch_frequency, t);
  const double yaw = big_omega * t + 0.5 * 3.14159265358979323846;
  m.pose = pose3_from_xyz_rpy(radius * c, radius * s, height + z[0], roll[0], pitch[0], yaw);
  m.velocity = Eigen::Vector3d(-radius * big_omega * s, radius * big_omega * c, z[1]);
  m.acceleration = Eigen::Vector3d(-radius * big_omega * big_omega * c,
                                   -radius * big_omega * big_omega * s, z[2]);
  const double cr = std::cos(roll[0]), sr = std::sin(roll[0]);
  const double cp = std::cos(pitch[0]), sp = std::sin(pitch[0]);
  m.body_rates = Eigen::Vector3d(roll[1] - sp * big_omega, cr * pitch[1] + sr * cp * big_omega,
                                 -sr * pitch[1] + cr * cp * big_omega);
  return m;
}

std::vector<ImuSample> simulate_imu(const std::function<MotionState3(double)>& trajectory,
                                    double t_start, double t_end, const ImuSimulation& o,
                                    std::mt19937& rng) {
  VDTNAV_CHECK(std::isfinite(t_start) && std::isfinite(t_end) && t_start <= t_end,
               "simulate_imu: expected t_start <= t_end");
  VDTNAV_CHECK(std::isfinite(o.rate_hz) && o.rate_hz > 0.0, "simulate_imu: rate_hz must be > 0");
  VDTNAV_CHECK(o.gyro_noise_density >= 0.0 && o.accel_noise_density >= 0.0,
               "simulate_imu: the noise densities must be >= 0");
  const Eigen::Vector3d g(0.0, 0.0, -o.gravity);
  const double sg = o.gyro_noise_density * std::sqrt(o.rate_hz);
  const double sa = o.accel_noise_density * std::sqrt(o.rate_hz);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](double sigma) {
    if (sigma == 0.0) return Eigen::Vector3d(Eigen::Vector3d::Zero());
    return Eigen::Vector3d(sigma * normal(rng), sigma * normal(rng), sigma * normal(rng));
  };
  const auto count = static_cast<long>(std::floor((t_end - t_start) * o.rate_hz + 1e-9));
  std::vector<ImuSample> out;
  out.reserve(static_cast<std::size_t>(count) + 1);
  for (long k = 0; k <= count; ++k) {
    ImuSample x;
    x.t = t_start + static_cast<double>(k) / o.rate_hz;
    const MotionState3 m = trajectory(x.t);
    x.gyro = m.body_rates + o.gyro_bias + draw(sg);
    x.accel = m.pose.linear().transpose() * (m.acceleration - g) + o.accel_bias + draw(sa);
    out.push_back(x);
  }
  return out;
}

}  // namespace vdtnav::sim
