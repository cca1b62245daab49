// Scan agreement (estimation/scan_agreement.hpp): the wall-crossing march against a fine-step
// oracle on the same cells, and every reading's class against an independent classification —
// brute-force distances to the surface cells, exact ray casting through the occupancy grid, and
// the knowledge grid — at right and wrong poses of simulated scans, with part of the map unknown.
// In 3D (no knowledge of free space), each reading against exact ray casting through the
// occupancy of the box room: at the right pose nothing is contradicted; at a wrong one every beam
// that runs a metre into or through a solid is, none whose segment meets no solid is.
#include "vdtnav/estimation/scan_agreement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "cloud_fixture.hpp"
#include "scan_fixture.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool surface_cell(const VdtMap2& map, const Eigen::Vector2i& c) {
  const auto& n = map.nearest_cells();
  return n.contains(c) && n(c) == n.linear_index(c);
}

/// The occupied (surface) cells the segment passes through, by steps of h / 200: the first one
/// entered at all, and the first one whose chord is at least half a cell (its entry and exit).
struct Crossings {
  double first = kInf;
  double long_entry = kInf, long_exit = kInf;
};
Crossings fine_march(const VdtMap2& map, const Eigen::Vector2d& o, const Eigen::Vector2d& u,
                     double from, double to) {
  Crossings c;
  const double h = map.resolution(), dt = h / 200.0;
  Eigen::Vector2i run_cell(-1, -1);
  double run_start = 0.0;
  for (double t = from; t <= to + dt; t += dt) {
    const Eigen::Vector2i cell = map.nearest_cells().cell_of(o + t * u);
    const bool occ = surface_cell(map, cell);
    if (occ && cell != run_cell) {
      run_cell = cell;
      run_start = t;
      c.first = std::min(c.first, t);
    }
    if (!occ || cell != run_cell || t > to) {
      if (run_cell.x() >= 0 && !std::isfinite(c.long_entry) && t - run_start >= 0.5 * h) {
        c.long_entry = run_start;
        c.long_exit = t;
      }
      if (!occ) run_cell = Eigen::Vector2i(-1, -1);
    }
  }
  return c;
}

TEST(ScanAgreement, TheWallCrossingIsFoundAsAFineMarchFindsIt) {
  const auto& w = test::world();
  const double h = w.map.resolution();
  std::mt19937 rng(5);
  const Eigen::Vector2d lo = w.plan.occupancy.frame().origin();
  const Eigen::Vector2d ext = w.plan.occupancy.extent();
  std::uniform_real_distribution<double> ux(lo.x(), lo.x() + ext.x()), uy(lo.y(), lo.y() + ext.y());
  std::uniform_real_distribution<double> ua(-M_PI, M_PI), ul(0.5, 15.0);
  int crossings = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector2d o(ux(rng), uy(rng));
    const double a = ua(rng);
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const double len = ul(rng);
    if (!w.plan.occupancy.contains(w.plan.occupancy.cell_of(o + len * u))) continue;
    const double t = first_occupied_crossing(w.map, o, u, 0.0, len);
    const Crossings c = fine_march(w.map, o, u, 0.0, len);
    // Never before the segment enters an occupied cell, never past the first cell it crosses by
    // half a cell or more; nothing found only when every crossing is a shorter graze.
    if (std::isfinite(t)) {
      ++crossings;
      EXPECT_GE(t, c.first - h / 200.0) << trial;
      EXPECT_LE(t, c.long_exit + 1e-9) << trial;
      EXPECT_TRUE(surface_cell(w.map, w.map.nearest_cells().cell_of(o + t * u))) << trial;
    } else {
      EXPECT_FALSE(std::isfinite(c.long_entry))
          << trial << ": missed a crossing at " << c.long_entry;
    }
  }
  EXPECT_GT(crossings, 1000);
  (void)h;
}

/// The independent classification of one reading (see the file comment); -1 when it lies within
/// 1 cm of the explained distance (either class is right there).
int oracle_class(const VdtMap2& map, const OccupancyGrid<2>& occupied,
                 const Grid<std::int8_t, 2>& cells, const ScanPoints& scan, std::size_t i,
                 const Pose2& x, double explained, double margin) {
  const Eigen::Rotation2Dd rot(x[2]);
  const Eigen::Vector2d e = x.head<2>() + rot * scan.points[i];
  const Eigen::Vector2d u = rot * scan.directions[i];
  const Eigen::Vector2d o = e - scan.ranges[i] * u;
  // Brute force over the surface cells within 4 cells of the endpoint's.
  const Eigen::Vector2i c = occupied.cell_of(e);
  double d = kInf;
  for (int dy = -4; dy <= 4; ++dy) {
    for (int dx = -4; dx <= 4; ++dx) {
      const Eigen::Vector2i n = c + Eigen::Vector2i(dx, dy);
      if (surface_cell(map, n)) d = std::min(d, (e - occupied.cell_center(n)).norm());
    }
  }
  if (surface_cell(map, c)) return 0;  // on a wall
  if (std::abs(d - explained) < 0.01) return -1;
  if (d < explained) return 0;
  const double hit = sim::cast_ray<2>(occupied, o + margin * u, u, scan.ranges[i] - 2.0 * margin,
                                      sim::RaySurface::kCellBoundary);
  if (std::isfinite(hit)) return 1;
  const bool known = cells.contains(c) && cells(c) >= 0;
  return known ? 1 : 2;
}

