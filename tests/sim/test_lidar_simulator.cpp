// The simulated Dataset 1: scans are the exact ray cast plus the configured range noise, odometry
// is the true motion plus the configured velocity noise integrated on exact arcs, and the whole
// run is reproducible per seed.
#include "vdtnav/sim/lidar_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"
#include "vdtnav/sim/route_planner.hpp"

namespace vdtnav::sim {
namespace {

/// A planned tour on the generated floor plan and the first `n` samples of its trajectory.
struct Fixture {
  FloorPlan plan;
  std::vector<Eigen::Vector2d> path;
  std::vector<TimedPose> trajectory;

  explicit Fixture(std::size_t n) {
    // Planned and driven once per test program.
    static const Fixture full = [] {
      Fixture f;
      f.plan = generate_floor_plan({});
      f.path = plan_tour(f.plan.occupancy, 6, 0.4, 3);
      f.trajectory = follow_path(f.path, f.plan.occupancy, {});
      return f;
    }();
    *this = full;
    trajectory.resize(std::min(n, trajectory.size()));
  }

 private:
  Fixture() = default;
};

/// A one-beam LiDAR, for tests about odometry only (the odometry noise ignores the beams).
LidarOptions one_beam() {
  LidarOptions lidar;
  lidar.fov = lidar.angular_resolution / 2;
  return lidar;
}

/// Sample mean and standard deviation.
std::pair<double, double> mean_std(const std::vector<double>& x) {
  double m = 0.0;
  for (double v : x) m += v;
  m /= static_cast<double>(x.size());
  double s = 0.0;
  for (double v : x) s += (v - m) * (v - m);
  return {m, std::sqrt(s / static_cast<double>(x.size() - 1))};
}

TEST(LidarOptions, DefaultsAreTheUtm30lxOfTable31) {
  const LidarOptions o;
  EXPECT_EQ(o.num_beams(), 1081);
  EXPECT_DOUBLE_EQ(o.fov, 1.5 * kPi);
  EXPECT_DOUBLE_EQ(o.angular_resolution, 0.25 * kPi / 180.0);
  EXPECT_EQ(o.range_min, 0.1);
  EXPECT_EQ(o.range_max, 30.0);
  EXPECT_EQ(o.sigma_range, 0.02);
  const NoiseProfile s = NoiseProfile::table_3_2_sigma(), v = NoiseProfile::table_3_2_variance();
  EXPECT_EQ(s.sigma_range, 0.02);
  EXPECT_EQ(s.sigma_v, 0.05);
  EXPECT_EQ(s.sigma_w, 0.01);
  EXPECT_DOUBLE_EQ(v.sigma_range * v.sigma_range, 0.02);
  EXPECT_DOUBLE_EQ(v.sigma_v * v.sigma_v, 0.05);
  EXPECT_DOUBLE_EQ(v.sigma_w * v.sigma_w, 0.01);
}

TEST(SimulateRun, NoiseFreeScansAreTheRayCastAndEndOnOccupiedCellBoundaries) {
  const Fixture f(10);
  const auto& occ = f.plan.occupancy;
  LidarOptions lidar;
  lidar.surface = RaySurface::kCellBoundary;  // this test checks the solid-cell surface
  lidar.mount = Pose2(0.12, -0.04, 0.3);      // off-centre and rotated
  const SimulatedRun run = simulate_run(occ, f.trajectory, lidar, NoiseProfile::none(), 1);
  ASSERT_EQ(run.size(), f.trajectory.size());
  ASSERT_EQ(run.scans.size(), run.size());
  const double res = occ.resolution();
  std::size_t hits = 0;
  for (std::size_t k = 0; k < run.size(); ++k) {
    const LaserScan& scan = run.scans[k];
    EXPECT_EQ(scan.time, f.trajectory[k].t);
    EXPECT_EQ(run.times[k], f.trajectory[k].t);
    EXPECT_EQ(run.truth[k], f.trajectory[k].pose);
    ASSERT_EQ(scan.ranges.size(), 1081u);
    EXPECT_DOUBLE_EQ(scan.angle_min, -0.75 * kPi);
    EXPECT_DOUBLE_EQ(scan.angle(1080), 0.75 * kPi);
    EXPECT_EQ(scan.mount, lidar.mount);
    EXPECT_EQ(scan.sigma_range, lidar.sigma_range);  // noise-free: the nominal sigma is declared
    const Pose2 sensor = compose(run.truth[k], lidar.mount);
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      const double a = sensor[2] + scan.angle(i);
      const Eigen::Vector2d d(std::cos(a), std::sin(a));
      const double expected = cast_ray<2>(occ, sensor.head<2>(), d, lidar.range_max, lidar.surface);
      if (std::isinf(expected)) {  // along the 40 m corridor
        ASSERT_TRUE(std::isinf(scan.ranges[i]) && scan.ranges[i] > 0) << k << " " << i;
        continue;
      }
      ASSERT_NEAR(scan.ranges[i], expected, 1e-9) << "scan " << k << " beam " << i;
      // Independent of the ray caster: the endpoint lies on a cell boundary, with a free cell
      // just before it and an occupied one just after.
      const Eigen::Vector2d p = sensor.head<2>() + scan.ranges[i] * d;
      const Eigen::Vector2d u = (p - occ.frame().origin()) / res;
      const double off =
          std::min(std::abs(u.x() - std::round(u.x())), std::abs(u.y() - std::round(u.y())));
      ASSERT_LT(off, 1e-6) << "scan " << k << " beam " << i;
      ASSERT_TRUE(occ(occ.cell_of(p + 1e-6 * d))) << "scan " << k << " beam " << i;
      ASSERT_FALSE(occ(occ.cell_of(p - 1e-6 * d))) << "scan " << k << " beam " << i;
      ++hits;
    }
  }
  EXPECT_GT(hits, 8u * 1081u);
}

TEST(SimulateRun, DefaultThinWallEndpointsLieOnTheZeroSetOfTheMapsVdt) {
  const Fixture f(20);
  const VdtMap2 map = VdtMap2::build(f.plan.occupancy);
  const SimulatedRun run =
      simulate_run(f.plan.occupancy, f.trajectory, LidarOptions{}, NoiseProfile::none(), 1);
  std::vector<double> d;
  for (std::size_t k = 0; k < run.size(); k += 5) {
    const ScanPoints pts = scan_points(run.scans[k]);
    for (std::size_t i = 0; i < pts.size(); ++i)
      d.push_back(map.evaluate(transform_point(run.truth[k], pts.points[i])).value.norm());
  }
  ASSERT_GT(d.size(), 1000u);
  std::sort(d.begin(), d.end());
  EXPECT_LT(d[d.size() / 2], 1e-5);         // median: on the surface
  EXPECT_LT(d[d.size() * 95 / 100], 5e-3);  // 95 %: within 5 mm (corners, staircases)
}

TEST(SimulateRun, BeamsThatHitNothingWithinRangeMaxReadInfinity) {
  const Fixture f(8);
  LidarOptions lidar;
  lidar.range_max = 2.0;
  const SimulatedRun run =
      simulate_run(f.plan.occupancy, f.trajectory, lidar, NoiseProfile::table_3_2_sigma(), 4);
  std::size_t misses = 0, hits = 0;
  for (std::size_t k = 0; k < run.size(); ++k) {
    const Pose2& pose = run.truth[k];
    for (std::size_t i = 0; i < run.scans[k].ranges.size(); ++i) {
      const double a = pose[2] + run.scans[k].angle(i);
      const double exact =
          cast_ray<2>(f.plan.occupancy, pose.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)),
                      1e9, LidarOptions{}.surface);
      const double r = run.scans[k].ranges[i];
      if (exact >= 2.0) {
        ASSERT_TRUE(std::isinf(r) && r > 0) << k << " " << i;
        ++misses;
      } else {
        ASSERT_TRUE(std::isfinite(r)) << k << " " << i;
        ASSERT_GE(r, 0.0);
        ++hits;
      }
    }
  }
  EXPECT_GT(misses, 1000u);
  EXPECT_GT(hits, 1000u);
}

