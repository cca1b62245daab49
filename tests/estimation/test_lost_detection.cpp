// Lost detection (estimation/lost_detection.hpp) and the kidnapped robot
// (estimation/recovering_localizer.hpp): the window test against its definition (pooled counts,
// undecided where the map cannot judge, doubt above the track's own baseline), then vdt-opt and
// vdt-ekf as make_localizer builds them on a simulated drive whose robot is teleported: no false
// alarm before, lost and re-acquired at the right pose after, never a converged pose elsewhere
// once the window could know; in a symmetric room, where two places pass, lost is kept rather
// than a twin guessed; and a drive through rooms the map lacks leaves the track as it was.
#include "vdtnav/estimation/lost_detection.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "scan_fixture.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/recovering_localizer.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace vdtnav {
namespace {

/// A scan of 200 readings: `judged` of them judged by the map, a share `c` of those contradicted.
ScanAgreement scan(double c, double judged = 0.9) {
  ScanAgreement a;
  a.readings = 200;
  const int j = static_cast<int>(std::lround(judged * a.readings));
  a.contradicted = static_cast<int>(std::lround(c * j));
  a.explained = j - a.contradicted;
  a.unknown = a.readings - j;
  return a;
}

/// Feeds scans of contradiction `values` and returns the index of the first update that says
/// lost (-1: none).
int first_lost(LostDetector& d, const std::vector<double>& values, double judged = 0.9) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (d.update(scan(values[k], judged))) return static_cast<int>(k);
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

TEST(LostDetector, ARightTrackIsNeverLostAndAWrongOneWithinTheWindow) {
  LostDetector d;  // W = 5, lost 0.5, found 0.3
  // What right poses on real maps look like: a few percent contradicted, dips to 0.25.
  EXPECT_EQ(first_lost(d, noisy(0.05, 0.06, 2000, 1)), -1);
  // A kidnapped track: scans at 0.9. The window's contradiction after j of them (equal judged
  // counts) is (0.05 (5 - j) + 0.9 j) / 5, at least 0.5 from j = 3 on (index 2).
  EXPECT_EQ(first_lost(d, std::vector<double>(10, 0.9)), 2);
  EXPECT_TRUE(d.lost());
  // Lost until a decided window is back at found_contradiction: the window (0.9 x 4, 0.1) is
  // 0.74, ... (0.9, 0.1 x 4) is 0.26.
  for (int j = 0; j < 3; ++j) EXPECT_TRUE(d.update(scan(0.1))) << j;
  EXPECT_FALSE(d.update(scan(0.1)));
  d.reset();
  EXPECT_FALSE(d.lost());
  EXPECT_FALSE(d.decided());
  EXPECT_TRUE(std::isnan(d.baseline()));
}

TEST(LostDetector, WhatTheMapCannotJudgeDecidesNothing) {
  // A robot in a room the map lacks: 90 % of the readings end in unknown space, and of the few
  // the map judges most are contradicted (a doorway seen at an angle). Undecided: never lost.
  LostDetector d;
  EXPECT_EQ(first_lost(d, std::vector<double>(100, 0.8), 0.1), -1);
  EXPECT_FALSE(d.decided());
  EXPECT_FALSE(d.in_doubt());
  // Once lost, an undecided stretch keeps the loss (nothing says the track is right again).
  ASSERT_GE(first_lost(d, std::vector<double>(10, 0.9)), 0);
  EXPECT_EQ(first_lost(d, std::vector<double>(20, 0.0), 0.05), 0);
  EXPECT_TRUE(d.lost());
  // Counts, not fractions, are pooled: one scan judged 5 times as much weighs 5 times more.
  LostDetectionOptions two;
  two.window = 2;
  LostDetector w(two);
  w.update(scan(1.0, 0.2));
  EXPECT_FALSE(w.update(scan(0.2, 1.0)));  // (40 + 40) / (40 + 200) = 0.33: doubt, not lost
  EXPECT_NEAR(w.contradiction(), 80.0 / 240.0, 1e-12);
  EXPECT_TRUE(w.in_doubt());
}

TEST(LostDetector, DoubtRisesAboveTheTracksOwnBaseline) {
  // The same rise to 0.22: doubt after a clean track (an exact map: spread ~0.01, margin 0.15)...
  LostDetector clean;
  ASSERT_EQ(first_lost(clean, noisy(0.01, 0.01, 300, 2)), -1);
  EXPECT_NEAR(clean.baseline(), 0.01, 0.01);
  bool doubt = false;
  for (int k = 0; k < 10; ++k) {
    EXPECT_FALSE(clean.update(scan(0.22)));
    doubt |= clean.in_doubt();
  }
  EXPECT_TRUE(doubt);
  // ... not after a track that always scattered more (its windows' spread ~0.04: the margin
  // 0.15 from a baseline of 0.12 puts the doubt at 0.27).
  LostDetector scattered;
  ASSERT_EQ(first_lost(scattered, noisy(0.12, 0.08, 500, 3)), -1);
  EXPECT_NEAR(scattered.baseline(), 0.12, 0.02);
  for (int k = 0; k < 10; ++k) {
    EXPECT_FALSE(scattered.update(scan(0.2)));
    EXPECT_FALSE(scattered.in_doubt()) << k;
  }
  // The absolute level decides whatever the baseline: 0.3 is doubt.
  for (int k = 0; k < 5; ++k) (void)scattered.update(scan(0.35));
  EXPECT_TRUE(scattered.in_doubt());
}

TEST(LostDetector, BadOptionsThrow) {
  for (auto set : {+[](LostDetectionOptions& o) { o.window = 0; },
                   +[](LostDetectionOptions& o) { o.lost_contradiction = 1.5; },
                   +[](LostDetectionOptions& o) { o.found_contradiction = 0.6; },
                   +[](LostDetectionOptions& o) { o.doubt_contradiction = 0.7; },
                   +[](LostDetectionOptions& o) { o.min_judged = -0.1; },
                   +[](LostDetectionOptions& o) { o.doubt_rise = 0.0; },
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
  const LocalizerSettings settings = exact_map_settings();  // a generated map; recovery on
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
      // No pose the default outputs hold (converged or bridged) is elsewhere once the window
      // has had its scans.
      if (j >= window) {
        EXPECT_FALSE(published_by_default(r.status) && elsewhere(r.pose, d.truth[k]))
            << "scan " << j << " after the teleport to " << to << ": " << to_string(r.status) << " "
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
  LocalizerSettings settings = exact_map_settings();
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
    if (k >= 450 + 5 && published_by_default(r.status)) {
      EXPECT_FALSE(elsewhere(r.pose, d.truth[k])) << "scan " << k << " " << to_string(r.status);
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
  for (int k = 0; k < 30; ++k) {
    const LocalizationResult r = loc.update(OdometryStep{}, scan_from(g, carried));
    if (k >= 5) {
      EXPECT_EQ(r.status, LocalizationStatus::kLost) << k;
    }
  }
  // The carried pose and its twin both pass the verification, again and again: never adopted.
  EXPECT_GE(loc.searches(), 2);
  EXPECT_GE(loc.ambiguous(), 2);
  EXPECT_EQ(loc.recoveries(), 0);
  bool twins = false;
  for (const Pose2& p : loc.ambiguous_poses()) twins |= right(p, carried);
  EXPECT_TRUE(twins);
}

TEST(RecoveringLocalizer, InASymmetricRoomFewerScansThanTheVerificationNeverMoveTheTrack) {
  // A right track (at `start`) gets one, then two, scans taken elsewhere (`odd`: they match `odd`
  // and its twin equally) before its own scans return. In doubt or lost, a candidate found by the
  // search on an odd scan must be confirmed by the scans after it (verify_scans = 3) like any
  // other: the track is never moved, to `odd` or to its twin, and never reported converged there.
  const OccupancyGrid<2> g = test::symmetric_room();
  const VdtMap2 map = VdtMap2::build(g);
  const Pose2 start(1.55, 1.25, 0.4), odd(1.0, 3.0, 1.0);
  const Pose2 odd_twin(5.7 - odd[0], 3.7 - odd[1], wrap_angle(odd[2] + kPi));
  ASSERT_GT((odd.head<2>() - start.head<2>()).norm(), 1.5);
  ASSERT_GT((odd_twin.head<2>() - start.head<2>()).norm(), 1.5);
  RecoveryOptions ro;
  ASSERT_EQ(ro.verify_scans, 3);
  for (int odd_scans = 1; odd_scans < ro.verify_scans; ++odd_scans) {
    RecoveringLocalizer loc(std::make_unique<StuckTracker>(), map, g, GlobalLocalizationOptions{},
                            ro);
    loc.reset(start, Eigen::Matrix3d::Identity() * 1e-4);
    for (int k = 0; k < 10; ++k) (void)loc.update(OdometryStep{}, scan_from(g, start));
    int candidates = 0;
    for (int k = 0; k < odd_scans + 15; ++k) {
      const Pose2& at = k < odd_scans ? odd : start;
      const LocalizationResult r = loc.update(OdometryStep{}, scan_from(g, at));
      candidates += r.work.candidates;
      EXPECT_TRUE(right(r.pose, start))
          << odd_scans << " odd scans, update " << k << ": moved to " << r.pose.transpose();
      EXPECT_FALSE(right(r.pose, odd) || right(r.pose, odd_twin)) << odd_scans << ", " << k;
    }
    EXPECT_EQ(loc.recoveries(), 0) << odd_scans;
    // The odd scans were noticed (a search ran, its candidates were weighed) and refused.
    EXPECT_GE(loc.searches() + candidates, 1) << odd_scans;
  }
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
  for (int k = 0; k < 20 && recovered_at < 0; ++k) {
    const LocalizationResult r = loc.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
    if (r.status == LocalizationStatus::kConverged && right(r.pose, carried)) recovered_at = k;
    if (k == 0) {  // one scan is not a window
      EXPECT_NE(r.status, LocalizationStatus::kLost);
    }
    // Never a converged pose at the stuck tracker's place once the window knows.
    if (k >= 3) {
      EXPECT_FALSE(r.status == LocalizationStatus::kConverged && !right(r.pose, carried)) << k;
    }
  }
  // The window (3 scans to lost), the search (the generated floor plan's in one update) and the
  // verification (verify_scans = 3) take about 7 scans.
  EXPECT_GE(recovered_at, 3);
  EXPECT_LE(recovered_at, 10);
  EXPECT_EQ(loc.recoveries(), 1);
  // The tracker restarted there: the next scan is converged at the right pose, not lost.
  const LocalizationResult r = loc.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
  EXPECT_EQ(r.status, LocalizationStatus::kConverged);
  EXPECT_TRUE(right(r.pose, carried));
}

TEST(RecoveringLocalizer, ATrackLeftBehindIsFoundAndNoPoseInDoubtIsPublishedElsewhere) {
  // The robot drives on while the tracker stays where it was (a track that stopped following).
  // Along the corridor the stuck pose is contradicted little (a window at 0.17 at 1.1 m off,
  // which the baseline absorbs as it rises: no doubt); when the robot turns the window rises into
  // doubt, and the search must find where the scans are: no pose published converged while in
  // doubt is more than a metre off, and the track is re-acquired (again each time it is left
  // behind).
  const auto& w = test::world();
  const Drive& d = drive();
  RecoveringLocalizer loc(std::make_unique<StuckTracker>(), w.map, w.plan.occupancy,
                          GlobalLocalizationOptions{});
  const std::size_t from = 100;
  loc.reset(d.truth[from], Eigen::Matrix3d::Identity() * 1e-4);
  int doubted = 0;
  for (std::size_t k = from; k < from + 80; ++k) {
    const LocalizationResult r = loc.update(d.odometry[k], d.scans[k]);
    if (!loc.detector().in_doubt()) continue;
    ++doubted;
    EXPECT_FALSE(r.status == LocalizationStatus::kConverged && elsewhere(r.pose, d.truth[k]))
        << k << " " << (r.pose - d.truth[k]).transpose();
  }
  EXPECT_GE(doubted, 2);
  EXPECT_GE(loc.recoveries(), 2);
}

TEST(RecoveringLocalizer, OnAWorkerThreadTheSearchRunsBesideTheUpdates) {
  // search_thread: the updates never score a box themselves; the search finishes on the worker
  // while they go on (paced here as a sensor would be), and its candidates are verified as in the
  // updates' own budget. A localizer destroyed mid-search stops its worker.
  const auto& w = test::world();
  RecoveryOptions o;
  o.search_thread = true;
  const Pose2 start = test::tour_pose(1), carried = test::tour_pose(7);
  {
    RecoveringLocalizer loc(std::make_unique<StuckTracker>(), w.map, w.plan.occupancy,
                            GlobalLocalizationOptions{}, o);
    loc.reset(start, Eigen::Matrix3d::Identity() * 1e-4);
    for (int k = 0; k < 10; ++k) {
      (void)loc.update(OdometryStep{}, scan_from(w.plan.occupancy, start));
    }
    int recovered_at = -1, searched = 0;
    for (int k = 0; k < 400 && recovered_at < 0; ++k) {
      const LocalizationResult r = loc.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
      EXPECT_EQ(r.work.search_boxes, 0) << k;
      searched += loc.searching();
      if (r.status == LocalizationStatus::kConverged && right(r.pose, carried)) recovered_at = k;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_GT(searched, 0);
    EXPECT_GE(recovered_at, 3);
    EXPECT_EQ(loc.recoveries(), 1);
  }
  RecoveringLocalizer busy(std::make_unique<StuckTracker>(), w.map, w.plan.occupancy,
                           GlobalLocalizationOptions{}, o);
  busy.reset(start, Eigen::Matrix3d::Identity() * 1e-4);
  for (int k = 0; k < 10; ++k)
    (void)busy.update(OdometryStep{}, scan_from(w.plan.occupancy, start));
  for (int k = 0; k < 5 && !busy.searching(); ++k) {
    (void)busy.update(OdometryStep{}, scan_from(w.plan.occupancy, carried));
  }
  EXPECT_TRUE(busy.searching());
}  // `busy` is destroyed with its search running: the worker stops within a chunk of boxes

TEST(RecoveringLocalizer, APlaceTheMapLacksIsNoEvidenceAgainstTheTrack) {
  // The map lacks the rooms between x0 and x1 (never seen: unknown cells, no walls); the robot
  // drives through them (scans 750-1150 of the tour). A right track there contradicts nothing
  // the map knows: never lost, never moved; only a track that went wrong in there (more than a
  // metre off) may be replaced. Told that every cell is known, the same run holds a fifth of the
  // readings there against the track and calls right tracks lost (or recovery moves them off).
  const auto& w = test::world();
  const Drive& d = drive();
  const double x0 = 12.0, x1 = 16.5;
  OccupancyGrid<2> part = w.plan.occupancy;
  Grid<std::int8_t, 2> cells(part.size(), part.frame(), -1);
  const auto gap = [&](const Eigen::Vector2d& p) { return p.x() >= x0 && p.x() <= x1; };
  for (std::size_t c = 0; c < part.num_cells(); ++c) {
    if (gap(part.cell_center(part.index_of(static_cast<std::ptrdiff_t>(c))))) {
      part[c] = 0;
    } else {
      cells[c] = part[c] ? 100 : 0;
    }
  }
  const VdtMap2 map = VdtMap2::build(part);
  const LocalizerSettings settings = exact_map_settings();
  std::unique_ptr<Localizer2D> b =
      make_localizer("vdt-opt", map, part, settings, MapKnowledge(cells));
  std::unique_ptr<Localizer2D> all_known = make_localizer("vdt-opt", map, part, settings);
  const auto* rb = static_cast<const RecoveringLocalizer*>(b.get());
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal();
  b->reset(d.truth[0], p0);
  all_known->reset(d.truth[0], p0);
  const std::size_t n = std::min<std::size_t>(d.scans.size(), 1500);
  const auto* rk = static_cast<const RecoveringLocalizer*>(all_known.get());
  int in_gap = 0, right_in_gap = 0, lost_right = 0, lost_right_all_known = 0;
  int moved_off_all_known = 0, recoveries_all_known = 0;
  // The default outputs in the gap (issue 57): how many of its correct poses (within 0.1 m) they
  // hold, and the poses they hold.
  int correct_in_gap = 0, correct_published_in_gap = 0, bridged = 0;
  double c_known = 0.0, c_all_known = 0.0;  // window contradiction at right poses in the gap
  Pose2 previous = d.truth[0];
  for (std::size_t k = 0; k < n; ++k) {
    const OdometryStep step = k == 0 ? OdometryStep{} : d.odometry[k];
    const int recoveries = rb->recoveries();
    const LocalizationResult r = b->update(step, d.scans[k]);
    const LocalizationResult ra = all_known->update(step, d.scans[k]);
    const double error = (r.pose.head<2>() - d.truth[k].head<2>()).norm();
    const bool inside = d.truth[k].x() > x0 + 0.5 && d.truth[k].x() < x1 - 0.5;
    in_gap += inside;
    right_in_gap += inside && error < 0.5;
    if (inside && error < 0.1) {
      ++correct_in_gap;
      correct_published_in_gap += published_by_default(r.status);
    }
    if (published_by_default(r.status)) {
      EXPECT_TRUE(r.has_covariance) << "scan " << k << " " << to_string(r.status);
    }
    if (r.status == LocalizationStatus::kBridged) {
      ++bridged;
      EXPECT_LT(error, 0.5) << "scan " << k << ": a bridged pose off the truth";
    }
    if (inside && error < 0.5) {
      c_known += rb->detector().contradiction();
      c_all_known += rk->detector().contradiction();
    }
    lost_right += r.status == LocalizationStatus::kLost && error < 0.5;
    const double error_all_known = (ra.pose.head<2>() - d.truth[k].head<2>()).norm();
    lost_right_all_known += ra.status == LocalizationStatus::kLost && error_all_known < 0.5;
    moved_off_all_known += rk->recoveries() > recoveries_all_known && error_all_known > 1.0;
    recoveries_all_known = rk->recoveries();
    if (rb->recoveries() > recoveries) {
      // An adoption: the track it replaced was wrong, the candidate is right.
      const Pose2 before = compose(previous, d.odometry[k].delta);
      EXPECT_GT((before.head<2>() - d.truth[k].head<2>()).norm(), 1.0) << "scan " << k;
      EXPECT_LT(error, 0.3) << "scan " << k;
    }
    previous = r.pose;
  }
  ASSERT_GT(in_gap, 100) << "the drive must enter what the map lacks";
  EXPECT_GT(right_in_gap, in_gap / 4) << "right tracks in the gap must be tested";
  EXPECT_EQ(lost_right, 0);
  // Blind to what the map knows, the gap's readings count against right tracks: they are called
  // lost, or moved off by recovery (a place explaining the scans "clearly better").
  EXPECT_GT(lost_right_all_known + moved_off_all_known, 0)
      << "the test would not tell a knowledge-blind detector";
  // The gap crossed by bridges, held by the default outputs; correct poses not withheld.
  EXPECT_GT(bridged, 50);
  EXPECT_GE(correct_published_in_gap, 0.95 * correct_in_gap)
      << correct_published_in_gap << " of " << correct_in_gap;
  // What the knowledge changes: the window's contradiction at right poses in the gap (0.008
  // against 0.21 when the missing rooms count as known free space).
  EXPECT_LT(c_known / right_in_gap, 0.05);
  EXPECT_GT(c_all_known / right_in_gap, 0.15);
}

TEST(LostDetection, AScanAloneContradictedAtScanDoubtContradictionIsInDoubt) {
  // Five right scans (nothing contradicted), then one whose readings the map judges are 60 %
  // contradicted: the window's sum (0.12 contradicted) neither reaches the levels nor rises enough
  // above a baseline that does not exist yet; the scan alone does, with the 3D setting.
  const auto scan = [](int explained, int contradicted) {
    ScanAgreement a;
    a.readings = explained + contradicted;
    a.explained = explained;
    a.contradicted = contradicted;
    return a;
  };
  LostDetectionOptions three_d;
  three_d.scan_doubt_contradiction = 0.5;
  LostDetector plain, with_scan(three_d);
  for (int k = 0; k < 5; ++k) {
    EXPECT_FALSE(plain.update(scan(1000, 0)));
    EXPECT_FALSE(with_scan.update(scan(1000, 0)));
  }
  EXPECT_FALSE(plain.update(scan(400, 600)));
  EXPECT_FALSE(with_scan.update(scan(400, 600)));
  EXPECT_FALSE(plain.in_doubt());
  EXPECT_TRUE(with_scan.in_doubt());
  EXPECT_FALSE(with_scan.lost());
  // The next right scan: no longer in doubt.
  with_scan.update(scan(1000, 0));
  EXPECT_FALSE(with_scan.in_doubt());
  three_d.scan_doubt_contradiction = 1.5;
  EXPECT_THROW(three_d.validate(), ConfigError);
}

}  // namespace
}  // namespace vdtnav
