// The IMU (sensor/imu.hpp): preintegration against an analytic trajectory (the simulator's own
// derivatives checked by finite differences first), its order of accuracy, the bias Jacobian by
// finite differences, the propagated covariances by Monte Carlo (NEES), roll and pitch from
// gravity, and the errors.
#include "vdtnav/sensor/imu.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/sim/imu_simulator.hpp"

namespace vdtnav {
namespace {

using Vector9d = Eigen::Matrix<double, 9, 1>;

const sim::WavyCircle kCircle{};

sim::MotionState3 state(double t) { return kCircle.at(t); }

std::vector<ImuSample> ideal_samples(double rate_hz, double t_end = 2.0) {
  sim::ImuSimulation o;
  o.rate_hz = rate_hz;
  std::mt19937 rng(1);
  return sim::simulate_imu(state, 0.0, t_end, o, rng);
}

/// (Log(ΔR_a ΔR_b^T), Δv_a - Δv_b, Δp_a - Δp_b): a's increment as a left perturbation of b's.
Vector9d increment_error(const ImuIncrement& a, const ImuIncrement& b) {
  Vector9d e;
  e << so3_log(a.delta_R * b.delta_R.transpose()), a.delta_v - b.delta_v, a.delta_p - b.delta_p;
  return e;
}

TEST(ImuSimulator, TheWavyCircleDerivativesAreThoseOfItsPoses) {
  const double h = 1e-5;
  for (const double t : {0.0, 0.37, 1.9}) {
    const sim::MotionState3 m = state(t), before = state(t - h), after = state(t + h);
    const Eigen::Vector3d fd_velocity =
        (after.pose.translation() - before.pose.translation()) / (2 * h);
    EXPECT_LT((fd_velocity - m.velocity).norm(), 1e-8) << t;
    EXPECT_LT(((after.velocity - before.velocity) / (2 * h) - m.acceleration).norm(), 1e-8) << t;
    // R^T dR/dt = [ω]x: ω = Log(R(t-h)^T R(t+h)) / 2h.
    const Eigen::Vector3d fd_rates =
        so3_log(before.pose.linear().transpose() * after.pose.linear()) / (2 * h);
    EXPECT_LT((fd_rates - m.body_rates).norm(), 1e-8) << t;
  }
  // At rest and level, the accelerometer reads +g on z.
  sim::ImuSimulation o;
  std::mt19937 rng(1);
  const auto still =
      sim::simulate_imu([](double) { return sim::MotionState3{}; }, 0.0, 1.0, o, rng);
  ASSERT_EQ(still.size(), 201u);
  EXPECT_NEAR(still.back().t, 1.0, 1e-15);
  EXPECT_LT((still[7].accel - Eigen::Vector3d(0, 0, 9.80665)).norm(), 1e-15);
}

struct PredictionError {
  double position = 0.0;  // m
  double attitude = 0.0;  // rad
  double velocity = 0.0;  // m/s
};

PredictionError predict_error(const std::vector<ImuSample>& samples, double t0, double t1) {
  ImuNoise noise;
  const ImuIncrement inc = integrate_imu(samples, t0, t1, noise);
  const sim::MotionState3 a = state(t0), b = state(t1);
  Eigen::Vector3d v1;
  const Pose3 predicted = predict_with_imu(a.pose, a.velocity, inc, noise.gravity, &v1);
  return {(predicted.translation() - b.pose.translation()).norm(),
          attitude_error(predicted, b.pose), (v1 - b.velocity).norm()};
}

// The scheme's error is O(h²) (file comment). The rates' trapezoid errs by h³/12 |ω''| a step:
// the roll oscillation has ω'' = A_r (2π f_r)³ = 13 rad/s³, so 1.3e-7 rad a step at h = 5 ms,
// ~2e-6 rad over 0.1 s (measured 1.9e-6) and ~1e-5 over 1 s where it partly averages out
// (measured 8.9e-6 rad; 6.5e-6 m, 2.3e-5 m/s). Tolerances: 1e-6 m and 1e-5 rad at 0.1 s, 5e-5 m
// and rad and 1e-4 m/s at 1 s. A zero-order hold (Forster's Euler step) errs by ~h/2 times the
// change of the rates and force over the window: ~1e-3 rad and mm over 1 s. t0 is off the sample
// grid: the partial intervals are interpolated.
TEST(Imu, NoiseFreeSamplesPredictTheAnalyticPose) {
  const std::vector<ImuSample> samples = ideal_samples(200.0);
  const double t0 = 0.1234;
  const PredictionError short_window = predict_error(samples, t0, t0 + 0.1);
  const PredictionError long_window = predict_error(samples, t0, t0 + 1.0);
  std::cout << "200 Hz: 0.1 s " << short_window.position << " m " << short_window.attitude
            << " rad; 1 s " << long_window.position << " m " << long_window.attitude << " rad "
            << long_window.velocity << " m/s\n";
  EXPECT_LT(short_window.position, 1e-6);
  EXPECT_LT(short_window.attitude, 1e-5);
  EXPECT_LT(long_window.position, 5e-5);
  EXPECT_LT(long_window.attitude, 5e-5);
  EXPECT_LT(long_window.velocity, 1e-4);
  const ImuIncrement inc = integrate_imu(samples, t0, t0 + 1.0, ImuNoise{});
  EXPECT_EQ(inc.samples_used, 202u);  // 0.12 ... 1.125 at 200 Hz: the brackets and 200 inside
  EXPECT_NEAR(inc.max_gap, 0.005, 1e-12);
  EXPECT_DOUBLE_EQ(inc.dt, 1.0);
}

TEST(Imu, TheIntegrationIsSecondOrder) {
  // Halving the sample period divides the 1 s error by ~4 (2 for a first-order scheme).
  const double t0 = 0.1234;
  const PredictionError coarse = predict_error(ideal_samples(50.0), t0, t0 + 1.0);
  const PredictionError fine = predict_error(ideal_samples(100.0), t0, t0 + 1.0);
  std::cout << "order: 50 Hz " << coarse.position << " m, 100 Hz " << fine.position << " m\n";
  EXPECT_GT(coarse.position / fine.position, 3.0);
  EXPECT_GT(coarse.attitude / fine.attitude, 3.0);
}

TEST(Imu, TheRelativePoseIsTheIncrementInThePreviousRobotFrame) {
  const std::vector<ImuSample> samples = ideal_samples(200.0);
  const double t0 = 0.5, t1 = 0.6;
  ImuNoise noise;
  const ImuIncrement inc = integrate_imu(samples, t0, t1, noise);
  const sim::MotionState3 a = state(t0), b = state(t1);
  const ImuRelativePose rel =
      imu_relative_pose(a.pose, a.velocity, Eigen::Matrix3d::Zero(), inc, noise.gravity);
  const Pose3 truth = a.pose.inverse() * b.pose;
  EXPECT_LT((rel.delta.translation() - truth.translation()).norm(), 1e-6);
  EXPECT_LT(attitude_error(rel.delta, truth), 1e-5);
  EXPECT_LT((rel.velocity_world_t1 - b.velocity).norm(), 1e-5);
  // What a localizer does with it: pose_ * delta.
  EXPECT_LT(((a.pose * rel.delta).translation() -
             predict_with_imu(a.pose, a.velocity, inc, noise.gravity).translation())
                .norm(),
            1e-12);
  // Blocks in (dt, dθ) order.
  const Matrix6d& c = rel.covariance;
  EXPECT_TRUE((c.bottomRightCorner<3, 3>() == inc.covariance.topLeftCorner<3, 3>()));
  EXPECT_TRUE((c.topLeftCorner<3, 3>() == inc.covariance.bottomRightCorner<3, 3>()));
  EXPECT_TRUE((c.topRightCorner<3, 3>() == inc.covariance.block<3, 3>(6, 0)));
}

TEST(Imu, TheBiasJacobianIsTheIncrementsFiniteDifference) {
  const std::vector<ImuSample> samples = ideal_samples(200.0);
  const double t0 = 0.2071, t1 = 0.7071;
  const ImuNoise noise;
  const ImuIncrement base = integrate_imu(samples, t0, t1, noise);
  const double eps = 1e-6;
  for (int k = 0; k < 6; ++k) {
    ImuNoise shifted = noise;
    (k < 3 ? shifted.gyro_bias[k] : shifted.accel_bias[k - 3]) = eps;
    const Vector9d fd = increment_error(integrate_imu(samples, t0, t1, shifted), base) / eps;
    EXPECT_LT((fd - base.bias_jacobian.col(k)).norm(), 1e-5 * (1.0 + fd.norm())) << k;
  }
  // A gyro bias turns the rotation by about -dt per unit (the rotation's column).
  const Eigen::Matrix3d gyro_rotation = base.bias_jacobian.topLeftCorner<3, 3>();
  EXPECT_NEAR(gyro_rotation.trace(), -3 * 0.5, 0.1);
}

/// Monte Carlo: `runs` noisy IMUs (white noise from the densities, a bias per run from its σ) on
/// the trajectory; the increment's error against the noise-free one, and the relative pose's with
/// a velocity error drawn from its covariance.
struct MonteCarlo {
  double anees9 = 0.0;
  double anees6 = 0.0;
  Vector9d variance_ratio = Vector9d::Zero();  // sample variance / propagated, per component
};

MonteCarlo monte_carlo(double t0, double t1, const ImuNoise& noise, int runs) {
  std::mt19937 rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](double sigma) {
    return Eigen::Vector3d(sigma * normal(rng), sigma * normal(rng), sigma * normal(rng));
  };
  const sim::MotionState3 a = state(t0);
  const Eigen::Matrix3d velocity_covariance = Eigen::Vector3d(0.04, 0.01, 0.0025).asDiagonal();
  const ImuIncrement clean = integrate_imu(ideal_samples(200.0), t0, t1, noise);
  const ImuRelativePose clean_rel =
      imu_relative_pose(a.pose, a.velocity, velocity_covariance, clean, noise.gravity);
  const Eigen::LLT<Eigen::Matrix3d> velocity_sqrt(velocity_covariance);
  MonteCarlo mc;
  Matrix9d scatter = Matrix9d::Zero();
  Matrix9d covariance = Matrix9d::Zero();
  for (int run = 0; run < runs; ++run) {
    sim::ImuSimulation o;
    o.gyro_noise_density = noise.gyro_noise_density;
    o.accel_noise_density = noise.accel_noise_density;
    o.gyro_bias = draw(noise.gyro_bias_sigma);
    o.accel_bias = draw(noise.accel_bias_sigma);
    const ImuIncrement inc =
        integrate_imu(sim::simulate_imu(state, 0.0, 2.0, o, rng), t0, t1, noise);
    const Vector9d e = increment_error(inc, clean);
    mc.anees9 += eval::nees<9>(e, inc.covariance) / runs;
    scatter += e * e.transpose() / runs;
    covariance += inc.covariance / runs;
    const Eigen::Vector3d v0 = a.velocity + velocity_sqrt.matrixL() * draw(1.0);
    const ImuRelativePose rel =
        imu_relative_pose(a.pose, v0, velocity_covariance, inc, noise.gravity);
    mc.anees6 += eval::nees<6>(ominus(rel.delta, clean_rel.delta), rel.covariance) / runs;
  }
  mc.variance_ratio = scatter.diagonal().cwiseQuotient(covariance.diagonal());
  return mc;
}

// 2000 runs over 0.1 s and 1 s from t0 off the sample grid. The chi-square 95 % interval of the
// mean of 2000 NEES is [8.82, 9.18] for 9 DOF, [5.85, 6.15] for 6 (with 500 runs, [8.63, 9.38]:
// the 0.1 s window's 8.58 at seed 42 fell out, 5 % of seeds do per check; 5000 runs give 9.00
// and 8.99). Each component's sample variance is within ±10 % of the propagated one (3 σ of a
// variance estimated from 2000 runs). Leaving the bias out of the covariance gives an ANEES of 55
// over 0.1 s and 430 over 1 s; the bias alone is singular (6 parameters for 9 components).
TEST(Imu, TheIncrementCovarianceMatchesMonteCarlo) {
  const ImuNoise noise;
  const int runs = 2000;
  const eval::ChiSquareInterval nine = eval::anees_interval(runs, 9);
  const eval::ChiSquareInterval six = eval::anees_interval(runs, 6);
  for (const double dt : {0.1, 1.0}) {
    const MonteCarlo mc = monte_carlo(0.1234, 0.1234 + dt, noise, runs);
    std::cout << "dt " << dt << " s: ANEES 9-DOF " << mc.anees9 << " in [" << nine.lower << ", "
              << nine.upper << "], relative pose 6-DOF " << mc.anees6 << " in [" << six.lower
              << ", " << six.upper << "], variance ratios " << mc.variance_ratio.transpose()
              << "\n";
    EXPECT_TRUE(nine.contains(mc.anees9)) << dt << ": " << mc.anees9;
    EXPECT_TRUE(six.contains(mc.anees6)) << dt << ": " << mc.anees6;
    for (int k = 0; k < 9; ++k) {
      EXPECT_NEAR(mc.variance_ratio[k], 1.0, 0.1) << dt << " component " << k;
    }
  }
}

TEST(Imu, UncoveredTimesAreNamed) {
  const std::vector<ImuSample> samples = ideal_samples(200.0, 1.0);  // [0, 1] s
  EXPECT_TRUE(imu_covers(samples, 0.0, 1.0));
  EXPECT_FALSE(imu_covers(samples, 0.9, 1.1));
  EXPECT_FALSE(imu_covers({}, 0.0, 1.0));
  try {
    (void)integrate_imu(samples, 0.9, 1.1, ImuNoise{});
    FAIL() << "no throw";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("span [0.000000, 1.000000]"), std::string::npos) << what;
    EXPECT_NE(what.find("missing (1.000000, 1.100000]"), std::string::npos) << what;
  }
  try {
    (void)integrate_imu(samples, -0.5, 0.5, ImuNoise{});
    FAIL() << "no throw";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("missing [-0.500000, 0.000000)"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)integrate_imu(samples, 0.5, 0.5, ImuNoise{}), ConfigError);
  std::vector<ImuSample> unsorted = samples;
  std::swap(unsorted[10], unsorted[11]);
  EXPECT_THROW((void)integrate_imu(unsorted, 0.0, 0.5, ImuNoise{}), ConfigError);
  EXPECT_NO_THROW((void)integrate_imu(unsorted, 0.1, 0.5, ImuNoise{}));  // only those used
  // On the grid at both ends: no interpolation, the samples themselves.
  EXPECT_EQ(integrate_imu(samples, 0.1, 0.2, ImuNoise{}).samples_used, 21u);
}