TEST(SimulateRun, RangeNoiseHasTheConfiguredStandardDeviation) {
  const Fixture f(200);
  ASSERT_EQ(f.trajectory.size(), 200u);
  const auto& occ = f.plan.occupancy;
  const SimulatedRun exact = simulate_run(occ, f.trajectory, {}, NoiseProfile::none(), 9);
  // The default profile over 200 scans; the variance reading over the first 20.
  for (const auto& [noise, scans] : {std::pair{NoiseProfile::table_3_2_sigma(), 200u},
                                     std::pair{NoiseProfile::table_3_2_variance(), 20u}}) {
    SCOPED_TRACE("sigma_range " + std::to_string(noise.sigma_range));
    const std::vector<TimedPose> part(f.trajectory.begin(), f.trajectory.begin() + scans);
    const SimulatedRun noisy = simulate_run(occ, part, {}, noise, 9);
    std::vector<double> err;
    for (std::size_t k = 0; k < noisy.size(); ++k) {
      EXPECT_EQ(noisy.scans[k].sigma_range, noise.sigma_range);
      for (std::size_t i = 0; i < noisy.scans[k].ranges.size(); ++i) {
        const double r0 = exact.scans[k].ranges[i];
        if (std::isinf(r0)) {
          ASSERT_TRUE(std::isinf(noisy.scans[k].ranges[i]));
          continue;
        }
        if (r0 < 5 * noise.sigma_range) continue;  // keep clear of the clamp at 0
        err.push_back(noisy.scans[k].ranges[i] - r0);
      }
    }
    ASSERT_GT(err.size(), scans * 900u);
    const auto [mean, std] = mean_std(err);
    EXPECT_NEAR(std, noise.sigma_range, 0.05 * noise.sigma_range);
    EXPECT_LT(std::abs(mean), 4 * noise.sigma_range / std::sqrt(err.size()));
  }
  // The other seed draws other noise.
  const std::vector<TimedPose> few(f.trajectory.begin(), f.trajectory.begin() + 3);
  const SimulatedRun a = simulate_run(occ, few, {}, NoiseProfile::table_3_2_sigma(), 9);
  const SimulatedRun b = simulate_run(occ, few, {}, NoiseProfile::table_3_2_sigma(), 10);
  EXPECT_NE(a.scans[2].ranges, b.scans[2].ranges);
}

