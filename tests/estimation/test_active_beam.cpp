// Active localization with a single rotating beam (thesis ch. 4): the hypothetical reading against
// a real ray cast, the predicted covariance against the EKF's after the same readings, the range
// gradient of the Fisher prediction against finite differences, the segment a corridor makes the
// selector choose, and the beam's sweep.
#include "vdtnav/estimation/active_beam.hpp"
#include "vdtnav/estimation/active_beam_localizer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "scan_fixture.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/ray_casting.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace vdtnav {
namespace {

using test::world;

TEST(ActiveBeam, HypotheticalReadingEqualsARayCastInTheWorld) {
  RotatingBeamOptions beam = RotatingBeamOptions::table_4_3();  // up to 30 m
  const ActiveBeamSelector sel(world().map, beam);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> bearing(-kPi, kPi);
  int compared = 0, agree = 0;
  for (std::size_t k = 0; k < 12; ++k) {
    const Pose2 pose = test::tour_pose(k);
    for (int b = 0; b < 40; ++b) {
      const double theta = 0.75 * bearing(rng);
      const double a = pose[2] + theta;
      const Eigen::Vector2d u(std::cos(a), std::sin(a));
      const double truth = sim::cast_ray<2>(world().plan.occupancy, pose.head<2>(), u,
                                            beam.range_max, sim::RaySurface::kCellCentre);
      const double r = sel.hypothetical_range(pose, theta);
      if (!std::isfinite(truth) || truth < beam.range_min + 0.05 || truth > beam.range_max - 0.05) {
        continue;
      }
      ASSERT_TRUE(std::isfinite(r)) << "pose " << k << " bearing " << theta;
      // Along the surface's normal (at grazing incidence a millimetre across is centimetres
      // along the beam): the map's normal just in front of the hit.
      const Eigen::Vector2d v = world().map.value(pose.head<2>() + (truth - 0.03) * u);
      const double cos_incidence = v.norm() > 1e-6 ? std::abs(v.normalized().dot(u)) : 1.0;
      if (cos_incidence < 0.3) continue;
      ++compared;
      if (std::abs(r - truth) * cos_incidence < 0.01) {
        ++agree;
        continue;
      }
      // Otherwise the beam grazes a corner within a fraction of a cell, which the thin walls
      // through the cells' centres resolve and a 5 cm distance field cannot: the traced hit must
      // lie at an occupied cell centre's corner, not in free space.
      const Eigen::Vector2d q = pose.head<2>() + r * u;
      EXPECT_LT((q - world().map.nearest_occupied_point(q)).norm(), 0.03)
          << "pose " << k << " bearing " << theta << ": ray cast " << truth << ", traced " << r;
    }
  }
  EXPECT_GT(compared, 250);
  EXPECT_GT(agree, 0.95 * compared) << agree << " of " << compared;
}

TEST(ActiveBeam, PredictedCovarianceEqualsTheEkfsAfterTheSameReadings) {
  const RotatingBeamOptions beam = RotatingBeamOptions::table_4_1();
  const ActiveBeamSelector sel(world().map, beam);
  VdtEkfOptions eo;
  eo.min_inliers = 1;
  eo.max_iterations = 1;  // linearised once at the prediction, as the selection predicts
  eo.search.enabled = false;
  VdtEkfLocalizer ekf(world().map, eo);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.05 * 0.05, 0.08 * 0.08, 0.02 * 0.02).asDiagonal();
  int checked = 0;
  for (std::size_t k = 0; k < 6; ++k) {
    const Pose2 pose = test::tour_pose(k);
    for (int i = 0; i < beam.segments; ++i) {
      int readings = 0;
      const Eigen::Matrix3d predicted =
          sel.predicted_covariance(pose, p0, i, BeamStrategy::kActiveTrace, &readings);
      if (readings == 0) {
        EXPECT_TRUE(predicted.isApprox(p0));
        continue;
      }
      // The same readings, through the filter.
      ScanPoints pts;
      pts.sigma_range = beam.sigma_range;
      const double lo = sel.segment_lower(i), hi = sel.segment_upper(i);
      const int n = static_cast<int>(std::lround((hi - lo) / beam.hypothesis_resolution));
      for (int b = 0; b < n; ++b) {
        const double theta = lo + (b + 0.5) * (hi - lo) / n;
        const double r = sel.hypothetical_range(pose, theta);
        if (std::isfinite(r)) {
          pts.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(std::cos(theta), std::sin(theta)), r,
                  static_cast<std::size_t>(b));
        }
      }
      ekf.reset(pose, p0);
      const LocalizationResult res = ekf.update(OdometryStep{}, pts);
      ASSERT_EQ(res.status, LocalizationStatus::kConverged);
      EXPECT_LT((res.covariance - predicted).norm(), 1e-9 * p0.norm()) << k << " " << i;
      EXPECT_LT(predicted.trace(), p0.trace());
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

/// A corridor along x (walls at y = +-1 m) closed by an end wall 2 m ahead of the robot.
struct Corridor {
  OccupancyGrid<2> grid{Eigen::Vector2i(300, 60), GridFrame<2>(0.05, Eigen::Vector2d(-10.0, -1.5))};
  VdtMap2 map;
  Corridor() {
    for (int x = 0; x < 300; ++x) {
      grid(Eigen::Vector2i(x, 10)) = 1;  // y = -0.975
      grid(Eigen::Vector2i(x, 50)) = 1;  // y = 1.025
    }
    for (int y = 10; y <= 50; ++y) grid(Eigen::Vector2i(240, y)) = 1;  // x = 2.025
    map = VdtMap2::build(grid);
  }
};

/// g = dr/dX against central differences of the sphere-traced range, where the beam meets a
/// straight wall of the corridor (J a projector: not near its corners) away from grazing incidence.
TEST(ActiveBeam, RangeGradientMatchesFiniteDifferencesOfTheRayCast) {
  const Corridor c;
  const auto check = [](const ActiveBeamSelector& sel, const VdtMap2& map, const Pose2& pose,
                        double theta, double tolerance) {
    Eigen::Vector3d g;
    if (!sel.range_gradient(pose, theta, &g)) return false;
    const double r = sel.hypothetical_range(pose, theta);
    const Eigen::Vector2d u(std::cos(pose[2] + theta), std::sin(pose[2] + theta));
    const Eigen::Matrix2d j = map.evaluate(pose.head<2>() + r * u).jacobian;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (j + j.transpose()));
    // A straight wall's VDT (J the projector n n^T), not a corner's rounded field.
    if (std::abs(es.eigenvalues()[1] - 1.0) > 0.03 || std::abs(es.eigenvalues()[0]) > 0.03) {
      return false;
    }
    if (std::abs(es.eigenvectors().col(1).dot(u)) < 0.3) return false;  // grazing
    Eigen::Vector3d fd;
    for (int q = 0; q < 3; ++q) {
      const double step = q < 2 ? 2e-3 : 1e-3;
      Pose2 plus = pose, minus = pose;
      plus[q] += step;
      minus[q] -= step;
      const double rp = sel.hypothetical_range(plus, theta);
      const double rm = sel.hypothetical_range(minus, theta);
      if (!std::isfinite(rp) || !std::isfinite(rm) || std::abs(rp - rm) > 0.05) return false;
      fd[q] = (rp - rm) / (2.0 * step);
    }
    EXPECT_LT((g - fd).norm(), tolerance * (1.0 + g.norm()))
        << "bearing " << theta << " g " << g.transpose() << " fd " << fd.transpose();
    return true;
  };
  const RotatingBeamOptions beam = RotatingBeamOptions::table_4_3();
  const ActiveBeamSelector corridor(c.map, beam);
  int checked = 0;
  for (const Pose2& pose : {Pose2(0.1, 0.05, 0.1), Pose2(-0.7, -0.3, -0.4), Pose2(1.2, 0.4, 2.5)}) {
    for (double theta = -2.3; theta < 2.35; theta += 0.1) {
      checked += check(corridor, c.map, pose, theta, 0.02) ? 1 : 0;
    }
  }
  EXPECT_GT(checked, 60);
}

TEST(ActiveBeam, TurnsToTheWallThatConstrainsTheUncertainAxis) {
  const Corridor c;
  const RotatingBeamOptions beam = RotatingBeamOptions::table_4_1();  // 360 deg, 8 segments, 3 m
  const ActiveBeamSelector sel(c.map, beam);
  const Pose2 pose(0.0, 0.0, 0.0);
  for (const BeamStrategy s :
       {BeamStrategy::kActiveTrace, BeamStrategy::kActiveDet, BeamStrategy::kActiveFisher}) {
    // Uncertain along the corridor: only the end wall ahead (bearing 0) tells x.
    const Eigen::Matrix3d px = Eigen::Vector3d(0.2 * 0.2, 0.01 * 0.01, 0.005 * 0.005).asDiagonal();
    const BeamSelection ax = sel.select(pose, px, 0, s);
    const double cx = sel.segment_centre(ax.segment);
    EXPECT_GT(std::cos(cx), 0.7) << to_string(s) << ": segment " << ax.segment;
    // Uncertain across it: a segment that sees a side wall, which takes the y variance down.
    const Eigen::Matrix3d py = Eigen::Vector3d(0.01 * 0.01, 0.2 * 0.2, 0.005 * 0.005).asDiagonal();
    const BeamSelection ay = sel.select(pose, py, 0, s);
    const Eigen::Matrix3d post = sel.predicted_covariance(pose, py, ay.segment, s);
    EXPECT_LT(post(1, 1), 0.01 * py(1, 1)) << to_string(s) << ": segment " << ay.segment;
  }
  // Straight behind the robot the corridor is open beyond 3 m: no reading.
  EXPECT_FALSE(std::isfinite(sel.hypothetical_range(pose, kPi)));
  EXPECT_NEAR(sel.hypothetical_range(pose, 0.0), 2.025, 0.005);
  EXPECT_NEAR(sel.hypothetical_range(pose, 0.5 * kPi), 1.025, 0.005);
}

TEST(ActiveBeam, ControllerSweepsToTheFarEndOfTheGoalAtItsAngularVelocity) {
  const Corridor c;
  RotatingBeamOptions beam = RotatingBeamOptions::table_4_3();  // 270 deg, 23 segments
  const ActiveBeamSelector sel(c.map, beam);
  RotatingBeamController ctl(beam, BeamStrategy::kActiveTrace);
  EXPECT_TRUE(ctl.needs_goal());
  ctl.set_goal(20, sel);
  EXPECT_FALSE(ctl.needs_goal());
  const double target = sel.segment_upper(20);  // the far end from bearing 0
  const double dt = 0.025;
  int steps = 0;
  while (!ctl.needs_goal() && steps < 100000) {
    const double before = ctl.bearing();
    ctl.advance(dt);
    EXPECT_LE(std::abs(ctl.bearing() - before), beam.angular_velocity * dt + 1e-12);
    ++steps;
  }
  EXPECT_NEAR(ctl.bearing(), target, 1e-12);
  EXPECT_NEAR(steps * dt, target / beam.angular_velocity, 2 * dt);
  // Passive: fixed stays at the heading; rotate bounces within the range.
  RotatingBeamController fixed(beam, BeamStrategy::kPassiveFixed),
      rot(beam, BeamStrategy::kPassiveRotate);
  for (int k = 0; k < 40000; ++k) {
    fixed.advance(dt);
    rot.advance(dt);
    EXPECT_EQ(fixed.bearing(), 0.0);
    EXPECT_LE(std::abs(rot.bearing()), 0.5 * beam.rotation_range + 1e-12);
    EXPECT_FALSE(rot.needs_goal());
  }
  EXPECT_THROW((void)beam_strategy_from_string("active-everything"), ConfigError);
  EXPECT_EQ(beam_strategy_from_string("active-fisher"), BeamStrategy::kActiveFisher);
  RotatingBeamOptions bad = beam;
  bad.segments = 0;
  EXPECT_THROW(RotatingBeamController(bad, BeamStrategy::kActiveTrace), ConfigError);
}

}  // namespace
}  // namespace vdtnav

