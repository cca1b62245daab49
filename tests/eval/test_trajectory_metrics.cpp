// Trajectory metrics: association by stamp, interpolation, ATE (aligned and not) and RPE, each
// against a trajectory built with a known error (a rigid motion, a constant drift, a scale).
#include "vdtnav/eval/trajectory_metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "vdtnav/core/error.hpp"

namespace vdtnav::eval {
namespace {

/// A smooth looping reference: a lissajous-like path, yaw along the velocity, at rate_hz.
Trajectory2 reference_path(int n, double rate_hz = 10.0) {
  Trajectory2 traj;
  for (int k = 0; k < n; ++k) {
    const double t = 100.0 + k / rate_hz;
    const double s = 0.05 * k;
    const double x = 5.0 * std::sin(s), y = 3.0 * std::sin(2.0 * s);
    const double dx = 5.0 * std::cos(s), dy = 6.0 * std::cos(2.0 * s);
    traj.push_back({t, Pose2(x, y, std::atan2(dy, dx))});
  }
  return traj;
}

/// 3x3 homogeneous matrix of a pose (independent of pose2.hpp's compose/between).
Eigen::Matrix3d matrix(const Pose2& p) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(p[2]).toRotationMatrix();
  m.topRightCorner<2, 1>() = p.head<2>();
  return m;
}

TEST(ErrorStatistics, KnownList) {
  const ErrorStatistics s = error_statistics({3.0, 1.0, 2.0, 4.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(5.0 / 3.0));
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 4.0);
  EXPECT_EQ(error_statistics({5.0, 1.0, 2.0}).median, 2.0);
  EXPECT_EQ(error_statistics({}).count, 0u);
  EXPECT_EQ(s.p99, 4.0);  // ceil(0.99 * 4) = 4th smallest
}

TEST(ErrorStatistics, P99IsTheNearestRankPercentile) {
  // 1..n shuffled: the nearest-rank 99th percentile is ceil(0.99 n); at n = 100 it is 99 (one
  // value above it), at n = 1000 it is 990 (ten above), at n = 50 the 50th (the maximum).
  for (const int n : {1, 50, 100, 101, 1000}) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = (i * 7919) % n + 1.0;
    const ErrorStatistics s = error_statistics(v);
    const int above =
        static_cast<int>(std::count_if(v.begin(), v.end(), [&](double x) { return x > s.p99; }));
    EXPECT_LE(above, n / 100) << n;           // at least 99 % at or below it
    EXPECT_LT(n - above - 1, 0.99 * n) << n;  // the smallest such value: fewer are below it
    EXPECT_EQ(s.p99, std::ceil(0.99 * n)) << n;
  }
}

TEST(Associate, ClosestPairsOneToOneWithinTheMaximum) {
  Trajectory2 ref, est;
  for (int k = 0; k < 10; ++k) ref.push_back({static_cast<double>(k), Pose2::Zero()});
  // 0.004 s late, 0.02 s late (beyond 0.01), two stamps competing for reference 5, an extra one.
  est = {{0.004, Pose2::Zero()}, {1.02, Pose2::Zero()}, {4.995, Pose2::Zero()},
         {5.003, Pose2::Zero()}, {7.0, Pose2::Zero()},  {20.0, Pose2::Zero()}};
  const auto m = associate(est, ref, 0.01);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].estimate, 0u);
  EXPECT_EQ(m[0].reference, 0u);
  EXPECT_EQ(m[1].estimate, 3u);  // 5.003 is closer to 5 than 4.995
  EXPECT_EQ(m[1].reference, 5u);
  EXPECT_EQ(m[2].estimate, 4u);
  EXPECT_EQ(m[2].reference, 7u);
  EXPECT_EQ(associate(est, ref, 0.05).size(), 4u);  // 1.02 joins
  Trajectory2 unsorted = {{1.0, Pose2::Zero()}, {0.5, Pose2::Zero()}};
  EXPECT_THROW((void)associate(unsorted, ref, 0.01), ConfigError);
  EXPECT_THROW((void)associate(est, ref, -1.0), ConfigError);
}