TEST(ImuNoise, BadSettingsAreRefused) {
  EXPECT_NO_THROW(ImuNoise{}.validate());
  ImuNoise n;
  n.gyro_noise_density = -1.0;
  EXPECT_THROW(n.validate(), ConfigError);
  n = ImuNoise{};
  n.accel_bias_sigma = std::nan("");
  EXPECT_THROW(n.validate(), ConfigError);
  n = ImuNoise{};
  n.gravity = 0.0;
  EXPECT_THROW(n.validate(), ConfigError);
  n = ImuNoise{};
  n.gyro_bias.x() = INFINITY;
  EXPECT_THROW(n.validate(), ConfigError);
}

/// A robot standing still at (roll, pitch, yaw), accelerating by `a` (world frame).
std::vector<ImuSample> tilted(double roll, double pitch, const Eigen::Vector3d& a,
                              const sim::ImuSimulation& o, std::mt19937& rng) {
  sim::MotionState3 m;
  m.pose = pose3_from_xyz_rpy(0, 0, 0, roll, pitch, 1.0);
  m.acceleration = a;
  return sim::simulate_imu([m](double) { return m; }, 0.0, 1.0, o, rng);
}

TEST(GravityAttitude, AKnownTiltIsRecovered) {
  std::mt19937 rng(5);
  const ImuNoise noise;
  for (const auto& [roll, pitch] : {std::pair{0.2, -0.1}, {-0.5, 0.3}, {0.0, 1.2}}) {
    const GravityAttitude g = attitude_from_gravity(
        tilted(roll, pitch, Eigen::Vector3d::Zero(), {}, rng), 0.0, 0.5, noise);
    EXPECT_NEAR(g.roll, roll, 1e-12);
    EXPECT_NEAR(g.pitch, pitch, 1e-12);
    EXPECT_FALSE(g.accelerating);
    EXPECT_EQ(g.samples_used, 101u);
    EXPECT_LT(g.gravity_deviation, 1e-12);
  }
}

