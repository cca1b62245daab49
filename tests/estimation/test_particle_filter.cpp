// The AMCL-style particle filter against independent oracles: compose() for the noise-free motion
// model, first-order propagation (Probabilistic Robotics Table 7.3's V M V^T) for its Monte Carlo
// covariance, brute-force nearest occupied cells for the likelihood field, N w_i for the
// low-variance sampler, chi-square quantiles for the KLD bound, and scans ray cast in a hand-made
// room for tracking.
#include "vdtnav/estimation/particle_filter.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ParticleFilterOptions noise_free() {
  ParticleFilterOptions o;
  o.alpha1 = o.alpha2 = o.alpha3 = o.alpha4 = 0.0;
  return o;
}

// ---------------------------------------------------------------------------------------------
// (1) Motion model without noise is compose(pose, delta).

TEST(OdometryMotionModel, NoiseFreeSampleIsCompose) {
  std::mt19937_64 rng(7);
  const ParticleFilterOptions o = noise_free();
  const std::vector<Pose2> poses = {Pose2(0, 0, 0), Pose2(1.5, -2.0, 0.7), Pose2(-3, 4, -3.1),
                                    Pose2(2, 2, kPi)};
  const std::vector<Pose2> deltas = {Pose2(0.3, 0.0, 0.0),      Pose2(0.2, 0.1, 0.4),
                                     Pose2(-0.25, 0.05, 0.1),  // backwards
                                     Pose2(0.0, -0.3, -1.0),   // sideways
                                     Pose2(0.0, 0.0, 2.5),     // rotation in place
                                     Pose2(0.004, -0.003, 0.2), Pose2(0, 0, 0)};
  for (const Pose2& p : poses) {
    for (const Pose2& d : deltas) {
      const OdometryMotion m = decompose_odometry(d, o);
      EXPECT_EQ(m.rot1_sd, 0.0);
      EXPECT_EQ(m.trans_sd, 0.0);
      EXPECT_EQ(m.rot2_sd, 0.0);
      const Pose2 got = sample_motion_model_odometry(p, m, rng);
      const Pose2 want = compose(p, d);
      EXPECT_NEAR(got[0], want[0], 1e-12);
      EXPECT_NEAR(got[1], want[1], 1e-12);
      EXPECT_NEAR(wrap_angle(got[2] - want[2]), 0.0, 1e-12);
      EXPECT_GT(got[2], -kPi);  // wrapped to (-pi, pi]
      EXPECT_LE(got[2], kPi);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// (2) With noise, the Monte Carlo covariance of one step is the first-order one.

TEST(OdometryMotionModel, MonteCarloMatchesFirstOrderPropagation) {
  ParticleFilterOptions o;
  o.alpha1 = 0.02;
  o.alpha2 = 0.01;
  o.alpha3 = 0.015;
  o.alpha4 = 0.01;
  const Pose2 pose(1.0, 2.0, 0.3);
  const Pose2 delta(0.5, 0.1, 0.25);
  const OdometryMotion m = decompose_odometry(delta, o);

  // The decomposition and its noise, restated (Table 5.6 with amcl's variances).
  const double rot1 = std::atan2(0.1, 0.5), trans = std::hypot(0.5, 0.1), rot2 = 0.25 - rot1;
  EXPECT_NEAR(m.rot1, rot1, 1e-15);
  EXPECT_NEAR(m.trans, trans, 1e-15);
  EXPECT_NEAR(m.rot2, rot2, 1e-15);
  const double var_rot1 = o.alpha1 * rot1 * rot1 + o.alpha2 * trans * trans;
  const double var_trans = o.alpha3 * trans * trans + o.alpha4 * (rot1 * rot1 + rot2 * rot2);
  const double var_rot2 = o.alpha1 * rot2 * rot2 + o.alpha2 * trans * trans;
  EXPECT_NEAR(m.rot1_sd * m.rot1_sd, var_rot1, 1e-15);
  EXPECT_NEAR(m.trans_sd * m.trans_sd, var_trans, 1e-15);
  EXPECT_NEAR(m.rot2_sd * m.rot2_sd, var_rot2, 1e-15);

  // First order: x' = x + trans cos(th + rot1), y' = y + trans sin(th + rot1),
  // th' = th + rot1 + rot2; V = d x' / d (rot1, trans, rot2), Sigma = V M V^T.
  const double h = pose[2] + rot1;
  Eigen::Matrix3d v;
  v << -trans * std::sin(h), std::cos(h), 0.0,  //
      trans * std::cos(h), std::sin(h), 0.0,    //
      1.0, 0.0, 1.0;
  const Eigen::Matrix3d cov =
      v * Eigen::Vector3d(var_rot1, var_trans, var_rot2).asDiagonal() * v.transpose();
  const Pose2 expected_mean = compose(pose, delta);

  constexpr int kSamples = 20000;
  std::mt19937_64 rng(42);
  std::vector<Pose2> s(kSamples);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (auto& p : s) {
    p = sample_motion_model_odometry(pose, m, rng);
    mean += pose_error(p, expected_mean);
  }
  mean /= kSamples;
  Eigen::Matrix3d mc = Eigen::Matrix3d::Zero();
  for (const auto& p : s) {
    const Eigen::Vector3d e = pose_error(p, expected_mean) - mean;
    mc += e * e.transpose();
  }
  mc /= kSamples - 1;
  // Mean within 4 standard errors (plus the second-order shift trans var_rot1 / 2 of a cosine).
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean[i], 0.0, 4.0 * std::sqrt(cov(i, i) / kSamples) + trans * var_rot1 / 2)
        << "axis " << i;
  }
  // Covariance within 5% of the first-order one, elementwise, relative to sqrt(S_ii S_jj).
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(mc(i, j) / std::sqrt(cov(i, i) * cov(j, j)),
                  cov(i, j) / std::sqrt(cov(i, i) * cov(j, j)), 0.05)
          << "(" << i << ", " << j << ")";
    }
    EXPECT_NEAR(mc(i, i) / cov(i, i), 1.0, 0.05) << "variance " << i;
  }
}

