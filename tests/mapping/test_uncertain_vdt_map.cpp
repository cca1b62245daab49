// Uncertain VDT maps (thesis ch. 5) on Experiment 1's L-shaped room: a fit to noise-free scans
// reproduces the room's exact VDT to the spline's approximation error (Fig. 5.2), the covariance
// holds against Monte Carlo over noisy map-building runs (Table 5.1's noise), the queries agree
// with each other, and bad input is refused.
#include "vdtnav/mapping/uncertain_vdt_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sim/mapping_run.hpp"

namespace vdtnav::mapping {
namespace {

sim::LidarOptions lidar_180() {
  sim::LidarOptions l;
  l.fov = kPi;
  l.angular_resolution = 0.5 * kPi / 180.0;
  l.range_max = 10.0;
  return l;
}

/// The room, its exact VDT and its wall cells (the true boundary).
struct Room {
  sim::MappingScene scene = sim::l_shaped_room(0.01);
  VdtMap2 vdt = VdtMap2::build(scene.world);
  std::vector<Eigen::Vector2d> walls;
  Room() {
    for (int y = 0; y < scene.world.size().y(); ++y) {
      for (int x = 0; x < scene.world.size().x(); ++x) {
        if (scene.world(Eigen::Vector2i(x, y))) {
          walls.push_back(scene.world.cell_center(Eigen::Vector2i(x, y)));
        }
      }
    }
  }
  [[nodiscard]] Eigen::Vector2d truth(const Eigen::Vector2d& p) const {
    return p - vdt.nearest_occupied_point(p);
  }
};

const Room& room() {
  static const Room r;
  return r;
}

/// rms of |DT_v| at the true boundary points the map covers.
double boundary_rms(const UncertainVdtMap& map, const std::vector<Eigen::Vector2d>& truth,
                    int* covered = nullptr) {
  double ss = 0.0;
  int n = 0;
  for (const auto& p : truth) {
    const UncertainMapSample s = map.evaluate(p);
    if (!s.inside) continue;
    ss += s.value.squaredNorm();
    ++n;
  }
  if (covered != nullptr) *covered = n;
  return n > 0 ? std::sqrt(ss / n) : std::nan("");
}

TEST(UncertainVdtMap, NoiseFreeFitReproducesTheExactVdtToTheApproximationError) {
  const Room& r = room();
  const sim::MappingRun run =
      sim::simulate_mapping_run(r.scene.world, r.scene.poses, lidar_180(), sim::MappingNoise{}, 1);
  UncertainMapOptions o;
  o.spacing = 0.2;
  const UncertainVdtMap fit = UncertainVdtMap::fit(run.scans, o);
  ASSERT_TRUE(fit.summary().converged) << fit.summary().message;
  // Fig. 5.2's least-squares approximation of the exact VDT at the same spacing: the floor.
  const UncertainVdtMap ls = UncertainVdtMap::approximate(
      r.walls, [&](const Eigen::Vector2d& p) { return r.truth(p); }, o);
  int covered = 0;
  const double fit_rms = boundary_rms(fit, run.true_boundary, &covered);
  const double ls_rms = boundary_rms(ls, run.true_boundary);
  EXPECT_GT(covered, static_cast<int>(run.true_boundary.size()) * 9 / 10);
  std::printf("noise-free fit: rms %.4f m at the true boundary, least squares %.4f m\n", fit_rms,
              ls_rms);
  EXPECT_LT(fit_rms, 2.0 * ls_rms + 0.002);
  // Off the boundary, across the band, away from the room's cut loci (the corners' bisectors,
  // where the spline smooths over the jump of the nearest wall): DT_v itself.
  double ss = 0.0;
  int n = 0;
  for (double x = 0.9; x < 4.6; x += 0.061) {
    for (const double y : {0.2, 0.45, 5.55, 5.8}) {
      const Eigen::Vector2d p(x, y);
      if (x > 2.1 && (x < 3.4 || y > 3.0)) continue;
      const UncertainMapSample s = fit.evaluate(p);
      if (!s.inside) continue;
      ss += (s.value - r.truth(p)).squaredNorm();
      ++n;
    }
  }
  ASSERT_GT(n, 40);
  std::printf("off the boundary: rms %.4f m over %d points\n", std::sqrt(ss / n), n);
  EXPECT_LT(std::sqrt(ss / n), 0.01);
}

TEST(UncertainVdtMap, CovarianceHoldsAgainstMonteCarloOverNoisyMapBuildingRuns) {
  const Room& r = room();
  UncertainMapOptions o;
  o.spacing = 0.2;
  int within = 0, total = 0;
  double sum_z2 = 0.0;
  for (std::uint32_t seed = 0; seed < 10; ++seed) {
    const sim::MappingRun run = sim::simulate_mapping_run(
        r.scene.world, r.scene.poses, lidar_180(), sim::MappingNoise::table_5_1(), 100 + seed);
    const UncertainVdtMap map = UncertainVdtMap::fit(run.scans, o);
    ASSERT_TRUE(map.summary().covariance_ok) << map.summary().message;
    for (std::size_t k = 0; k < run.true_boundary.size(); k += 4) {
      const UncertainMapSample s = map.evaluate(run.true_boundary[k]);
      if (!s.inside) continue;
      // The error along the wall's normal (the true field's gradient direction).
      const Eigen::Vector2d q = run.true_boundary[k];
      const Eigen::Vector2d off = r.truth(q + Eigen::Vector2d(0.03, 0.0)).norm() > 0.02
                                      ? Eigen::Vector2d(1.0, 0.0)
                                      : Eigen::Vector2d(0.0, 1.0);
      const double e = off.dot(s.value), sigma = std::sqrt(off.dot(s.covariance * off));
      within += std::abs(e) <= 2.0 * sigma ? 1 : 0;
      sum_z2 += (e / sigma) * (e / sigma);
      ++total;
    }
  }
  ASSERT_GT(total, 1000);
  const double pct = 100.0 * within / total, mean_z2 = sum_z2 / total;
  std::printf("Monte Carlo over 10 runs: %.1f %% within 2 sigma, mean (e / sigma)^2 %.2f\n", pct,
              mean_z2);
  EXPECT_GE(pct, 92.0);     // the issue asks 95 % (measured 97-98 %)
  EXPECT_GT(mean_z2, 0.3);  // and not uselessly conservative
  EXPECT_LT(mean_z2, 1.5);
}

TEST(UncertainVdtMap, PropagateOfOnePointIsItsCovarianceAndSkipsPointsOutside) {
  const Room& r = room();
  const sim::MappingRun run = sim::simulate_mapping_run(r.scene.world, r.scene.poses, lidar_180(),
                                                        sim::MappingNoise::table_5_1(), 7);
  UncertainMapOptions o;
  o.spacing = 0.2;
  const UncertainVdtMap map = UncertainVdtMap::fit(run.scans, o);
  MapUncertainty2::Sensitivity s;
  s << 1.0, 0.5, -0.3, 2.0, 0.7, -1.1;
  int checked = 0;
  for (std::size_t k = 0; k < run.true_boundary.size(); k += 37) {
    const Eigen::Vector2d q = run.true_boundary[k];
    Eigen::Matrix2d c;
    const bool inside = map.dt_covariance(q, &c);
    std::vector<char> known;
    const Eigen::Matrix3d p = map.propagate({q, Eigen::Vector2d(50.0, 50.0)}, {s, s}, &known);
    ASSERT_EQ(known.size(), 2u);
    EXPECT_EQ(known[0] != 0, inside);
    EXPECT_FALSE(known[1]);
    if (!inside) continue;  // a cell the map left out (no residual, or a cut locus)
    // dt_covariance reads the cell's quadratic forms, propagate Z's blocks and Y's rows (both
    // stored as floats): they agree to float rounding.
    const Eigen::Matrix3d expected = s * c * s.transpose();
    EXPECT_LT((p - expected).norm(), 1e-5 * expected.norm()) << k;
    ++checked;
  }
  EXPECT_GT(checked, 20);
  // Two points of one wall a metre apart share the scans' pose errors: correlated.
  const Eigen::Vector2d a(0.0, 1.5), b(0.0, 2.5);
  MapUncertainty2::Sensitivity ex = MapUncertainty2::Sensitivity::Zero();
  ex(0, 0) = 1.0;  // the x component
  Eigen::Matrix2d ca, cb;
  ASSERT_TRUE(map.dt_covariance(a, &ca) && map.dt_covariance(b, &cb));
  const double var_sum = map.propagate({a, b}, {ex, ex}, nullptr)(0, 0);
  const double independent = ca(0, 0) + cb(0, 0);
  EXPECT_GT(var_sum, 1.2 * independent);          // positively correlated
  EXPECT_LT(var_sum, 2.0 * independent + 1e-12);  // |rho| <= 1
}

// Free space: readings in the middle of the room in one scan (a post that was moved) that the
// other scans' beams pass through are dropped, and the field stays off zero there; without the
// free-space term it becomes a wall.
TEST(UncertainVdtMap, BeamsThatPassThroughAReadingClearIt) {
  const Room& r = room();
  // Three runs of the room's three poses: nine scans.
  sim::MappingRun run = sim::simulate_mapping_run(r.scene.world, r.scene.poses, lidar_180(),
                                                  sim::MappingNoise::table_5_1(), 5);
  for (const std::uint32_t seed : {6u, 7u}) {
    const sim::MappingRun more = sim::simulate_mapping_run(
        r.scene.world, r.scene.poses, lidar_180(), sim::MappingNoise::table_5_1(), seed);
    run.scans.insert(run.scans.end(), more.scans.begin(), more.scans.end());
  }
  // A thin post of 2 readings, in scan 0, where the other scans' beams pass.
  MapScan& s0 = run.scans[0];
  const Eigen::Vector2d ghost_world(1.0, 1.0);
  ASSERT_GT(r.truth(ghost_world).norm(), 0.5);
  const Eigen::Vector2d ghost = Eigen::Rotation2Dd(-s0.pose[2]) * (ghost_world - s0.pose.head<2>());
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d p = ghost + Eigen::Vector2d(0.0, 0.01 * k);
    s0.points.add(Eigen::Vector2d::Zero(), p.normalized(), p.norm(), s0.points.size());
  }
  UncertainMapOptions o;
  o.spacing = 0.2;
  o.compute_covariance = false;
  const UncertainVdtMap with = UncertainVdtMap::fit(run.scans, o);
  o.free_space = false;
  const UncertainVdtMap without = UncertainVdtMap::fit(run.scans, o);
  EXPECT_GE(with.summary().cleared_readings, 2);
  EXPECT_LT(with.summary().cleared_readings, 0.02 * with.summary().boundary_points);
  EXPECT_EQ(without.summary().cleared_readings, 0);
  const UncertainMapSample a = with.evaluate(ghost_world), b = without.evaluate(ghost_world);
  ASSERT_TRUE(b.inside);
  EXPECT_LT(b.value.norm(), 0.05);  // without: a wall where the post stood
  // With: the post is gone (the map is not defined there, or far from zero).
  if (a.inside) {
    EXPECT_GT(a.value.norm(), 0.3);
  }
}

// spacing_from_data: five times the median gap between consecutive readings, within [0.2, 0.5].
TEST(UncertainVdtMap, SpacingFromTheReadingsGaps) {
  const auto scan_with_gap = [](double gap, int n) {
    MapScan s;
    s.points.sigma_range = 0.02;
    for (int k = 0; k < n; ++k)
      s.points.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), 1.0 + gap * k, k);
    return s;
  };
  EXPECT_DOUBLE_EQ(spacing_from_data({scan_with_gap(0.06, 50)}), 0.3);
  EXPECT_DOUBLE_EQ(spacing_from_data({scan_with_gap(0.01, 50)}), 0.2);  // held at 0.2
  EXPECT_DOUBLE_EQ(spacing_from_data({scan_with_gap(0.09, 50)}), 0.45);
  EXPECT_DOUBLE_EQ(spacing_from_data({scan_with_gap(0.6, 50)}), 0.25);  // no gap under 0.5 m
}