namespace vdtnav {
namespace {

/// The Localizer2D form (`vdtnav localize --method active-ekf`): full 40 Hz scans in, one reading
/// per scan used, the beam turning; it tracks a drive through the generated floor plan.
TEST(ActiveBeam, GateKeepsReadingsOfThePredictedSurfaceAndRefusesOthers) {
  // sigma^2 = g^T P g + sigma_r^2 + floor^2 (Cholesky-free: P diagonal, so the bound is explicit).
  RotatingBeamOptions beam = RotatingBeamOptions::table_4_3();
  VdtSensorModelOptions sensor;
  sensor.map_sigma = 0.03;
  const ActiveBeamSelector sel(world().map, beam, sensor);
  const Eigen::Matrix3d p = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, 0.005 * 0.005).asDiagonal();
  int tested = 0;
  for (std::size_t k = 0; k < 12; ++k) {
    const Pose2 pose = test::tour_pose(k);
    for (int b = -8; b <= 8; ++b) {
      const double theta = 0.15 * b;
      Eigen::Vector3d g;
      if (!sel.range_gradient(pose, theta, &g)) continue;
      const double r = sel.hypothetical_range(pose, theta);
      const double sigma =
          std::sqrt(g.dot(p * g) + beam.sigma_range * beam.sigma_range + 0.03 * 0.03);
      ++tested;
      EXPECT_TRUE(sel.consistent(pose, p, theta, r));
      EXPECT_TRUE(sel.consistent(pose, p, theta, r + 0.95 * beam.gate * sigma));
      EXPECT_FALSE(sel.consistent(pose, p, theta, r - 1.05 * beam.gate * sigma));
      // Another surface a metre on (unless the beam grazes so that a metre is within the gate).
      if (beam.gate * sigma < 0.9) {
        EXPECT_FALSE(sel.consistent(pose, p, theta, r + 1.0));
      }
      // An uncertain pose accepts what a certain one refuses.
      EXPECT_TRUE(sel.consistent(pose, 1e4 * p, theta, r - 1.05 * beam.gate * sigma));
    }
  }
  EXPECT_GT(tested, 100);
  beam.gate = 0.0;  // no gate
  const ActiveBeamSelector open(world().map, beam, sensor);
  EXPECT_TRUE(open.consistent(test::tour_pose(0), p, 0.0, 1e3));
  beam.gate = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ActiveBeamSelector(world().map, beam), ConfigError);
}