TEST(ScanAgreement, EveryReadingIsClassedAsAnIndependentClassificationClassesIt) {
  const auto& w = test::world();
  const OccupancyGrid<2>& occ = w.plan.occupancy;
  // The map knows the left 70 % of the building.
  const double x0 = occ.frame().origin().x() + 0.7 * occ.extent().x();
  Grid<std::int8_t, 2> cells(occ.size(), occ.frame(), -1);
  for (std::size_t k = 0; k < occ.num_cells(); ++k) {
    if (occ.cell_center(occ.index_of(static_cast<std::ptrdiff_t>(k))).x() < x0)
      cells[k] = occ[k] ? 100 : 0;
  }
  const MapKnowledge knowledge(cells);
  const VdtSensorModel model(w.map, VdtSensorModelOptions{});
  ScanAgreementOptions o;
  const double margin = 2.0 * o.explained_distance + w.map.resolution();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> off(-1.0, 1.0);
  int compared = 0, disagree = 0;
  ScanAgreement right, wrong;
  for (std::size_t k = 0; k < 24; ++k) {
    const Pose2 truth = test::tour_pose(k);
    const ScanPoints scan = scan_points(test::simulate_scan(truth, 0.01, rng, 361));
    const Pose2 moved = truth + Pose2(0.8 * off(rng), 0.8 * off(rng), 0.4 * off(rng));
    for (const Pose2& x : {truth, moved}) {
      const ScanAgreement a = scan_agreement(model, w.map, knowledge, scan, x, o);
      ASSERT_EQ(a.readings, static_cast<int>(scan.size()));
      ASSERT_EQ(a.explained + a.contradicted + a.unknown, a.readings);
      ScanAgreement expect;
      for (std::size_t i = 0; i < scan.size(); ++i) {
        const int cls = oracle_class(w.map, occ, cells, scan, i, x, o.explained_distance, margin);
        if (cls < 0) continue;
        ++expect.readings;
        (cls == 0 ? expect.explained : cls == 1 ? expect.contradicted : expect.unknown) += 1;
      }
      // Counts, not reading by reading (the oracle skips the borderline ones): equal within 3 %
      // of the readings plus the borderline ones left out.
      const int slack = static_cast<int>(0.03 * a.readings) + (a.readings - expect.readings);
      EXPECT_NEAR(a.explained, expect.explained, slack) << k;
      EXPECT_NEAR(a.contradicted, expect.contradicted, slack) << k;
      EXPECT_NEAR(a.unknown, expect.unknown, slack) << k;
      compared += expect.readings;
      disagree += std::abs(a.contradicted - expect.contradicted);
      (x == truth ? right : wrong) += a;
    }
  }
  EXPECT_LT(disagree, 0.03 * compared);
  // What lost detection relies on: right poses are not contradicted, wrong ones are.
  EXPECT_LT(right.contradiction(), 0.03);
  EXPECT_GT(wrong.contradiction(), 0.5);
  EXPECT_GT(right.unknown + wrong.unknown, 100) << "the unknown part must be seen";
}