TEST(SimulateRun, NoiseFreeOdometryComposesToTheTrueTrajectory) {
  const Fixture f(100000);  // the whole tour
  ASSERT_GT(f.trajectory.size(), 5000u);
  const SimulatedRun run =
      simulate_run(f.plan.occupancy, f.trajectory, one_beam(), NoiseProfile::none(), 2);
  EXPECT_EQ(run.odometry[0].dt, 0.0);
  EXPECT_EQ(run.odometry[0].v, 0.0);
  EXPECT_EQ(run.odometry[0].w, 0.0);
  EXPECT_EQ(run.odometry[0].delta, Pose2::Zero());
  Pose2 dead_reckoning = run.truth[0];
  double worst = 0.0;
  for (std::size_t k = 1; k < run.size(); ++k) {
    ASSERT_EQ(run.odometry[k].v, f.trajectory[k].v);
    ASSERT_EQ(run.odometry[k].w, f.trajectory[k].w);
    ASSERT_NEAR(run.odometry[k].dt, 1.0 / 40.0, 1e-12);
    dead_reckoning = compose(dead_reckoning, run.odometry[k].delta);
    worst = std::max(worst, pose_error(dead_reckoning, run.truth[k]).norm());
    // Each increment alone, too (independent of accumulation).
    ASSERT_LT(pose_error(compose(run.truth[k - 1], run.odometry[k].delta), run.truth[k]).norm(),
              1e-12);
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(SimulateRun, OdometryNoiseHasTheConfiguredStandardDeviationAndDrifts) {
  const Fixture f(100000);
  ASSERT_GT(f.trajectory.size(), 5000u);
  for (const NoiseProfile& noise :
       {NoiseProfile::table_3_2_sigma(), NoiseProfile::table_3_2_variance()}) {
    SCOPED_TRACE("sigma_v " + std::to_string(noise.sigma_v));
    const SimulatedRun run = simulate_run(f.plan.occupancy, f.trajectory, one_beam(), noise, 5);
    ASSERT_EQ(run.scans[0].ranges.size(), 1u);
    std::vector<double> ev, ew;
    Pose2 dead_reckoning = run.truth[0];
    for (std::size_t k = 1; k < run.size(); ++k) {
      const OdometryStep& o = run.odometry[k];
      ev.push_back(o.v - f.trajectory[k].v);
      ew.push_back(o.w - f.trajectory[k].w);
      // The increment is the exact arc of the *measured* velocities.
      ASSERT_LT(pose_error(o.delta, unicycle_increment(o.v, o.w, o.dt)).norm(), 1e-15);
      dead_reckoning = compose(dead_reckoning, o.delta);
    }
    const auto [mv, sv] = mean_std(ev);
    const auto [mw, sw] = mean_std(ew);
    EXPECT_NEAR(sv, noise.sigma_v, 0.05 * noise.sigma_v);
    EXPECT_NEAR(sw, noise.sigma_w, 0.05 * noise.sigma_w);
    EXPECT_LT(std::abs(mv), 4 * noise.sigma_v / std::sqrt(ev.size()));
    EXPECT_LT(std::abs(mw), 4 * noise.sigma_w / std::sqrt(ew.size()));
    // Dead reckoning drifts away from the truth (like wheel odometry).
    EXPECT_GT(pose_error(dead_reckoning, run.truth.back()).head<2>().norm(), 0.05);
  }
}

TEST(SimulateRun, SameSeedSameRunAndTheSameDrawsForEveryProfile) {
  const Fixture f(8);
  const auto& occ = f.plan.occupancy;
  const auto a = simulate_run(occ, f.trajectory, {}, NoiseProfile::table_3_2_sigma(), 77);
  const auto b = simulate_run(occ, f.trajectory, {}, NoiseProfile::table_3_2_sigma(), 77);
  const auto c = simulate_run(occ, f.trajectory, {}, NoiseProfile::table_3_2_variance(), 77);
  const auto z = simulate_run(occ, f.trajectory, {}, NoiseProfile::none(), 77);
  const double ratio = std::sqrt(0.02) / 0.02;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.scans[k].ranges, b.scans[k].ranges);
    ASSERT_EQ(a.odometry[k].delta, b.odometry[k].delta);
    // Common random numbers: the variance profile's noise is the sigma profile's, scaled.
    for (std::size_t i = 0; i < a.scans[k].ranges.size(); i += 7) {
      const double r0 = z.scans[k].ranges[i];
      if (r0 < 1.0 || std::isinf(r0)) continue;
      ASSERT_NEAR(c.scans[k].ranges[i] - r0, ratio * (a.scans[k].ranges[i] - r0), 1e-9);
    }
  }
}