TEST(OdometryMotionModel, BackwardsIsAsCertainAsForwards) {
  ParticleFilterOptions o;  // amcl defaults
  const OdometryMotion fwd = decompose_odometry(Pose2(0.3, 0.0, 0.1), o);
  const OdometryMotion bwd = decompose_odometry(Pose2(-0.3, 0.0, 0.1), o);
  EXPECT_NEAR(std::abs(bwd.rot1), kPi, 1e-12);  // the translation points backwards
  EXPECT_NEAR(bwd.rot1_sd, fwd.rot1_sd, 1e-12);
  EXPECT_NEAR(bwd.trans_sd, fwd.trans_sd, 1e-12);
  EXPECT_NEAR(bwd.rot2_sd, fwd.rot2_sd, 1e-12);
  // A rotation in place with sub-centimetre jitter: no rot1 noise, rot2 carries the rotation.
  const OdometryMotion turn = decompose_odometry(Pose2(0.0, 0.001, 0.5), o);
  EXPECT_NEAR(turn.rot1_sd, std::sqrt(o.alpha2) * 0.001, 1e-12);
  EXPECT_NEAR(turn.rot2_sd, std::sqrt(o.alpha1 * 0.25 + o.alpha2 * 1e-6), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// (3) The likelihood field is the clamped distance to the nearest occupied cell centre.

TEST(LikelihoodField, EqualsBruteForceNearestOccupiedCell) {
  for (const double yaw : {0.0, 0.4}) {
    OccupancyGrid<2> g(Eigen::Vector2i(37, 23), GridFrame<2>(0.1, Eigen::Vector2d(-1.0, 0.5), yaw),
                       0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (auto& v : g.values()) v = uni(rng) < 0.03 ? 1 : 0;
    std::vector<Eigen::Vector2d> occupied;
    for (int j = 0; j < 23; ++j)
      for (int i = 0; i < 37; ++i)
        if (g(Eigen::Vector2i(i, j))) occupied.push_back(g.cell_center(Eigen::Vector2i(i, j)));
    ASSERT_GT(occupied.size(), 5U);

    const double max_d = 0.7;
    const LikelihoodField field(g, max_d);
    int clamped = 0;
    for (int j = 0; j < 23; ++j) {
      for (int i = 0; i < 37; ++i) {
        const Eigen::Vector2d c = g.cell_center(Eigen::Vector2i(i, j));
        double best = std::numeric_limits<double>::infinity();
        for (const auto& o : occupied) best = std::min(best, (c - o).norm());
        clamped += best > max_d;
        ASSERT_NEAR(field.distances()(Eigen::Vector2i(i, j)), std::min(best, max_d), 1e-5)
            << i << ", " << j;
        ASSERT_NEAR(field.distance(c + Eigen::Vector2d(0.02, -0.03)),
                    field.distances()(g.cell_of(c + Eigen::Vector2d(0.02, -0.03))), 0.0);
      }
    }
    EXPECT_GT(clamped, 0);                                          // the clamp was exercised
    EXPECT_EQ(field.distance(Eigen::Vector2d(-50.0, 3.0)), max_d);  // outside the map
  }
}

TEST(LikelihoodField, EmptyMapIsMaxDistanceEverywhere) {
  OccupancyGrid<2> g(Eigen::Vector2i(10, 8), GridFrame<2>(0.1, Eigen::Vector2d::Zero()), 0);
  const LikelihoodField field(g, 2.0);
  for (float d : field.distances().values()) EXPECT_EQ(d, 2.0F);
}

// ---------------------------------------------------------------------------------------------
// (4) Low-variance sampler counts are within 1 of N w_i.

TEST(LowVarianceSampler, CountsAreWithinOneOfExpected) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<double> w(50);
  for (auto& x : w) x = uni(rng) * uni(rng);  // skewed, some tiny
  w[7] = 0.0;
  w[30] = 5.0;  // one dominant particle
  double sum = 0.0;
  for (double x : w) sum += x;
  for (auto& x : w) x /= sum;
  std::vector<std::size_t> idx;
  for (const std::size_t n : {1000UL, 137UL, 50UL}) {
    for (const double u : {0.0, 0.3, 0.999999}) {
      low_variance_sampler(w, n, u, idx);
      ASSERT_EQ(idx.size(), n);
      std::vector<int> count(w.size(), 0);
      for (std::size_t k = 0; k < n; ++k) {
        ASSERT_LT(idx[k], w.size());
        if (k > 0) {
          ASSERT_LE(idx[k - 1], idx[k]);  // the sampler walks the CDF once
        }
        ++count[idx[k]];
      }
      for (std::size_t i = 0; i < w.size(); ++i) {
        EXPECT_LE(std::abs(count[i] - static_cast<double>(n) * w[i]), 1.0 + 1e-9)
            << "n=" << n << " u=" << u << " i=" << i;
      }
      EXPECT_EQ(count[7], 0);
    }
  }
}

// KLD bound: M_chi(k) = chi^2_{k-1, 1-delta} / (2 err) (Fox 2003). Quantiles from tables.
TEST(KldSampling, BoundMatchesChiSquareQuantiles) {
  // chi^2_{10, 0.99} = 23.209, chi^2_{50, 0.99} = 76.154, chi^2_{1, 0.99} = 6.635; z_0.99 = 2.3263
  EXPECT_NEAR(kld_sample_count(11, 0.01, 2.3263), 23.209 / 0.02, 0.005 * 23.209 / 0.02);
  EXPECT_NEAR(kld_sample_count(51, 0.05, 2.3263), 76.154 / 0.1, 0.005 * 76.154 / 0.1);
  EXPECT_NEAR(kld_sample_count(2, 0.01, 2.3263), 6.635 / 0.02, 0.05 * 6.635 / 0.02);
  EXPECT_EQ(kld_sample_count(1, 0.01, 2.3263), 1);
  EXPECT_LT(kld_sample_count(100, 0.01, 0.99), kld_sample_count(200, 0.01, 0.99));
}

// ---------------------------------------------------------------------------------------------
// A 7 m x 5 m room with one-cell walls around [0.5, 6.5] x [0.5, 4.5] (as in SLAM maps), a pillar
// and a round box, and scans ray cast in it. Walls are thin on purpose: the likelihood field is
// zero throughout a wall, so a thick wall with free space behind it lets endpoints slide into it
// for free and leaves the pose unobservable along its normal when the opposite wall is in the
// scanner's blind spot.

OccupancyGrid<2> room() {
  OccupancyGrid<2> g(Eigen::Vector2i(140, 100), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int j = 0; j < 100; ++j) {
    for (int i = 0; i < 140; ++i) {
      const Eigen::Vector2d c = g.cell_center(Eigen::Vector2i(i, j));
      const bool inside = c.x() > 0.5 && c.x() < 6.5 && c.y() > 0.5 && c.y() < 4.5;
      const bool in_box = c.x() > 0.45 && c.x() < 6.55 && c.y() > 0.45 && c.y() < 4.55;
      const bool pillar = (c - Eigen::Vector2d(5.3, 3.6)).cwiseAbs().maxCoeff() < 0.2;
      const bool box = (c - Eigen::Vector2d(1.2, 1.1)).norm() < 0.15;
      g(Eigen::Vector2i(i, j)) = (in_box && !inside) || pillar || box ? 1 : 0;
    }
  }
  return g;
}

LaserScan ray_cast_scan(const OccupancyGrid<2>& g, const Pose2& robot, const Pose2& mount,
                        std::mt19937& rng) {
  LaserScan scan;
  scan.angle_min = -0.75 * kPi;
  scan.angle_increment = 1.5 * kPi / 180;
  scan.range_max = 8.0;
  scan.mount = mount;
  scan.sigma_range = 0.01;
  std::normal_distribution<double> noise(0.0, scan.sigma_range);
  const Pose2 sensor = compose(robot, mount);
  for (int b = 0; b <= 180; ++b) {
    const double a = sensor[2] + scan.angle(static_cast<std::size_t>(b));
    const double r =
        sim::cast_ray<2>(g, sensor.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)), 8.0);
    scan.ranges.push_back(std::isfinite(r) ? r + noise(rng) : r);
  }
  return scan;
}

