// Global localization (estimation/global_localization.hpp): the branch and bound's best leaf
// against an exhaustive search with an independent brute-force distance, poses found from random
// free poses of the generated floor plan, a symmetric room refused as ambiguous, random sampling,
// and bad options.
#include "vdtnav/estimation/global_localization.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "../thread_count.hpp"
#include "scan_fixture.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

/// A scan of `grid` from `pose`: 270 degrees, `beams` readings, ray cast to cell centres.
ScanPoints scan_in(const OccupancyGrid<2>& grid, const Pose2& pose, double sigma, std::mt19937& rng,
                   int beams = 541) {
  std::normal_distribution<double> n(0.0, sigma);
  ScanPoints s;
  s.sigma_range = std::max(sigma, 0.01);
  for (int i = 0; i < beams; ++i) {
    const double b = -0.75 * kPi + 1.5 * kPi * i / (beams - 1);
    const Eigen::Vector2d u(std::cos(pose[2] + b), std::sin(pose[2] + b));
    const double r = sim::cast_ray<2>(grid, pose.head<2>(), u, 30.0, sim::RaySurface::kCellCentre);
    if (!std::isfinite(r) || r < 0.1) continue;
    s.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(std::cos(b), std::sin(b)),
          r + (sigma > 0 ? n(rng) : 0.0), static_cast<std::size_t>(i));
  }
  return s;
}

Pose2 random_free_pose(const OccupancyGrid<2>& grid, const VdtMap2& map, std::mt19937& rng,
                       double clearance) {
  std::uniform_int_distribution<int> x(0, grid.size().x() - 1), y(0, grid.size().y() - 1);
  std::uniform_real_distribution<double> yaw(-kPi, kPi);
  while (true) {
    const Eigen::Vector2i i(x(rng), y(rng));
    if (grid(i)) continue;
    const Eigen::Vector2d p = grid.cell_center(i);
    if (map.value(p).norm() < clearance) continue;
    return Pose2(p.x(), p.y(), yaw(rng));
  }
}

/// A small asymmetric room: 5.3 x 4.3 m in a 6 x 5 m grid of 0.1 m cells, two interior walls
/// and a pillar.
OccupancyGrid<2> small_room() {
  OccupancyGrid<2> g(Eigen::Vector2i(60, 50), GridFrame<2>(0.1, Eigen::Vector2d(-1.0, 2.0)), 0);
  for (int y = 0; y < 50; ++y) {
    for (int x = 0; x < 60; ++x) {
      // Walls inside a margin of free cells (the spline is clamped at the grid's edge).
      const bool border =
          ((x == 3 || x == 56) && y >= 3 && y <= 46) || ((y == 3 || y == 46) && x >= 3 && x <= 56);
      const bool wall = (x == 20 && y < 30 && y > 3) || (y == 35 && x > 35 && x < 56);
      const bool pillar = x >= 44 && x <= 46 && y >= 10 && y <= 12;
      g(Eigen::Vector2i(x, y)) = (border || wall || pillar) ? 1 : 0;
    }
  }
  return g;
}