// 500 windows of 0.5 s with noise and a bias per run: the NEES of (roll, pitch) against their
// 2 x 2 covariance within the 95 % interval of the mean of 500 chi-square(2) ([1.83, 2.18]); the
// bias dominates (2 mrad against 0.1 mrad of white noise), so a sigma without it fails.
TEST(GravityAttitude, ItsSigmaMatchesMonteCarlo) {
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  const ImuNoise noise;
  const double roll = 0.15, pitch = -0.25;
  const int runs = 500;
  double anees = 0.0, sigma_roll = 0.0, square_roll = 0.0;
  for (int run = 0; run < runs; ++run) {
    sim::ImuSimulation o;
    o.gyro_noise_density = noise.gyro_noise_density;
    o.accel_noise_density = noise.accel_noise_density;
    o.accel_bias = noise.accel_bias_sigma * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    const GravityAttitude g = attitude_from_gravity(
        tilted(roll, pitch, Eigen::Vector3d::Zero(), o, rng), 0.2, 0.7, noise);
    const Eigen::Vector2d e(g.roll - roll, g.pitch - pitch);
    anees += eval::nees<2>(e, g.covariance) / runs;
    sigma_roll += g.sigma_roll / runs;
    square_roll += e.x() * e.x() / runs;
  }
  const eval::ChiSquareInterval interval = eval::anees_interval(runs, 2);
  std::cout << "gravity attitude: ANEES " << anees << " in [" << interval.lower << ", "
            << interval.upper << "], roll sigma " << sigma_roll << " rad, measured "
            << std::sqrt(square_roll) << " rad\n";
  EXPECT_TRUE(interval.contains(anees)) << anees;
  EXPECT_NEAR(std::sqrt(square_roll) / sigma_roll, 1.0, 0.1);
}