/// Pose k of a counter-clockwise circle of radius 1.2 m about (3, 2.5), 0.1 m per step.
Pose2 circle_pose(int k) {
  const double step = 0.1 / 1.2;
  const double phi = -0.5 * kPi + k * step;  // position angle about the centre
  return {3.0 + 1.2 * std::cos(phi), 2.5 + 1.2 * std::sin(phi), wrap_angle(phi + 0.5 * kPi)};
}

struct TrackingRun {
  double initial_error = 0.0;  // of the particle cloud's mean right after reset
  std::size_t initial_particles = 0;
  std::vector<double> position_error, yaw_error, position_sd;
  std::vector<std::size_t> particles;
  std::vector<LocalizationStatus> status;
};

TrackingRun track(const ParticleFilterOptions& options, int steps) {
  const OccupancyGrid<2> g = room();
  ParticleFilterLocalizer pf(g, options);
  const Pose2 mount(0.1, 0.0, 0.0);
  std::mt19937 rng(5);
  std::normal_distribution<double> odo_noise(0.0, 1.0);
  // Started 0.2 m / 0.1 rad off, with a covariance of that size.
  const Pose2 start = circle_pose(0);
  const Pose2 initial = start + Pose2(0.2 * std::cos(2.0), 0.2 * std::sin(2.0), 0.1);
  pf.reset(initial, Eigen::Vector3d(0.2 * 0.2, 0.2 * 0.2, 0.1 * 0.1).asDiagonal());
  TrackingRun run;
  Eigen::Vector2d cloud_mean = Eigen::Vector2d::Zero();
  for (const Pose2& p : pf.particles()) cloud_mean += p.head<2>() / pf.particles().size();
  run.initial_error = (cloud_mean - start.head<2>()).norm();
  run.initial_particles = pf.particles().size();
  for (int k = 1; k <= steps; ++k) {
    OdometryStep odo;
    odo.dt = 0.1;
    odo.delta = between(circle_pose(k - 1), circle_pose(k));
    odo.delta += Pose2(0.005 * odo_noise(rng), 0.002 * odo_noise(rng), 0.005 * odo_noise(rng));
    const LocalizationResult r = pf.update(odo, ray_cast_scan(g, circle_pose(k), mount, rng));
    const Eigen::Vector3d e = pose_error(r.pose, circle_pose(k));
    run.position_error.push_back(e.head<2>().norm());
    run.yaw_error.push_back(std::abs(e[2]));
    run.position_sd.push_back(std::sqrt(r.covariance(0, 0) + r.covariance(1, 1)));
    run.particles.push_back(pf.particles().size());
    run.status.push_back(r.status);
    EXPECT_TRUE(r.has_covariance);
    EXPECT_EQ(r.inliers, options.max_beams);
    EXPECT_EQ(r.dropped, 0);
    EXPECT_TRUE(r.covariance.allFinite());
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(r.covariance).eigenvalues().minCoeff(),
              -1e-12);
  }
  return run;
}