TEST(ScanAgreement3, ABeamThroughASolidIsContradictedAndOneThatMeetsNoneNever) {
  const test::World3& w = test::world3();
  const VdtSensorModel3 model(w.map);
  std::mt19937 rng(3);
  const Pose3 right = test::cloud_pose(0);
  const ObservationSet3 scan = test::simulate_cloud(right, 0.0, rng, test::Keep::kExact);
  ASSERT_GT(scan.size(), 3000u);
  ScanAgreementOptions o;  // 0.1 m explained; margin 2 x 0.1 + 0.05
  const ScanAgreement at_right = scan_agreement(model, scan, right, o);
  EXPECT_EQ(at_right.readings, static_cast<int>(scan.size()));
  EXPECT_EQ(at_right.contradicted, 0);
  EXPECT_GE(at_right.explained_fraction(), 0.99);

  // 1.3 m along x and turned 0.4 rad: the readings put where the beams would run into the walls,
  // the furniture, or into the room's open space. The oracle: where the beam, cast exactly
  // through the occupancy from the wrong pose, first enters a solid (r_hit).
  const Pose3 wrong = pose3_from_xyz_rpy(4.4, 2.9, 0.03, 0.04, -0.03, 0.75);
  o.max_readings = 0;
  int through = 0, clear = 0, through_found = 0, clear_contradicted = 0;
  ScanAgreement sum;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    ObservationSet3 one = scan.subsampled(scan.size());  // reading 0 only: re-filled below
    one.points = {scan.points[i]};
    one.directions = {scan.directions[i]};
    one.ranges = {scan.ranges[i]};
    one.beam = {scan.beam[i]};
    const ScanAgreement a = scan_agreement(model, one, wrong, o);
    sum += a;
    if (a.explained == 1) continue;
    const Eigen::Vector3d u = wrong.linear() * scan.directions[i];
    const Eigen::Vector3d origin = wrong * scan.points[i] - scan.ranges[i] * u;
    const auto hit = [&](const Eigen::Vector3d& o) {
      return sim::cast_ray<3>(w.occupancy, o, u, 60.0, sim::RaySurface::kCellBoundary);
    };
    // Two directions across the beam, for the beams parallel to it 1.5 voxels away.
    const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    const Eigen::Vector3d across[4] = {e1, -e1, e2, -e2};
    const double h = w.map.resolution();
    double nearby = hit(origin);
    for (const Eigen::Vector3d& e : across) nearby = std::min(nearby, hit(origin + 1.5 * h * e));
    if (hit(origin) + 1.0 < scan.ranges[i] && hit(origin) > 0.3) {  // a metre into or through
      ++through;
      through_found += a.contradicted;
    } else if (!(nearby < scan.ranges[i] + 0.1)) {  // neither it nor the beams beside it meet one
      ++clear;
      clear_contradicted += a.contradicted;
    }
  }
  std::printf(
      "wrong pose: %d readings, %d explained, %d contradicted, %d unknown; %d through a "
      "solid (%d contradicted), %d meeting none (%d contradicted)\n",
      sum.readings, sum.explained, sum.contradicted, sum.unknown, through, through_found, clear,
      clear_contradicted);
  EXPECT_GT(through, 300) << "the wrong pose must put beams through solids";
  EXPECT_GT(clear, 50) << "and some into open space";
  EXPECT_EQ(through_found, through);
  EXPECT_EQ(clear_contradicted, 0);
  EXPECT_GE(sum.contradicted, through);  // and no more than the readings not explained
  EXPECT_LE(sum.contradicted, sum.readings - sum.explained - clear);
  // The whole scan at once classifies as the readings one by one.
  const ScanAgreement whole = scan_agreement(model, scan, wrong, o);
  EXPECT_EQ(whole.explained, sum.explained);
  EXPECT_EQ(whole.contradicted, sum.contradicted);
  EXPECT_EQ(whole.unknown, sum.unknown);
}

TEST(ScanAgreement3, ABeamGrazingTheFloorAndEndingJustUnderItIsNotAPassage) {
  // A reading of the floor at 5 degrees of incidence whose endpoint lies 0.1 m under the floor's
  // surface (its range 1.15 m past the floor): near the floor for a metre, never out the other
  // side. The same beam continued 3 m past the floor runs 0.26 m deep into the floor's solid:
  // a passage, from where it came within a voxel of the floor's surface voxels.
  const test::World3& w = test::world3();
  const Eigen::Vector3d origin(0.5, 2.0, 0.3);
  const double incidence = 5.0 * kPi / 180.0;
  const Eigen::Vector3d u(std::cos(incidence), 0.0, -std::sin(incidence));
  const double to_floor = origin.z() / std::sin(incidence);  // 3.44 m
  const double h = w.map.resolution(), out = 2.0 * 0.1;
  const double range = to_floor + 0.1 / std::sin(incidence);
  EXPECT_TRUE(std::isinf(first_surface_crossing(w.map, origin, u, 0.25, range - 0.25, out)));
  EXPECT_NEAR(first_surface_crossing(w.map, origin, u, 0.25, to_floor + 3.0, out),
              to_floor - h / std::sin(incidence), 0.5 * h / std::sin(incidence) + h);
}

TEST(ScanAgreement, MaxReadingsAndBadOptions) {
  const auto& w = test::world();
  const VdtSensorModel model(w.map, VdtSensorModelOptions{});
  std::mt19937 rng(1);
  const ScanPoints scan = scan_points(test::simulate_scan(test::tour_pose(3), 0.01, rng, 361));
  ScanAgreementOptions o;
  o.max_readings = 50;
  EXPECT_EQ(scan_agreement(model, w.map, MapKnowledge{}, scan, test::tour_pose(3), o).readings, 50);
  EXPECT_EQ(scan_agreement(model, w.map, MapKnowledge{}, ScanPoints{}, test::tour_pose(3)).readings,
            0);
  o = {};
  o.explained_distance = 0.0;
  EXPECT_THROW(o.validate(), ConfigError);
  o = {};
  o.max_readings = -1;
  EXPECT_THROW(o.validate(), ConfigError);
}

}  // namespace
}  // namespace vdtnav