TEST(Interpolate, LinearInPositionShortestArcInYawAndReportsGapsAndEnds) {
  const Trajectory2 traj = {{0.0, Pose2(0, 0, 3.0)},
                            {1.0, Pose2(2, 4, -3.0)},  // crosses +-pi: the short way is +0.28
                            {5.0, Pose2(6, 4, -3.0)}};
  InterpolatedPose p = interpolate(traj, 0.25, 2.0);
  ASSERT_TRUE(p.ok());
  EXPECT_NEAR(p.pose[0], 0.5, 1e-12);
  EXPECT_NEAR(p.pose[1], 1.0, 1e-12);
  EXPECT_NEAR(p.pose[2], wrap_angle(3.0 + 0.25 * (2.0 * kPi - 6.0)), 1e-12);
  EXPECT_DOUBLE_EQ(p.gap, 1.0);
  p = interpolate(traj, 0.5, 2.0);
  EXPECT_NEAR(std::abs(p.pose[2]), kPi, 1e-12);  // half way: through pi, not through 0
  // Between 1 and 5 the gap is 4 s.
  p = interpolate(traj, 3.0, 2.0);
  EXPECT_EQ(p.status, InterpolationStatus::kInGap);
  EXPECT_NEAR(p.pose[0], 4.0, 1e-12);
  EXPECT_TRUE(interpolate(traj, 3.0).ok());  // default max_gap: no limit
  // Exact stamps are samples, whatever the gap next to them.
  p = interpolate(traj, 5.0, 2.0);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.pose, traj[2].pose);
  EXPECT_EQ(interpolate(traj, 1.0, 0.1).status, InterpolationStatus::kOk);
  EXPECT_EQ(interpolate(traj, -0.1).status, InterpolationStatus::kBeforeStart);
  EXPECT_EQ(interpolate(traj, 5.1).status, InterpolationStatus::kAfterEnd);
  EXPECT_EQ(interpolate(Trajectory2{}, 0.0).status, InterpolationStatus::kEmpty);
}