TEST(GlobalLocalization, BestLeafIsTheExhaustiveSearchsMinimum) {
  const OccupancyGrid<2> grid = small_room();
  const VdtMap2 map = VdtMap2::build(grid);
  GlobalLocalizationOptions o;
  o.angular_step = 3.0 * kPi / 180.0;
  o.max_readings = 40;
  o.levels = 4;
  const GlobalLocalizer loc(map, grid, o);
  // Surface cell centres (occupied, a free face-neighbour) for the brute-force distance: the
  // VDT's features, which a reading rounded into the pillar is measured to.
  std::vector<Eigen::Vector2i> occupied;
  for (int y = 0; y < 50; ++y) {
    for (int x = 0; x < 60; ++x) {
      if (!grid(Eigen::Vector2i(x, y))) continue;
      bool exposed = false;
      for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0),
                                       Eigen::Vector2i(0, 1), Eigen::Vector2i(0, -1)}) {
        const Eigen::Vector2i j = Eigen::Vector2i(x, y) + d;
        exposed |= grid.contains(j) && !grid(j);
      }
      if (exposed) occupied.emplace_back(x, y);
    }
  }
  const double tau2 = o.truncation * o.truncation, h = 0.1;
  std::mt19937 rng(11);
  int accepted = 0;
  for (int trial = 0; trial < 3; ++trial) {
    const Pose2 truth = random_free_pose(grid, map, rng, 0.3);
    const ScanPoints scan = scan_in(grid, truth, 0.01, rng);
    const GlobalLocalizationResult r = loc.localize(scan);
    // The readings the localizer scores: max_readings evenly over the scan.
    std::vector<Eigen::Vector2d> pts;
    for (int k = 0; k < o.max_readings; ++k) {
      pts.push_back(scan.points[static_cast<std::size_t>(k) * scan.size() / o.max_readings]);
    }
    const int angles = static_cast<int>(std::ceil(2.0 * kPi / o.angular_step - 1e-9));
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < angles; ++a) {
      const Eigen::Rotation2Dd rot(a * 2.0 * kPi / angles);
      std::vector<Eigen::Vector2i> off;
      for (const auto& p : pts) {
        const Eigen::Vector2d u = rot * p / h;
        off.emplace_back(static_cast<int>(std::lround(u.x())),
                         static_cast<int>(std::lround(u.y())));
      }
      for (int cy = 0; cy < 50; ++cy) {
        for (int cx = 0; cx < 60; ++cx) {
          if (grid(Eigen::Vector2i(cx, cy))) continue;
          double s = 0.0;
          for (const auto& d : off) {
            const Eigen::Vector2i c(cx + d.x(), cy + d.y());
            if (c.x() < 0 || c.y() < 0 || c.x() >= 60 || c.y() >= 50) {
              s += tau2;
              continue;
            }
            double d2 = std::numeric_limits<double>::infinity();
            for (const auto& q : occupied) d2 = std::min(d2, (c - q).cast<double>().squaredNorm());
            s += std::min(d2 * h * h, tau2);
            if (s >= best) break;
          }
          best = std::min(best, s);
        }
      }
    }
    EXPECT_NEAR(r.best_leaf_score, best, 1e-4 * (1.0 + best)) << "trial " << trial;
    // Accepted only where right (the room's halves look alike from some poses: refused there).
    if (r.result.status == LocalizationStatus::kConverged) {
      ++accepted;
      EXPECT_LT((r.result.pose.head<2>() - truth.head<2>()).norm(), 0.1);
      EXPECT_LT(std::abs(wrap_angle(r.result.pose[2] - truth[2])), 0.05);
    } else {
      EXPECT_TRUE(r.ambiguous);
    }
  }
  EXPECT_GE(accepted, 1);
}

TEST(GlobalLocalization, FindsRandomPosesOfTheFloorPlanAndAcceptsNoWrongOne) {
  const auto& w = test::world();
  const GlobalLocalizer loc(w.map, w.plan.occupancy);
  std::mt19937 rng(5);
  int accepted = 0, right = 0;
  const int trials = 12;
  double seconds = 0.0;
  for (int t = 0; t < trials; ++t) {
    const Pose2 truth = random_free_pose(w.plan.occupancy, w.map, rng, 0.3);
    const ScanPoints scan = scan_in(w.plan.occupancy, truth, 0.02, rng);
    const GlobalLocalizationResult r = loc.localize(scan);
    seconds += r.seconds;
    const bool ok = (r.result.pose.head<2>() - truth.head<2>()).norm() < 0.3 &&
                    std::abs(wrap_angle(r.result.pose[2] - truth[2])) < 0.1;
    if (r.result.status == LocalizationStatus::kConverged) {
      ++accepted;
      EXPECT_TRUE(ok) << "wrong pose accepted at trial " << t;
    }
    right += ok ? 1 : 0;
  }
  std::printf("floor plan: %d/%d right, %d accepted, %.3f s per scan\n", right, trials, accepted,
              seconds / trials);
  EXPECT_GE(accepted, trials - 2);
}