// ---------------------------------------------------------------------------------------------
// (5) Tracking in the room.

TEST(ParticleFilterLocalizer, ConvergesAndTracksInARoom) {
  const TrackingRun run = track(ParticleFilterOptions{}, 60);
  EXPECT_NEAR(run.initial_error, 0.2, 0.02);  // the start really is off
  for (std::size_t k = 19; k < run.position_error.size(); ++k) {
    EXPECT_EQ(run.status[k], LocalizationStatus::kConverged);
    EXPECT_LT(run.position_error[k], 0.05) << "step " << k + 1;
    EXPECT_LT(run.yaw_error[k], 0.03) << "step " << k + 1;
    EXPECT_LT(run.position_sd[k], 0.15) << "step " << k + 1;  // the cloud has contracted
    EXPECT_EQ(run.particles[k], 2000U);
  }
}

TEST(ParticleFilterLocalizer, KldShrinksTheSetOnceConverged) {
  ParticleFilterOptions o;
  o.kld = true;
  const TrackingRun run = track(o, 60);
  EXPECT_EQ(run.initial_particles, 5000U);  // amcl starts KLD at max_particles
  for (std::size_t k = 19; k < run.position_error.size(); ++k) {
    EXPECT_LT(run.position_error[k], 0.05) << "step " << k + 1;
    EXPECT_LT(run.yaw_error[k], 0.03) << "step " << k + 1;
    EXPECT_GE(run.particles[k], 500U);
    EXPECT_LT(run.particles[k], 1500U) << "step " << k + 1;  // well below max_particles = 5000
  }
}

