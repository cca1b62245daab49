// Lost detection (estimation/lost_detection.hpp) and the kidnapped robot
// (estimation/recovering_localizer.hpp): the window test against its definition (fixed drops,
// a baseline that follows the track's own spread), then vdt-opt and vdt-ekf as make_localizer
// builds them on a simulated drive whose robot is teleported: no false alarm before, lost and
// re-acquired at the right pose after, never a converged pose elsewhere once the window could
// know; and in a symmetric room, where global localization is ambiguous, lost is kept rather than
// a twin guessed.
#include "vdtnav/estimation/lost_detection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "scan_fixture.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/recovering_localizer.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace vdtnav {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Feeds `values` and returns the index of the first update that says lost (-1: none).
int first_lost(LostDetector& d, const std::vector<double>& values) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (d.update(values[k])) return static_cast<int>(k);
  }
  return -1;
}

std::vector<double> noisy(double mean, double sigma, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(mean, sigma);
  std::vector<double> v;
  for (int k = 0; k < n; ++k) v.push_back(std::clamp(g(rng), 0.0, 1.0));
  return v;
}

TEST(LostDetector, ASteadyTrackIsNeverLostAndADropIsWithinTheWindow) {
  LostDetector d;  // W = 5, lost_fraction 0.5, drop 0.25
  EXPECT_EQ(first_lost(d, noisy(0.95, 0.02, 2000, 1)), -1);
  // Scans at 0.3 after a baseline of ~0.95: the window's mean after j of them is
  // (0.95 (5 - j) + 0.3 j) / 5, below 0.95 - 0.25 from j = 2 on.
  const int k = first_lost(d, std::vector<double>(10, 0.3));
  EXPECT_EQ(k, 1);
  EXPECT_TRUE(d.lost());
  // Lost stays lost until the window explains found_fraction (no acquisition here): the window
  // (x, x, x, 0.3, 0.3) takes 0.7, then 0.9s; (0.3, 0.7, 0.9, 0.9, 0.9) has mean 0.74, and
  // (0.7, 0.9, 0.9, 0.9, 0.9) 0.86 >= 0.75.
  EXPECT_TRUE(d.update(0.7));
  for (int j = 0; j < 3; ++j) EXPECT_TRUE(d.update(0.9)) << j;
  EXPECT_FALSE(d.update(0.9));
  d.reset();
  EXPECT_FALSE(d.lost());
  EXPECT_EQ(d.window_mean(), 1.0);
  EXPECT_TRUE(std::isnan(d.baseline()));
}

TEST(LostDetector, TheMarginFollowsTheTracksOwnSpread) {
  // The same fall to 0.62: lost after a steady track (spread ~0.01: margin = drop = 0.25) ...
  LostDetector steady;
  ASSERT_EQ(first_lost(steady, noisy(0.99, 0.01, 500, 2)), -1);
  EXPECT_NEAR(steady.spread(), 0.01, 0.005);
  EXPECT_GE(first_lost(steady, std::vector<double>(10, 0.62)), 0);
  // ... not after a track that always scattered that much (spread 0.12: margin 3 s = 0.36).
  LostDetector scattered;
  ASSERT_EQ(first_lost(scattered, noisy(0.85, 0.12, 500, 3)), -1);
  EXPECT_NEAR(scattered.spread(), 0.12, 0.03);
  EXPECT_NEAR(scattered.baseline(), 0.85, 0.05);
  EXPECT_EQ(first_lost(scattered, std::vector<double>(10, 0.62)), -1);
  // Below lost_fraction is lost whatever the spread.
  EXPECT_GE(first_lost(scattered, std::vector<double>(10, 0.2)), 0);
}

TEST(LostDetector, NothingMeasuredCountsAsNothingExplainedAndBadOptionsThrow) {
  LostDetector d;
  for (int k = 0; k < 20; ++k) ASSERT_FALSE(d.update(0.9));
  int k = 0;
  while (!d.update(std::nan("")) && k < 10) ++k;
  EXPECT_LE(k, 2);
  for (auto set : {+[](LostDetectionOptions& o) { o.window = 0; },
                   +[](LostDetectionOptions& o) { o.lost_fraction = 1.5; },
                   +[](LostDetectionOptions& o) { o.found_fraction = 0.3; },
                   +[](LostDetectionOptions& o) { o.drop = 0.0; },
                   +[](LostDetectionOptions& o) { o.sigmas = -1.0; },
                   +[](LostDetectionOptions& o) { o.baseline_scans = 0; }}) {
    LostDetectionOptions o;
    set(o);
    EXPECT_THROW((LostDetector(o)), ConfigError);
  }
}

// ------------------------------------------------------------------ the kidnapped robot

struct Drive {
  std::vector<ScanPoints> scans;
  std::vector<OdometryStep> odometry;
  std::vector<Pose2> truth;
};