TEST(Ate, RigidlyMovedReferenceIsZeroAlignedAndTheKnownOffsetUnaligned) {
  const Trajectory2 ref = reference_path(300);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  // Pure translation: every unaligned error is |offset|.
  {
    const Pose2 offset(0.3, -0.4, 0.0);
    Trajectory2 est;
    for (const auto& s : ref) est.push_back({s.t + jitter(rng), compose(offset, s.pose)});
    const AteResult ate = absolute_trajectory_error(est, ref);
    ASSERT_TRUE(ate.ok());
    EXPECT_EQ(ate.matches.size(), ref.size());
    EXPECT_NEAR(ate.unaligned_translation.mean, 0.5, 1e-12);
    EXPECT_NEAR(ate.unaligned_translation.min, 0.5, 1e-12);
    EXPECT_NEAR(ate.unaligned_translation.max, 0.5, 1e-12);
    EXPECT_NEAR(ate.unaligned_rotation.max, 0.0, 1e-12);
    EXPECT_LT(ate.translation.max, 1e-9);
    EXPECT_LT(ate.rotation.max, 1e-12);
    EXPECT_LT((ate.alignment - Pose2(-0.3, 0.4, 0.0)).norm(), 1e-9);
  }
  // A rotation about a far point: the unaligned error per pose is |T p - p| (matrices).
  {
    const Pose2 motion(2.0, -1.0, 0.7);
    Trajectory2 est;
    for (const auto& s : ref) est.push_back({s.t, compose(motion, s.pose)});
    const AteResult ate = absolute_trajectory_error(est, ref);
    ASSERT_TRUE(ate.ok());
    double sum_sq = 0.0, max = 0.0;
    for (const auto& s : ref) {
      const Eigen::Vector3d p(s.pose[0], s.pose[1], 1.0);
      const double e = ((matrix(motion) * p - p).head<2>()).norm();
      sum_sq += e * e;
      max = std::max(max, e);
    }
    EXPECT_NEAR(ate.unaligned_translation.rmse, std::sqrt(sum_sq / ref.size()), 1e-9);
    EXPECT_NEAR(ate.unaligned_translation.max, max, 1e-9);
    EXPECT_NEAR(ate.unaligned_rotation.mean, 0.7, 1e-12);
    EXPECT_LT(ate.translation.rmse, 1e-9);
    EXPECT_LT(ate.rotation.max, 1e-9);
    // The alignment undoes the motion.
    EXPECT_LT((matrix(ate.alignment) * matrix(motion) - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  }
}

TEST(Ate, NoisyEstimateAlignedRmseMatchesTheNoise) {
  const Trajectory2 ref = reference_path(2000);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> noise(0.0, 0.05);
  Trajectory2 est;
  const Pose2 motion(1.0, 2.0, -0.4);
  for (const auto& s : ref) {
    const Pose2 p = s.pose + Pose2(noise(rng), noise(rng), 0.0);
    est.push_back({s.t, compose(motion, p)});
  }
  const AteResult ate = absolute_trajectory_error(est, ref);
  ASSERT_TRUE(ate.ok());
  // |2D Gaussian| has RMS sigma sqrt(2).
  EXPECT_NEAR(ate.translation.rmse, 0.05 * std::sqrt(2.0), 0.004);
  EXPECT_GT(ate.unaligned_translation.rmse, 1.0);
}

TEST(Ate, NoMatchesOrOneMatchSaySo) {
  const Trajectory2 ref = reference_path(10);
  Trajectory2 far = ref;
  for (auto& s : far) s.t += 1000.0;
  EXPECT_EQ(absolute_trajectory_error(far, ref).status, MetricStatus::kNoMatches);
  const AteResult one = absolute_trajectory_error(Trajectory2{ref[3]}, ref);
  EXPECT_EQ(one.status, MetricStatus::kDegenerateAlignment);
  EXPECT_EQ(one.unaligned_translation.count, 1u);
  EXPECT_EQ(one.unaligned_translation.max, 0.0);
}

/// The estimate drifts by `drift` (in the robot frame) on every step of the reference.
Trajectory2 drifting(const Trajectory2& ref, const Pose2& drift) {
  Trajectory2 est = {ref.front()};
  for (std::size_t k = 1; k < ref.size(); ++k) {
    const Pose2 step = between(ref[k - 1].pose, ref[k].pose);
    est.push_back({ref[k].t, compose(compose(est.back().pose, step), drift)});
  }
  return est;
}

TEST(Rpe, ConstantDriftPerStepIsThePerStepError) {
  const Trajectory2 ref = reference_path(500);
  const Pose2 drift(0.01, -0.005, 0.002);
  const Trajectory2 est = drifting(ref, drift);
  for (const RpeOptions& o :
       {RpeOptions{RpeDelta::kFrames, 1.0}, RpeOptions{RpeDelta::kSeconds, 0.1}}) {
    const RpeResult rpe = relative_pose_error(est, ref, o);
    ASSERT_TRUE(rpe.ok());
    EXPECT_EQ(rpe.pairs, ref.size() - 1);
    EXPECT_NEAR(rpe.translation.mean, drift.head<2>().norm(), 1e-9);
    EXPECT_NEAR(rpe.translation.rmse, drift.head<2>().norm(), 1e-9);
    EXPECT_LT(rpe.translation.std, 1e-9);
    EXPECT_NEAR(rpe.rotation.mean, 0.002, 1e-9);
    EXPECT_NEAR(rpe.rotation.rmse, 0.002, 1e-9);
  }
  // Over 3 frames on a path with a known increment the error is the product of matrices:
  // E = (D1 D2 D3)^-1 (D1 d D2 d D3 d).
  const RpeResult rpe3 = relative_pose_error(est, ref, {RpeDelta::kFrames, 3.0});
  ASSERT_TRUE(rpe3.ok());
  const Eigen::Matrix3d d = matrix(drift);
  std::vector<double> expected;
  for (std::size_t i = 0; i + 3 < ref.size(); ++i) {
    Eigen::Matrix3d q = Eigen::Matrix3d::Identity(), p = Eigen::Matrix3d::Identity();
    for (std::size_t k = i; k < i + 3; ++k) {
      const Eigen::Matrix3d step = matrix(ref[k].pose).inverse() * matrix(ref[k + 1].pose);
      q = q * step;
      p = p * step * d;
    }
    expected.push_back((q.inverse() * p).topRightCorner<2, 1>().norm());
  }
  EXPECT_NEAR(rpe3.translation.mean, error_statistics(expected).mean, 1e-9);
  EXPECT_EQ(rpe3.pairs, expected.size());
}

TEST(Rpe, ScaleDriftOnAStraightLineOverATimeDelta) {
  // Reference along x at 1 m/s sampled at 10 Hz; the estimate reports 10 % more distance.
  Trajectory2 ref, est;
  for (int k = 0; k < 200; ++k) {
    const double t = 0.1 * k;
    ref.push_back({t, Pose2(t, 0.0, 0.0)});
    est.push_back({t, Pose2(1.1 * t, 0.0, 0.0)});
  }
  RpeOptions o;
  o.unit = RpeDelta::kSeconds;
  o.delta = 2.0;
  o.delta_tolerance = 0.01;  // x 2 s = 0.02 s: only spans of 2 s
  const RpeResult rpe = relative_pose_error(est, ref, o);
  ASSERT_TRUE(rpe.ok());
  EXPECT_NEAR(rpe.translation.mean, 0.2, 1e-9);
  EXPECT_NEAR(rpe.translation.max, 0.2, 1e-9);
  EXPECT_EQ(rpe.rotation.max, 0.0);
  EXPECT_EQ(rpe.pairs, 200u - 20u);
  // A 1 s hole in the data: the pairs that would span delta +- 0.05 s or more are left out.
  Trajectory2 ref_gap, est_gap;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    if (ref[k].t > 5.05 && ref[k].t < 5.95) continue;
    ref_gap.push_back(ref[k]);
    est_gap.push_back(est[k]);
  }
  o.delta_tolerance = 0.025;  // x 2 s = 0.05 s
  const RpeResult with_gap = relative_pose_error(est_gap, ref_gap, o);
  ASSERT_TRUE(with_gap.ok());
  EXPECT_NEAR(with_gap.translation.max, 0.2, 1e-9);  // no pair over a longer span
  EXPECT_LT(with_gap.pairs, rpe.pairs - 8);
  EXPECT_THROW((void)relative_pose_error(est, ref, {RpeDelta::kFrames, 1.5}), ConfigError);
}

}  // namespace
}  // namespace vdtnav::eval