TEST(ParticleFilterLocalizer, SameSeedSameResult) {
  const OccupancyGrid<2> g = room();
  ParticleFilterLocalizer a(g), b(g);
  std::mt19937 rng(1);
  const LaserScan scan = ray_cast_scan(g, circle_pose(1), Pose2::Zero(), rng);
  OdometryStep odo;
  odo.delta = between(circle_pose(0), circle_pose(1));
  a.reset(circle_pose(0), Eigen::Matrix3d::Identity() * 0.01);
  b.reset(circle_pose(0), Eigen::Matrix3d::Identity() * 0.01);
  const LocalizationResult ra = a.update(odo, scan), rb = b.update(odo, scan);
  EXPECT_EQ(ra.pose, rb.pose);
  EXPECT_EQ(ra.covariance, rb.covariance);
  EXPECT_EQ(a.name(), "pf");
}

// The scan log-likelihood of one noise-free particle, restated: final_cost = -sum over the
// subsampled valid beams of log(z_hit N(d; 0, sigma_hit^2) + z_rand / range_max), d the brute-force
// distance from the endpoint's cell centre to the nearest occupied cell centre, clamped, and the
// clamp for endpoints outside the map.
TEST(ParticleFilterLocalizer, ScanLikelihoodIsTheLikelihoodFieldModel) {
  const OccupancyGrid<2> g = room();
  std::vector<Eigen::Vector2d> occupied;
  for (std::size_t l = 0; l < g.num_cells(); ++l)
    if (g[l]) occupied.push_back(g.cell_center(g.index_of(static_cast<std::ptrdiff_t>(l))));
  ParticleFilterOptions o = noise_free();
  o.particles = 1;
  o.max_beams = 3;
  o.sigma_hit = 0.3;
  o.z_hit = 0.8;
  o.z_rand = 0.2;
  o.max_likelihood_distance = 1.0;
  ParticleFilterLocalizer pf(g, o);
  const Pose2 pose(2.0, 1.5, 0.3);
  pf.reset(pose, Eigen::Matrix3d::Zero());
  LaserScan scan;
  scan.angle_min = -1.0;
  scan.angle_increment = 0.5;
  scan.range_max = 12.0;
  scan.mount = Pose2(0.2, 0.1, 0.05);
  // valid beams: 0, 2, 3, 5, 6 -> subsampled: valid #0, #2, #4 = beams 0, 3, 6 (beam 6 leaves the
  // map).
  scan.ranges = {1.3, kNaN, 0.9, 2.2, 0.05 /* < range_min */, 1.7, 11.0};
  double expected = 0.0;
  for (const int b : {0, 3, 6}) {
    const double a = scan.angle(static_cast<std::size_t>(b));
    const Eigen::Vector2d in_robot =
        transform_point(scan.mount, scan.ranges[b] * Eigen::Vector2d(std::cos(a), std::sin(a)));
    const Eigen::Vector2d end = transform_point(pose, in_robot);
    const Eigen::Vector2i cell = g.cell_of(end);
    double d = o.max_likelihood_distance;
    EXPECT_EQ(g.contains(cell), b != 6);
    if (g.contains(cell)) {
      for (const auto& c : occupied) d = std::min(d, (g.cell_center(cell) - c).norm());
    }
    const double hit =
        std::exp(-d * d / (2 * o.sigma_hit * o.sigma_hit)) / (std::sqrt(2 * kPi) * o.sigma_hit);
    expected += std::log(o.z_hit * hit + o.z_rand / scan.range_max);
  }
  const LocalizationResult r = pf.update(OdometryStep{}, scan);
  EXPECT_EQ(r.status, LocalizationStatus::kConverged);
  EXPECT_EQ(r.inliers, 3);
  EXPECT_EQ(r.dropped, 2);
  EXPECT_NEAR(r.final_cost, -expected, 1e-5);
  EXPECT_EQ(r.pose, pose);
}