/// The generated floor plan's tour at 10 Hz with Table 3.2 noise.
const Drive& drive() {
  static const Drive d = [] {
    const auto& w = test::world();
    sim::TrajectoryOptions t;
    t.rate_hz = 10.0;
    t.min_steps = 600;
    const sim::SimulatedRun run =
        sim::simulate_run(w.plan.occupancy, sim::follow_path(w.plan.tour, w.plan.occupancy, t),
                          sim::LidarOptions{}, sim::NoiseProfile::table_3_2_sigma(), 11);
    Drive out;
    for (std::size_t k = 0; k < run.size(); ++k) {
      out.scans.push_back(scan_points(run.scans[k]));
      out.odometry.push_back(run.odometry[k]);
      out.truth.push_back(run.truth[k]);
    }
    return out;
  }();
  return d;
}

bool right(const Pose2& a, const Pose2& b) {
  return (a.head<2>() - b.head<2>()).norm() <= 0.3 && std::abs(wrap_angle(a[2] - b[2])) <= 0.1;
}
bool elsewhere(const Pose2& a, const Pose2& b) {
  return (a.head<2>() - b.head<2>()).norm() > 1.0 || std::abs(wrap_angle(a[2] - b[2])) > 0.5;
}

class Kidnapped : public ::testing::TestWithParam<const char*> {};