TEST(GlobalLocalization, BetterThanAPoseFindsTheTruthOnlyWhenThePoseIsWrong) {
  const auto& w = test::world();
  const GlobalLocalizer loc(w.map, w.plan.occupancy);
  std::mt19937 rng(9);
  for (int t = 0; t < 4; ++t) {
    const Pose2 truth = random_free_pose(w.plan.occupancy, w.map, rng, 0.3);
    const ScanPoints scan = scan_in(w.plan.occupancy, truth, 0.02, rng);
    const GlobalLocalizationResult full = loc.localize(scan);
    // Right (within a cell and a degree): nothing explains the scan clearly better, and the
    // search capped at its score prunes most of what the full one visits.
    const Pose2 near(truth.x() + 0.02, truth.y() - 0.02, truth[2] + 0.01);
    const GlobalLocalizationResult same = loc.localize_better(scan, near, 0.1);
    EXPECT_EQ(same.result.status, LocalizationStatus::kRefused) << t;
    EXPECT_LT(same.nodes, full.nodes) << t;
    // Wrong (another free pose): the truth is found and accepted, as localize() finds it.
    const Pose2 wrong = random_free_pose(w.plan.occupancy, w.map, rng, 0.3);
    if ((wrong.head<2>() - truth.head<2>()).norm() < 2.0) continue;
    const GlobalLocalizationResult better = loc.localize_better(scan, wrong, 0.1);
    if (full.result.status != LocalizationStatus::kConverged) continue;  // an ambiguous place
    ASSERT_EQ(better.result.status, LocalizationStatus::kConverged) << t;
    EXPECT_LT((better.result.pose.head<2>() - truth.head<2>()).norm(), 0.3) << t;
    EXPECT_LT(std::abs(wrap_angle(better.result.pose[2] - truth[2])), 0.1) << t;
  }
  EXPECT_THROW((void)loc.localize_better(ScanPoints{}, Pose2::Zero(), -0.1), ConfigError);
}

TEST(GlobalLocalization, SymmetricRoomIsRefusedAsAmbiguous) {
  const OccupancyGrid<2> g = test::symmetric_room();  // every pose has a twin: ambiguous
  const VdtMap2 map = VdtMap2::build(g);
  const GlobalLocalizer loc(map, g);
  std::mt19937 rng(2);
  const Pose2 truth(1.55, 1.25, 0.4);  // a cell centre
  const GlobalLocalizationResult r = loc.localize(scan_in(g, truth, 0.01, rng));
  EXPECT_EQ(r.result.status, LocalizationStatus::kRefused);
  EXPECT_TRUE(r.ambiguous);
  const Pose2 twin(5.7 - 1.55, 3.7 - 1.25, wrap_angle(0.4 + kPi));
  bool found = false;
  for (const Pose2& a : r.alternatives) {
    found |=
        (a.head<2>() - twin.head<2>()).norm() < 0.2 || (a.head<2>() - truth.head<2>()).norm() < 0.2;
  }
  EXPECT_TRUE(found);
}

TEST(GlobalLocalization, RandomSamplingScoresItsBestSampleAndRefinesIt) {
  const OccupancyGrid<2> grid = small_room();
  const VdtMap2 map = VdtMap2::build(grid);
  const GlobalLocalizer loc(map, grid);
  std::mt19937 rng(3);
  const Pose2 truth = random_free_pose(grid, map, rng, 0.3);
  const ScanPoints scan = scan_in(grid, truth, 0.01, rng);
  const GlobalLocalizationResult bb = loc.localize(scan);
  const GlobalLocalizationResult rs = loc.localize_random(scan, 0.0, 1, 20000);
  EXPECT_EQ(rs.nodes % 64, 0U);
  EXPECT_GE(rs.nodes, 20000U);
  // Sampling never beats the exhaustive optimum on the same leaves.
  EXPECT_GE(rs.best_leaf_score, bb.best_leaf_score - 1e-6);
  if (rs.result.status == LocalizationStatus::kConverged) {
    EXPECT_LT((rs.result.pose.head<2>() - truth.head<2>()).norm(), 0.3);
  }
}