// ---------------------------------------------------------------------------------------------
// (6) No usable beam: prediction only.

TEST(ParticleFilterLocalizer, EmptyOrAllNanScanPredictsOnly) {
  const OccupancyGrid<2> g = room();
  ParticleFilterLocalizer pf(g, noise_free());
  pf.reset(Pose2(3.0, 2.0, 0.5), Eigen::Vector3d(0.04, 0.09, 0.01).asDiagonal());
  LaserScan nan_scan;
  nan_scan.angle_min = -1.0;
  nan_scan.angle_increment = 0.01;
  nan_scan.ranges.assign(200, kNaN);
  LaserScan empty_scan;
  OdometryStep odo;
  odo.delta = Pose2(0.2, -0.05, 0.3);
  for (const LaserScan* scan : {&empty_scan, &nan_scan}) {
    const std::vector<Pose2> before = pf.particles();
    const std::vector<double> weights_before = pf.weights();
    const LocalizationResult r = pf.update(odo, *scan);
    EXPECT_EQ(r.status, LocalizationStatus::kTooFewObservations);
    EXPECT_EQ(r.inliers, 0);
    EXPECT_EQ(r.dropped, static_cast<int>(scan->ranges.size()));
    ASSERT_EQ(pf.particles().size(), before.size());
    // The estimate: weighted mean, circular mean of yaw, weighted covariance about it.
    double mx = 0.0, my = 0.0, mc = 0.0, ms = 0.0;
    for (std::size_t i = 0; i < before.size(); ++i) {
      const Pose2 want = compose(before[i], odo.delta);
      ASSERT_NEAR(pose_error(pf.particles()[i], want).norm(), 0.0, 1e-12) << i;
      ASSERT_EQ(pf.weights()[i], weights_before[i]);
      const double w = pf.weights()[i];
      mx += w * pf.particles()[i][0];
      my += w * pf.particles()[i][1];
      mc += w * std::cos(pf.particles()[i][2]);
      ms += w * std::sin(pf.particles()[i][2]);
    }
    const Pose2 mean(mx, my, std::atan2(ms, mc));
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < before.size(); ++i) {
      Eigen::Vector3d e = pf.particles()[i] - mean;
      e[2] = std::remainder(e[2], 2 * kPi);
      cov += pf.weights()[i] * e * e.transpose();
    }
    EXPECT_FALSE(pf.resampled());
    EXPECT_NEAR(pose_error(r.pose, mean).norm(), 0.0, 1e-9);
    EXPECT_TRUE(r.has_covariance);
    EXPECT_NEAR((r.covariance - cov).norm(), 0.0, 1e-9);
    EXPECT_GT(r.covariance.trace(), 0.0);
  }
}