TEST_P(Kidnapped, NoFalseAlarmThenLostAndReacquiredAtTheRightPose) {
  const auto& w = test::world();
  const Drive& d = drive();
  ASSERT_GE(d.scans.size(), 600U);
  const LocalizerSettings settings;  // make_localizer's default: recovery on
  std::unique_ptr<Localizer2D> loc = make_localizer(GetParam(), w.map, w.plan.occupancy, settings);
  ASSERT_NE(dynamic_cast<RecoveringLocalizer*>(loc.get()), nullptr);
  loc->reset(d.truth[0], Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
  // 250 scans from the start, then the robot is carried three times, 60 scans each, to the scan
  // of the drive farthest from where it is (10 m and more: beyond any window the tracker searches
  // by itself), while its odometry reports an ordinary step.
  for (std::size_t k = 0; k < 250; ++k) {
    const LocalizationResult r = loc->update(k == 0 ? OdometryStep{} : d.odometry[k], d.scans[k]);
    ASSERT_NE(r.status, LocalizationStatus::kLost) << "false alarm at scan " << k;
    EXPECT_GE(r.explained, 0.0);
  }
  const int window = settings.recovery.lost.window;
  std::size_t from = 249;
  int lost = 0;
  for (int teleport = 0; teleport < 3; ++teleport) {
    std::size_t to = 0;
    for (std::size_t c = 0; c + 60 < d.scans.size(); c += 10) {
      if ((d.truth[c].head<2>() - d.truth[from].head<2>()).norm() >
          (d.truth[to].head<2>() - d.truth[from].head<2>()).norm())
        to = c;
    }
    ASSERT_GT((d.truth[to].head<2>() - d.truth[from].head<2>()).norm(), 10.0);
    int recovered_at = -1;
    for (int j = 0; j < 60; ++j) {
      const std::size_t k = to + static_cast<std::size_t>(j);
      const LocalizationResult r = loc->update(d.odometry[k], d.scans[k]);
      lost += r.status == LocalizationStatus::kLost;
      const bool converged = r.status == LocalizationStatus::kConverged;
      if (j >= window) {
        EXPECT_FALSE(converged && elsewhere(r.pose, d.truth[k]))
            << "scan " << j << " after the teleport to " << to << ": converged "
            << (r.pose - d.truth[k]).transpose();
      }
      if (recovered_at < 0 && converged && right(r.pose, d.truth[k])) recovered_at = j;
    }
    EXPECT_GE(recovered_at, 0) << to;
    EXPECT_LE(recovered_at, 20) << to;
    from = to + 59;
  }
  // Each teleport found lost and re-acquired by global localization (a scan whose acquisition is
  // accepted at once reports the acquisition, converged, not lost).
  EXPECT_EQ(static_cast<RecoveringLocalizer*>(loc.get())->recoveries(), 3) << lost << " lost";
}

TEST_P(Kidnapped, WithoutRecoveryTheLossIsReportedAndNothingElsewhereConverges) {
  const auto& w = test::world();
  const Drive& d = drive();
  LocalizerSettings settings;
  settings.recovery.recover = false;
  std::unique_ptr<Localizer2D> loc = make_localizer(GetParam(), w.map, w.plan.occupancy, settings);
  loc->reset(d.truth[0], Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
  for (std::size_t k = 0; k < 100; ++k) {
    (void)loc->update(k == 0 ? OdometryStep{} : d.odometry[k], d.scans[k]);
  }
  int lost = 0, searches = 0;
  for (std::size_t k = 450; k < 520; ++k) {
    const LocalizationResult r = loc->update(d.odometry[k], d.scans[k]);
    lost += r.status == LocalizationStatus::kLost;
    searches += r.work.global_searches;
    if (k >= 450 + 5 && r.status == LocalizationStatus::kConverged) {
      EXPECT_FALSE(elsewhere(r.pose, d.truth[k])) << "scan " << k;
    }
  }
  EXPECT_GE(lost, 50);
  EXPECT_EQ(searches, 0);
}

INSTANTIATE_TEST_SUITE_P(VdtLocalizers, Kidnapped, ::testing::Values("vdt-opt", "vdt-ekf"));

/// A tracker that stays where it was reset and says converged: what a tracker that slid onto a
/// wrong place looks like to the recovery, whatever the scans.
class StuckTracker final : public Localizer2D {
 public:
  void reset(const Pose2& pose, const Eigen::Matrix3d&) override { pose_ = pose; }
  using Localizer2D::update;
  LocalizationResult update(const OdometryStep&, const ScanPoints&) override {
    LocalizationResult r;
    r.status = LocalizationStatus::kConverged;
    r.pose = pose_;
    return r;
  }
  std::string name() const override { return "stuck"; }

 private:
  Pose2 pose_ = Pose2::Zero();
};

/// A scan of `grid` from `pose` (541 readings over 270 degrees, cell-centre surfaces).
ScanPoints scan_from(const OccupancyGrid<2>& grid, const Pose2& pose) {
  ScanPoints s;
  s.sigma_range = 0.01;
  for (int i = 0; i < 541; ++i) {
    const double b = -0.75 * kPi + 1.5 * kPi * i / 540.0;
    const Eigen::Vector2d u(std::cos(pose[2] + b), std::sin(pose[2] + b));
    const double r = sim::cast_ray<2>(grid, pose.head<2>(), u, 30.0, sim::RaySurface::kCellCentre);
    if (std::isfinite(r) && r > 0.1)
      s.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(std::cos(b), std::sin(b)), r,
            static_cast<std::size_t>(i));
  }
  return s;
}

TEST(RecoveringLocalizer, InASymmetricRoomTheLossIsKeptRatherThanATwinGuessed) {
  const OccupancyGrid<2> g = test::symmetric_room();  // every pose has a twin: ambiguous
  const VdtMap2 map = VdtMap2::build(g);
  RecoveringLocalizer loc(std::make_unique<StuckTracker>(), map, g, GlobalLocalizationOptions{});
  const Pose2 start(1.55, 1.25, 0.4), carried(4.05, 2.35, -2.0);
  loc.reset(start, Eigen::Matrix3d::Identity() * 1e-4);
  for (int k = 0; k < 10; ++k) {
    ASSERT_EQ(loc.update(OdometryStep{}, scan_from(g, start)).status,
              LocalizationStatus::kConverged);
  }
  int searches = 0;
  for (int k = 0; k < 15; ++k) {
    const LocalizationResult r = loc.update(OdometryStep{}, scan_from(g, carried));
    searches += r.work.global_searches;
    if (k >= 5) {
      EXPECT_EQ(r.status, LocalizationStatus::kLost) << k;
    }
  }
  EXPECT_GE(searches, 4);  // lost scans 1, 2, 4, 8 of the loss at least
  EXPECT_EQ(loc.recoveries(), 0);
}

TEST(RecoveringLocalizer, AStuckTrackerIsMovedToWhereTheScansAre) {
  const auto& w = test::world();
  RecoveringLocalizer loc(std::make_unique<StuckTracker>(), w.map, w.plan.occupancy,
                          GlobalLocalizationOptions{});
  const Pose2 start = test::tour_pose(1), carried = test::tour_pose(7);
  ASSERT_GT((start.head<2>() - carried.head<2>()).norm(), 3.0);
  loc.reset(start, Eigen::Matrix3d::Identity() * 1e-4);
  for (int k = 0; k < 10; ++k) (void)loc.update(OdometryStep{}, scan_from(w.plan.occupancy, start));
  int recovered_at = -1;
  for (int k = 0; k < 10 && recovered_at < 0; ++k) {
    const LocalizationResult r = loc.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
    if (r.status == LocalizationStatus::kConverged && right(r.pose, carried)) recovered_at = k;
    if (k == 0) {  // one scan is not a window
      EXPECT_NE(r.status, LocalizationStatus::kLost);
    }
  }
  // On the first scan already: its fall below the baseline asks for a clearly better pose
  // (check_drop), which the scan's true place is; by the window's test it would be a few later.
  EXPECT_GE(recovered_at, 0);
  EXPECT_LE(recovered_at, 5);
  EXPECT_EQ(loc.recoveries(), 1);
  // The tracker restarted there: the next scan is converged at the right pose, not lost.
  const LocalizationResult r = loc.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
  EXPECT_EQ(r.status, LocalizationStatus::kConverged);
  EXPECT_TRUE(right(r.pose, carried));
}

}  // namespace
}  // namespace vdtnav