TEST(UncertainVdtMap, RefusesBadInputAndDropsNonFiniteReadings) {
  UncertainMapOptions o;
  EXPECT_THROW((void)UncertainVdtMap::fit({}, o), ConfigError);
  MapScan s;
  s.points.sigma_range = 0.02;
  s.points.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(1.0, 0.0), 2.0, 0);
  UncertainMapOptions bad = o;
  bad.spacing = std::nan("");
  EXPECT_THROW((void)UncertainVdtMap::fit({s}, bad), ConfigError);
  bad = o;
  bad.eikonal_sigma = 0.0;
  EXPECT_THROW((void)UncertainVdtMap::fit({s}, bad), ConfigError);
  MapScan nan_pose = s;
  nan_pose.pose[0] = std::nan("");
  EXPECT_THROW((void)UncertainVdtMap::fit({nan_pose}, o), ConfigError);
  // A NaN reading is dropped, the others fitted.
  const Room& r = room();
  sim::MappingRun run = sim::simulate_mapping_run(r.scene.world, r.scene.poses, lidar_180(),
                                                  sim::MappingNoise::table_5_1(), 3);
  const std::size_t n = run.scans[0].points.size();
  run.scans[0].points.points[n / 2] = Eigen::Vector2d(std::nan(""), 0.0);
  const UncertainVdtMap map = UncertainVdtMap::fit(run.scans, o);
  EXPECT_TRUE(map.summary().covariance_ok);
  for (const auto& p : map.observed_points()) EXPECT_TRUE(p.allFinite());
}

}  // namespace
}  // namespace vdtnav::mapping