TEST(GravityAttitude, AnAcceleratingWindowIsFlaggedAndItsSigmaCoversTheTilt) {
  std::mt19937 rng(9);
  const ImuNoise noise;
  const double roll = 0.1, pitch = 0.05;
  // Vertically, the norm shows the whole acceleration (0.5 m/s^2): flagged, no tilt error.
  const GravityAttitude up = attitude_from_gravity(
      tilted(roll, pitch, Eigen::Vector3d(0, 0, 0.5), {}, rng), 0.0, 1.0, noise);
  EXPECT_TRUE(up.accelerating);
  EXPECT_NEAR(up.gravity_deviation, 0.5, 1e-9);
  // Sideways by 2 m/s^2: the norm moves by 0.2 m/s^2 only, the gravity direction by ~0.2 rad;
  // flagged, and the inflated sigma (sqrt(|f|² - g²) / g) is the size of the error.
  const GravityAttitude side = attitude_from_gravity(
      tilted(roll, pitch, Eigen::Vector3d(2.0, 0, 0), {}, rng), 0.0, 1.0, noise);
  EXPECT_TRUE(side.accelerating);
  const double error = std::hypot(side.roll - roll, side.pitch - pitch);
  EXPECT_GT(error, 0.15);
  EXPECT_GT(std::hypot(side.sigma_roll, side.sigma_pitch), error);
  // Standing still: the sigma is the bias's, σ_ba / g.
  const GravityAttitude still =
      attitude_from_gravity(tilted(roll, pitch, Eigen::Vector3d::Zero(), {}, rng), 0.0, 1.0, noise);
  EXPECT_FALSE(still.accelerating);
  EXPECT_LT(still.sigma_pitch, 1.1 * noise.accel_bias_sigma / noise.gravity);
  EXPECT_GT(side.sigma_pitch, 50 * still.sigma_pitch);
  EXPECT_THROW((void)attitude_from_gravity({}, 0.0, 1.0, noise), ConfigError);
  EXPECT_THROW(
      (void)attitude_from_gravity(tilted(0, 0, Eigen::Vector3d::Zero(), {}, rng), 2.0, 3.0, noise),
      ConfigError);
}

}  // namespace
}  // namespace vdtnav
