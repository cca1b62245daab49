// Poor initial guesses: the explained fraction, the window search whose size follows the
// predicted uncertainty, and the optimization localizer that refuses scans the map does not
// explain, runs on odometry meanwhile, and finds itself again when the map comes back into view.
#include "vdtnav/estimation/guess_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scan_fixture.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {
namespace {

using test::world;

TEST(ExplainedFraction, CountsTheBeamsWithinTheDistanceAgainstABruteForceCount) {
  const VdtSensorModel model(world().map);
  std::mt19937 rng(3);
  const Pose2 truth = test::tour_pose(5);
  const ScanPoints scan = scan_points(test::simulate_scan(truth, 0.02, rng));
  ASSERT_GT(scan.size(), 500u);
  const auto& occ = world().plan.occupancy;
  std::vector<Eigen::Vector2d> walls;  // occupied cell centres: the thin walls of the fixture
  for (int y = 0; y < occ.size().y(); ++y) {
    for (int x = 0; x < occ.size().x(); ++x) {
      if (occ(Eigen::Vector2i(x, y)) != 0) walls.push_back(occ.cell_center(Eigen::Vector2i(x, y)));
    }
  }
  for (const Pose2& at :
       {truth, Pose2(truth + Pose2(0.05, 0.0, 0.0)), Pose2(truth + Pose2(0.0, 0.0, 0.3))}) {
    // Brute force: the distance of each endpoint to the nearest occupied cell centre.
    std::size_t n = 0;
    const Eigen::Rotation2Dd rot(at[2]);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector2d p = at.head<2>() + rot * scan.points[i];
      double best = 1e18;
      for (const Eigen::Vector2d& w : walls) best = std::min(best, (w - p).squaredNorm());
      n += best < 0.01;
    }
    const double expected = static_cast<double>(n) / static_cast<double>(scan.size());
    // The VDT is interpolated between cell centres: allow a few beams right at 0.1 m to differ.
    EXPECT_NEAR(explained_fraction(model, scan, at, 0.1), expected, 0.02) << at.transpose();
  }
  EXPECT_GT(explained_fraction(model, scan, truth, 0.1), 0.95);
  EXPECT_LT(explained_fraction(model, scan, truth + Pose2(0.0, 0.0, 0.3), 0.1), 0.6);
}

TEST(SearchGuess, PicksTheCandidateOfLeastTruncatedVcdAsAnExhaustiveSearchDoes) {
  // search_guess drops a candidate once part of its readings scores no better than the best so
  // far; the winner must be the exhaustive argmin over the same grid (first of equals kept).
  const VdtSensorModel model(world().map);
  GuessSearchOptions o;
  o.max_beams = 0;  // every beam, as truncated_vcd() scores them
  std::mt19937 rng(12);
  int moved = 0;
  for (std::size_t k : {1u, 4u, 9u, 14u, 19u}) {
    const Pose2 truth = test::tour_pose(k);
    const ScanPoints scan = scan_points(test::simulate_scan(truth, 0.02, rng));
    const Pose2 guess = truth + Pose2(0.17, -0.12, 0.11);
    Pose2 best = guess;
    double best_score = truncated_vcd(model, scan, guess, o.truncation);
    const int hxy = o.steps_xy / 2, hyaw = o.steps_yaw / 2;
    for (int a = -hyaw; a <= hyaw; ++a) {
      for (int i = -hxy; i <= hxy; ++i) {
        for (int j = -hxy; j <= hxy; ++j) {
          const Pose2 c(guess[0] + i * o.window_xy / hxy, guess[1] + j * o.window_xy / hxy,
                        wrap_angle(guess[2] + a * o.window_yaw / hyaw));
          const double score = truncated_vcd(model, scan, c, o.truncation);
          if (score < best_score) {
            best_score = score;
            best = c;
          }
        }
      }
    }
    const Pose2 found = search_guess(model, scan, guess, o);
    EXPECT_LT(pose_error(found, best).norm(), 1e-12)
        << found.transpose() << " vs " << best.transpose();
    moved += pose_error(best, guess).norm() > 0.0;
  }
  EXPECT_GE(moved, 4) << "the guesses should be worse than some candidate of the window";
}

TEST(SearchGuess, TheWindowGrowsWithTheCovarianceAndFindsTheBasin) {
  const VdtSensorModel model(world().map);
  VdtOptimizerOptions oo;
  const VdtOptimizer opt(world().map, oo);
  const GuessSearchOptions o;
  std::mt19937 rng(4);
  int recovered = 0;
  for (std::size_t k : {2u, 6u, 11u, 17u}) {
    const Pose2 truth = test::tour_pose(k);
    const ScanPoints scan = scan_points(test::simulate_scan(truth, 0.0, rng));
    const Pose2 guess = truth + Pose2(0.35, -0.25, 0.55);
    // The base window (0.2 m, 0.2 rad) cannot reach the truth: its best candidate stays inside.
    const Pose2 base = search_guess(model, scan, guess, o);
    EXPECT_LE(std::abs(base[0] - guess[0]), o.window_xy + 1e-12);
    EXPECT_LE(std::abs(wrap_angle(base[2] - guess[2])), o.window_yaw + 1e-12);
    // With the uncertainty of the guess (sigma 0.25 m, 0.25 rad) it can.
    const Eigen::Matrix3d p = Eigen::Vector3d(0.0625, 0.0625, 0.0625).asDiagonal();
    const Pose2 wide = search_guess(model, scan, guess, o, &p);
    const LocalizationResult r = opt.solve(scan, wide);
    const Eigen::Vector3d e = pose_error(r.pose, truth);
    recovered += e.head<2>().norm() < 2e-3 && std::abs(e[2]) < 1e-3;
  }
  EXPECT_EQ(recovered, 4);
}