TEST(GlobalLocalization, BadOptionsAndEmptyScans) {
  const OccupancyGrid<2> grid = small_room();
  const VdtMap2 map = VdtMap2::build(grid);
  GlobalLocalizationOptions o;
  o.truncation = 0.0;
  EXPECT_THROW(GlobalLocalizer(map, grid, o), ConfigError);
  o = {};
  o.accept_fraction = 1.5;
  EXPECT_THROW(GlobalLocalizer(map, grid, o), ConfigError);
  const GlobalLocalizer loc(map, grid);
  EXPECT_EQ(loc.localize(ScanPoints{}).result.status, LocalizationStatus::kTooFewObservations);
  EXPECT_THROW((void)loc.start(ScanPoints{}, nullptr, 0.0, -1), ConfigError);
}

TEST(GlobalLocalization, AnAnytimeSearchSpreadOverStepsFindsWhatOneRunFinds) {
  // One thread: a whole run's batches (threads) score a few more boxes than steps do
  // (TheSameResultForAnyThreadCount covers the threads).
  const test::ThreadCount one_thread(1);
  const auto& w = test::world();
  const GlobalLocalizer loc(w.map, w.plan.occupancy);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const Pose2 truth = random_free_pose(w.plan.occupancy, w.map, rng, 0.4);
    const ScanPoints scan = scan_in(w.plan.occupancy, truth, 0.01, rng);
    for (int leaf : {0, 2}) {
      GlobalLocalizer::Search once = loc.start(scan, nullptr, 0.0, leaf);
      once.run();
      GlobalLocalizer::Search steps = loc.start(scan, nullptr, 0.0, leaf);
      int calls = 0;
      std::size_t before = 0;
      while (!steps.step(5000)) {
        // A step scores its budget, and at most one expansion (4 children) or the greedy
        // descents between two roots phases past it.
        ASSERT_LE(steps.nodes() - before, 5000U + 16U * 4U * 16U) << calls;
        before = steps.nodes();
        ++calls;
      }
      EXPECT_GT(calls, 3) << "the search must take several steps";
      EXPECT_EQ(steps.nodes(), once.nodes());
      ASSERT_EQ(steps.leaves().size(), once.leaves().size());
      for (std::size_t k = 0; k < once.leaves().size(); ++k) {
        EXPECT_EQ(steps.leaves()[k], once.leaves()[k]) << trial << " " << leaf << " " << k;
      }
      // The truth is among the leaves of the coarser search too (boxes of 4 x 4 cells).
      bool found = false;
      for (const Pose2& l : steps.leaves()) {
        found |= (l.head<2>() - truth.head<2>()).norm() < 0.3 &&
                 std::abs(wrap_angle(l[2] - truth[2])) < 0.1;
      }
      EXPECT_TRUE(found) << trial << " " << leaf;
    }
  }
}

TEST(GlobalLocalization, TheSameResultForAnyThreadCount) {
  // The roots, the greedy descents, the best-first expansions (in batches) and the refinements
  // run on the pool's threads: the leaves, their order and the refined pose are those of one
  // thread, also for a search spread over steps. The boxes a whole run scores may exceed one
  // thread's by two batches' expansions (64 boxes a thread, 4 children each); a search in
  // budgeted steps (a tracker's) scores exactly one thread's.
  const auto& w = test::world();
  const GlobalLocalizer loc(w.map, w.plan.occupancy);
  std::mt19937 rng(21);
  for (int trial = 0; trial < 3; ++trial) {
    const Pose2 truth = random_free_pose(w.plan.occupancy, w.map, rng, 0.4);
    const ScanPoints scan = scan_in(w.plan.occupancy, truth, 0.01, rng);
    const auto search = [&](int t, std::size_t budget) {
      const test::ThreadCount count(t);
      GlobalLocalizer::Search s = loc.start(scan);
      while (!s.step(budget)) {
      }
      return s;
    };
    const auto run = [&](int t) {
      const test::ThreadCount count(t);
      return loc.localize(scan);
    };
    const GlobalLocalizer::Search one = search(1, std::numeric_limits<std::size_t>::max());
    const GlobalLocalizationResult refined = run(1);
    ASSERT_GT(one.nodes(), 1000u);
    ASSERT_FALSE(one.leaves().empty());
    for (const int t : {2, 3}) {
      for (const std::size_t budget :
           {std::numeric_limits<std::size_t>::max(), std::size_t{3000}}) {
        const GlobalLocalizer::Search s = search(t, budget);
        ASSERT_EQ(s.leaves().size(), one.leaves().size()) << trial << ", " << t << " threads";
        for (std::size_t k = 0; k < one.leaves().size(); ++k) {
          EXPECT_EQ(s.leaves()[k], one.leaves()[k]) << trial << ", " << t << " threads, " << k;
        }
        EXPECT_EQ(s.best_leaf_score(), one.best_leaf_score());
        if (budget == 3000) {
          EXPECT_EQ(s.nodes(), one.nodes());  // a budgeted step expands one box at a time
        } else {
          EXPECT_GE(s.nodes(), one.nodes());
          EXPECT_LE(s.nodes(), one.nodes() + 2u * 4u * 64u * static_cast<std::size_t>(t));
        }
      }
      const GlobalLocalizationResult r = run(t);
      EXPECT_EQ(r.best_leaf, refined.best_leaf) << trial << ", " << t << " threads";
      EXPECT_EQ(r.result.status, refined.result.status);
      EXPECT_EQ(r.result.pose, refined.result.pose);
      EXPECT_EQ(r.result.iterations, refined.result.iterations);
      EXPECT_EQ(r.explained, refined.explained);
      EXPECT_EQ(r.ambiguous, refined.ambiguous);
      EXPECT_EQ(r.alternatives, refined.alternatives);
    }
  }
}