TEST(SimulateRun, InvalidInputThrowsConfigError) {
  const Fixture f(5);
  const auto& occ = f.plan.occupancy;
  LidarOptions lidar;
  lidar.angular_resolution = 0.0;
  EXPECT_THROW((void)simulate_run(occ, f.trajectory, lidar, {}, 1), ConfigError);
  lidar = {};
  lidar.range_max = lidar.range_min;
  EXPECT_THROW((void)simulate_run(occ, f.trajectory, lidar, {}, 1), ConfigError);
  NoiseProfile noise;
  noise.sigma_v = -1.0;
  EXPECT_THROW((void)simulate_run(occ, f.trajectory, {}, noise, 1), ConfigError);
  EXPECT_THROW((void)simulate_run(occ, {}, {}, {}, 1), ConfigError);
}

TEST(SimulateDefaultRun, IsTheDefaultPipelineWithTheRequestedNumberOfScans) {
  const auto plan = generate_floor_plan({});
  // A short open path (1 m of corridor, driven in ~3 s) so that the run is exactly min_scans long.
  const std::vector<Eigen::Vector2d> path{{plan.cross_corridor_x - 0.5, plan.corridor_y},
                                          {plan.cross_corridor_x + 0.5, plan.corridor_y}};
  const auto start = std::chrono::steady_clock::now();
  const SimulatedRun run = simulate_default_run(plan.occupancy, path, 150, 1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "simulate_default_run: " << run.size() / seconds << " scans/s (1081 beams)\n";
  ASSERT_EQ(run.size(), 150u);
  EXPECT_EQ(run.scans[0].sigma_range, 0.02);
  EXPECT_EQ(run.scans[0].ranges.size(), 1081u);
  // It is the explicit pipeline with default options (the same draws, sample by sample).
  TrajectoryOptions o;
  o.min_steps = 150;
  std::vector<TimedPose> trajectory = follow_path(path, plan.occupancy, o);
  trajectory.resize(20);
  const SimulatedRun same =
      simulate_run(plan.occupancy, trajectory, {}, NoiseProfile::table_3_2_sigma(), 1);
  for (std::size_t k = 0; k < same.size(); ++k) {
    ASSERT_EQ(run.truth[k], same.truth[k]);
    ASSERT_EQ(run.scans[k].ranges, same.scans[k].ranges);
    ASSERT_EQ(run.odometry[k].delta, same.odometry[k].delta);
  }
}

TEST(SimulateRun, DatasetOneOnTheStageHospitalSection) {
  const std::string file = std::string(VDTNAV_DATA_DIR) + "/stage_maps/hospital_section.png";
  if (!std::ifstream(file).good()) GTEST_SKIP() << "real data absent: " << file;
  const auto occ = load_occupancy_image(file, Eigen::Vector2d(40.0, 18.0), 0.05);
  const auto path = plan_tour(occ, 8, 0.4, 2);
  auto trajectory = follow_path(path, occ, {});
  const auto udt = unsigned_distance_transform(nearest_occupied_cells(occ));
  for (const auto& s : trajectory) ASSERT_GE(udt(occ.cell_of(s.pose.head<2>())), 0.2);
  trajectory.resize(40);
  const auto exact = simulate_run(occ, trajectory, {}, NoiseProfile::none(), 3);
  const auto noisy = simulate_run(occ, trajectory, {}, NoiseProfile::table_3_2_sigma(), 3);
  std::size_t finite = 0, total = 0;
  std::vector<double> err;
  for (std::size_t k = 0; k < exact.size(); ++k) {
    const Pose2& pose = exact.truth[k];
    for (std::size_t i = 0; i < exact.scans[k].ranges.size(); ++i) {
      const double a = pose[2] + exact.scans[k].angle(i);
      const double r = cast_ray<2>(occ, pose.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)),
                                   30.0, LidarOptions{}.surface);
      if (std::isinf(r)) {
        ASSERT_TRUE(std::isinf(exact.scans[k].ranges[i]));
      } else {
        ASSERT_NEAR(exact.scans[k].ranges[i], r, 1e-9);
      }
      ++total;
      if (!std::isfinite(exact.scans[k].ranges[i])) continue;
      ++finite;
      if (exact.scans[k].ranges[i] > 0.1)
        err.push_back(noisy.scans[k].ranges[i] - exact.scans[k].ranges[i]);
    }
  }
  EXPECT_GT(static_cast<double>(finite) / total, 0.95);  // indoors: nearly every beam returns
  EXPECT_NEAR(mean_std(err).second, 0.02, 0.001);
}

}  // namespace
}  // namespace vdtnav::sim