TEST(VdtOptimizationLocalizer, RefusesUnexplainedScansAndRecoversAfterwards) {
  VdtOptimizerOptions o;
  o.bridge.enabled = false;  // the bare odometry in the gap (the bridge is tested below)
  VdtOptimizationLocalizer loc(world().map, o);
  std::mt19937 rng(5);
  const Pose2 start = test::tour_pose(8);
  loc.reset(start, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  // Ten steps turning on the spot by 0.5 rad; the odometry over-reports each turn by 0.05 rad,
  // and the scans come from a place the map lacks (every beam 0.6 m: a small unmapped room).
  LaserScan unmapped = test::simulate_scan(start, 0.0, rng);
  for (double& r : unmapped.ranges) r = 0.6;
  Pose2 truth = start, odometry_estimate = start;
  for (int k = 0; k < 10; ++k) {
    OdometryStep step;
    step.dt = 1.0;
    step.delta = Pose2(0.0, 0.0, 0.55);
    step.w = 0.55;
    truth = compose(truth, Pose2(0.0, 0.0, 0.5));
    odometry_estimate = compose(odometry_estimate, step.delta);
    const LocalizationResult r = loc.update(step, unmapped);
    EXPECT_NE(r.status, LocalizationStatus::kConverged) << "step " << k;  // refused, says why
    EXPECT_FALSE(r.has_covariance);
    EXPECT_LT(pose_error(r.pose, odometry_estimate).norm(), 1e-9);  // it kept the odometry
  }
  // Back in view of the map, 0.5 rad off: the grown window finds the basin.
  OdometryStep none;
  none.dt = 1.0;
  const LocalizationResult r = loc.update(none, test::simulate_scan(truth, 0.0, rng));
  EXPECT_EQ(r.status, LocalizationStatus::kConverged);
  const Eigen::Vector3d e = pose_error(r.pose, truth);
  EXPECT_LT(e.head<2>().norm(), 2e-3);
  EXPECT_LT(std::abs(e[2]), 1e-3);
}

TEST(VdtOptimizationLocalizer, BridgesAGapOfTheMapByMatchingTheRecentScans) {
  // The localizer's map lacks everything within 4 m of a stretch of the tour (a room the map
  // was not built from); the robot drives through it with odometry that over-reports every
  // turn by 10 % and every metre by 5 %. Scans come from the complete world.
  const std::vector<Eigen::Vector2d>& tour = world().plan.tour;
  const Pose2 a = test::tour_pose(3);
  OccupancyGrid<2> gap = world().plan.occupancy;
  for (int y = 0; y < gap.size().y(); ++y) {
    for (int x = 0; x < gap.size().x(); ++x) {
      const Eigen::Vector2i c(x, y);
      if ((gap.cell_center(c) - a.head<2>()).norm() < 4.0) gap(c) = 0;
    }
  }
  const VdtMap2 map = VdtMap2::build(gap);
  ASSERT_GT(tour.size(), 5u);
  std::mt19937 rng(9);
  // 32 poses along a smooth arc through the gap, 0.1 m and 0.03 rad apart.
  std::vector<Pose2> truth{compose(a, Pose2(-1.5, 0.0, 0.0))};
  for (int k = 1; k < 32; ++k) truth.push_back(compose(truth.back(), Pose2(0.1, 0.0, 0.03)));
  for (const bool bridge : {false, true}) {
    VdtOptimizerOptions o;
    o.bridge.enabled = bridge;
    VdtOptimizationLocalizer loc(map, o);
    loc.reset(truth[0], Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
    double worst = 0.0;
    int refused = 0;
    for (std::size_t k = 1; k < truth.size(); ++k) {
      const Pose2 d = between(truth[k - 1], truth[k]);
      OdometryStep step;
      step.dt = 0.1;
      step.delta = Pose2(1.05 * d[0], 1.05 * d[1], 1.1 * d[2]);
      const LocalizationResult r = loc.update(step, test::simulate_scan(truth[k], 0.01, rng));
      refused += r.status != LocalizationStatus::kConverged;
      worst = std::max(worst, (r.pose.head<2>() - truth[k].head<2>()).norm());
    }
    EXPECT_GT(refused, 10) << "the gap must be a gap for the test to mean anything";
    // Bridged, the error stays at the local map's rasterization offset (its walls are the centres
    // of 0.1 m cells: measured 0.04 m, constant along the gap); dead reckoning drifts to 0.18 m.
    if (bridge) {
      EXPECT_LT(worst, 0.05) << refused << " refused";
    } else {
      EXPECT_GT(worst, 0.1) << "dead reckoning alone should drift";
    }
  }
}

}  // namespace
}  // namespace vdtnav