TEST(GlobalLocalization, TheOccupancyMayLieOnAnotherGridThanTheMap) {
  // The map sampled on a finer grid with another origin (a map sampled from a fitted surface):
  // the robot is placed where the coarse occupancy is free, looked up at the map's cells.
  const OccupancyGrid<2> coarse = small_room();
  const GridFrame<2> fine_frame(0.05, coarse.frame().origin() + Eigen::Vector2d(0.025, -0.025));
  OccupancyGrid<2> fine(Eigen::Vector2i(119, 101), fine_frame, 0);
  for (int y = 0; y < fine.size().y(); ++y) {
    for (int x = 0; x < fine.size().x(); ++x) {
      const Eigen::Vector2i c = coarse.cell_of(fine.cell_center(Eigen::Vector2i(x, y)));
      if (coarse.contains(c) && coarse(c)) fine(Eigen::Vector2i(x, y)) = 1;
    }
  }
  const VdtMap2 map = VdtMap2::build(fine);
  const GlobalLocalizer loc(map, coarse);
  std::size_t free = 0;
  for (int y = 0; y < fine.size().y(); ++y) {
    for (int x = 0; x < fine.size().x(); ++x) {
      const Eigen::Vector2i c = coarse.cell_of(fine.cell_center(Eigen::Vector2i(x, y)));
      free += coarse.contains(c) && !coarse(c);
    }
  }
  EXPECT_EQ(loc.free_cells(), free);
  std::mt19937 rng(4);
  const Pose2 truth = random_free_pose(coarse, VdtMap2::build(coarse), rng, 0.4);
  const GlobalLocalizationResult r = loc.localize(scan_in(coarse, truth, 0.01, rng));
  ASSERT_NE(r.result.status, LocalizationStatus::kRefused)  // accepted (the refinement may stop
      << r.explained  // at its iteration limit) << (r.ambiguous ? " ambiguous" : "") << " at " <<
                      // r.result.pose.transpose()
      << " truth " << truth.transpose();
  EXPECT_LT((r.result.pose.head<2>() - truth.head<2>()).norm(), 0.3);
  // Unknown cells hold no robot: a knowledge grid that knows only the left half.
  Grid<std::int8_t, 2> cells(coarse.size(), coarse.frame(), -1);
  for (int y = 0; y < coarse.size().y(); ++y) {
    for (int x = 0; x < 30; ++x)
      cells(Eigen::Vector2i(x, y)) = coarse(Eigen::Vector2i(x, y)) ? 100 : 0;
  }
  const GlobalLocalizer half(map, coarse, {}, MapKnowledge(cells));
  EXPECT_LT(half.free_cells(), free * 2 / 3);
  EXPECT_GT(half.free_cells(), free / 3);
}

}  // namespace
}  // namespace vdtnav