TEST(ActiveBeamLocalizer, KeepsOneReadingPerScanAndTracksADrive) {
  sim::TrajectoryOptions t;
  t.rate_hz = 40.0;
  t.min_steps = 1200;  // 30 s
  const auto drive = sim::follow_path(world().plan.tour, world().plan.occupancy, t);
  sim::LidarOptions lidar;  // UTM-30LX-like, 270 degrees at 0.25 degrees
  const sim::SimulatedRun run = sim::simulate_run(
      world().plan.occupancy, std::vector<sim::TimedPose>(drive.begin(), drive.begin() + 1200),
      lidar, sim::NoiseProfile::table_3_2_sigma(), 5);
  for (const BeamStrategy s : {BeamStrategy::kActiveTrace, BeamStrategy::kPassiveRotate}) {
    ActiveBeamLocalizerOptions o;
    o.strategy = s;
    ActiveBeamLocalizer loc(world().map, o, to_string(s));
    loc.reset(run.truth[0], Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal());
    double worst = 0.0, min_bearing = 10.0, max_bearing = -10.0;
    int updates = 0;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const LocalizationResult r = loc.update(run.odometry[k], run.scans[k]);
      EXPECT_LE(r.inliers, 1);
      updates += r.status == LocalizationStatus::kConverged ? 1 : 0;
      worst = std::max(worst, (r.pose.head<2>() - run.truth[k].head<2>()).norm());
      min_bearing = std::min(min_bearing, loc.bearing());
      max_bearing = std::max(max_bearing, loc.bearing());
    }
    EXPECT_GT(updates, static_cast<int>(run.size()) / 2) << to_string(s);
    EXPECT_LT(worst, 0.2) << to_string(s);
    EXPECT_GT(max_bearing - min_bearing, 0.5) << to_string(s);  // the beam turned
  }
}

}  // namespace
}  // namespace vdtnav