TEST(ParticleFilterLocalizer, ZeroCovarianceResetPutsEveryParticleAtThePose) {
  ParticleFilterLocalizer pf(room());
  const Pose2 p(2.0, 3.0, -2.0);
  pf.reset(p, Eigen::Matrix3d::Zero());
  ASSERT_EQ(pf.particles().size(), 2000U);
  for (const Pose2& q : pf.particles()) ASSERT_EQ(q, p);
  // A singular covariance (yaw only) moves yaw only.
  pf.reset(p, Eigen::Vector3d(0.0, 0.0, 0.01).asDiagonal());
  double yaw_var = 0.0;
  for (const Pose2& q : pf.particles()) {
    ASSERT_NEAR(q[0], p[0], 1e-12);
    ASSERT_NEAR(q[1], p[1], 1e-12);
    yaw_var += wrap_angle(q[2] - p[2]) * wrap_angle(q[2] - p[2]) / 2000;
  }
  EXPECT_NEAR(yaw_var, 0.01, 0.001);
  EXPECT_THROW(pf.reset(Pose2(kNaN, 0, 0), Eigen::Matrix3d::Zero()), ConfigError);
}

TEST(ParticleFilterLocalizer, UpdateGateHoldsTheFilterUntilTheRobotMoves) {
  const OccupancyGrid<2> g = room();
  ParticleFilterOptions o;
  o.update_min_d = 0.25;
  o.update_min_a = 0.2;
  ParticleFilterLocalizer pf(g, o);
  pf.reset(circle_pose(0), Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal());
  std::mt19937 rng(2);
  OdometryStep odo;
  // The first scan after reset always runs.
  EXPECT_EQ(pf.update(odo, ray_cast_scan(g, circle_pose(0), Pose2::Zero(), rng)).status,
            LocalizationStatus::kConverged);
  const std::vector<Pose2> held = pf.particles();
  odo.delta = between(circle_pose(0), circle_pose(1));  // 0.1 m, 0.083 rad: below the gate
  const LocalizationResult gated =
      pf.update(odo, ray_cast_scan(g, circle_pose(1), Pose2::Zero(), rng));
  EXPECT_EQ(gated.status, LocalizationStatus::kTooFewObservations);
  EXPECT_EQ(pf.particles(), held);
  EXPECT_LT(pose_error(gated.pose, circle_pose(1)).head<2>().norm(), 0.05);  // dead-reckoned
  odo.delta = between(circle_pose(1), circle_pose(3));  // 0.3 m accumulated: runs
  const LocalizationResult ran =
      pf.update(odo, ray_cast_scan(g, circle_pose(3), Pose2::Zero(), rng));
  EXPECT_EQ(ran.status, LocalizationStatus::kConverged);
  EXPECT_LT(pose_error(ran.pose, circle_pose(3)).head<2>().norm(), 0.05);
}

TEST(ParticleFilterLocalizer, BadOptionsThrow) {
  const OccupancyGrid<2> g = room();
  const auto throws = [&](auto edit) {
    ParticleFilterOptions o;
    edit(o);
    EXPECT_THROW((void)ParticleFilterLocalizer(g, o), ConfigError);
  };
  throws([](ParticleFilterOptions& o) { o.particles = 0; });
  throws([](ParticleFilterOptions& o) { o.max_beams = 0; });
  throws([](ParticleFilterOptions& o) { o.sigma_hit = 0.0; });
  throws([](ParticleFilterOptions& o) { o.sigma_hit = kNaN; });
  throws([](ParticleFilterOptions& o) { o.z_hit = 1.5; });
  throws([](ParticleFilterOptions& o) { o.z_rand = -0.1; });
  throws([](ParticleFilterOptions& o) { o.z_hit = o.z_rand = 0.0; });
  throws([](ParticleFilterOptions& o) { o.alpha3 = -1.0; });
  throws([](ParticleFilterOptions& o) { o.max_likelihood_distance = 0.0; });
  throws([](ParticleFilterOptions& o) { o.min_particles = 0; });
  throws([](ParticleFilterOptions& o) { o.max_particles = 100; });  // < min_particles
  throws([](ParticleFilterOptions& o) { o.kld_err = 0.0; });
  throws([](ParticleFilterOptions& o) { o.update_min_d = -1.0; });
  EXPECT_THROW((void)ParticleFilterLocalizer(OccupancyGrid<2>(), ParticleFilterOptions{}),
               ConfigError);
  EXPECT_NO_THROW((void)ParticleFilterLocalizer(g, ParticleFilterOptions{}));
}

}  // namespace
}  // namespace vdtnav
