// The simulated pan-tilt point laser (thesis 3.4.4.2): ranges in an empty box room against the
// closed-form distance to its planes from a rolled and pitched robot, noise statistics, no-return
// readings, reproducibility, and the observation set landing on the room's surfaces.
#include "vdtnav/sim/point_laser_simulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <vector>

#include "box_room.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"

namespace vdtnav::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRes = 0.05;

using test::BoxRoom;

/// The laser's pose in the world composed here from the calibration: robot, mount, pan about z,
/// offset, tilt about y, offset (beam along x).
Eigen::Isometry3d laser_in_world(const Pose3& robot, const PanTiltCalibration& c, double pan,
                                 double tilt) {
  return robot * c.mount * Eigen::AngleAxisd(pan, Eigen::Vector3d::UnitZ()) *
         Eigen::Translation3d(c.pan_to_tilt) * Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()) *
         Eigen::Translation3d(c.tilt_to_laser);
}

/// A robot standing rolled and pitched as on an uneven floor in the middle of the room.
Pose3 tilted_robot(double x, double y) { return pose3_from_xyz_rpy(x, y, 0.03, 0.06, -0.04, 0.7); }

PointLaserSimOptions noise_free() {
  PointLaserSimOptions o;
  o.noisy = false;
  return o;
}

TEST(PanTiltPattern, DefaultIs100PansOverAFullTurnBy57Tilts) {
  const PanTiltPattern p;
  EXPECT_EQ(p.size(), 5700u);
  const auto a = p.pan_tilt_angles();
  ASSERT_EQ(a.size(), 5700u);
  std::set<double> pans, tilts;
  for (const auto& v : a) {
    pans.insert(v.x());
    tilts.insert(v.y());
  }
  EXPECT_EQ(pans.size(), 100u);
  EXPECT_EQ(tilts.size(), 57u);
  EXPECT_DOUBLE_EQ(*pans.begin(), -kPi);
  EXPECT_NEAR(*pans.rbegin(), kPi - 2 * kPi / 100, 1e-12);  // a full turn, no angle twice
  EXPECT_DOUBLE_EQ(*tilts.begin(), -0.5);
  EXPECT_NEAR(*tilts.rbegin(), 0.8, 1e-12);
  // Pan outer, tilt inner.
  EXPECT_EQ(a[0], Eigen::Vector2d(-kPi, -0.5));
  EXPECT_EQ(a[1].x(), -kPi);
  EXPECT_EQ(a[57].x(), -kPi + 2 * kPi / 100);
  // Downsampling by the thesis's factors keeps every tilt.
  for (std::size_t k : {2u, 5u, 10u, 100u}) {
    std::set<double> kept;
    for (std::size_t i = 0; i < a.size(); i += k) kept.insert(a[i].y());
    EXPECT_EQ(kept.size(), 57u) << "every " << k << "th reading";
  }

  PanTiltPattern explicit_pairs;
  explicit_pairs.angles = {{0.1, 0.2}, {0.3, -0.4}};
  EXPECT_EQ(explicit_pairs.size(), 2u);
  EXPECT_EQ(explicit_pairs.pan_tilt_angles(), explicit_pairs.angles);
  PanTiltPattern one_tilt;
  one_tilt.tilt_steps = 1;
  one_tilt.pan_steps = 3;
  for (const auto& v : one_tilt.pan_tilt_angles()) EXPECT_EQ(v.y(), one_tilt.tilt_min);
}

TEST(PointLaserSimulator, FloorRangeIsHeightOverCosineFromATiltedRobot) {
  const BoxRoom room(20.0, 20.0, 3.0, true);
  const Pose3 robot = tilted_robot(10.0, 10.0);
  PointLaserSimOptions o = noise_free();
  o.pattern.tilt_min = 0.35;  // every beam looks down enough to reach the floor within ~1.5 m
  o.pattern.tilt_max = 1.3;
  o.pattern.pan_steps = 72;
  o.pattern.tilt_steps = 12;
  const PointLaserSweep sweep = simulate_point_laser_sweep(room.grid, robot, o, 1);
  ASSERT_EQ(sweep.readings.size(), 72u * 12u);
  EXPECT_TRUE(sweep.truth.isApprox(robot));
  for (const PanTiltReading& z : sweep.readings) {
    const Eigen::Isometry3d laser = laser_in_world(robot, o.calibration, z.pan, z.tilt);
    const double height = laser.translation().z();        // beam origin above the floor z = 0
    const double cos_angle = -laser.linear().col(0).z();  // angle between beam and straight down
    ASSERT_GT(cos_angle, 0.2);
    EXPECT_NEAR(z.range, height / cos_angle, 1e-9) << "pan " << z.pan << " tilt " << z.tilt;
  }
}

TEST(PointLaserSimulator, EveryRangeMatchesTheClosedFormBoxDistance) {
  const BoxRoom room(8.0, 6.0, 3.0, true);
  const Pose3 robot = tilted_robot(3.1, 2.4);
  const PointLaserSimOptions o = noise_free();
  const PointLaserSweep sweep = simulate_point_laser_sweep(room.grid, robot, o, 1);
  ASSERT_EQ(sweep.readings.size(), 5700u);
  int compared = 0;
  for (const PanTiltReading& z : sweep.readings) {
    const Eigen::Isometry3d laser = laser_in_world(robot, o.calibration, z.pan, z.tilt);
    int near = 0;
    const double expected =
        room.oracle(laser.translation(), laser.linear().col(0), 2 * kRes, &near);
    // Along an edge of the box the first cell entered may belong to the other plane.
    if (near > 1) continue;
    ++compared;
    EXPECT_NEAR(z.range, expected, 1e-9) << "pan " << z.pan << " tilt " << z.tilt;
  }
  EXPECT_GT(compared, 5000);
}

TEST(PointLaserSimulator, NoiseIsZeroMeanWithTheLidarLiteSigma) {
  const BoxRoom room(8.0, 6.0, 3.0, true);
  const Pose3 robot = tilted_robot(3.1, 2.4);
  PointLaserSimOptions o;  // noisy, sigma 0.025
  EXPECT_EQ(o.spec.sigma_range, 0.025);
  EXPECT_EQ(o.spec.range_min, 0.05);
  EXPECT_EQ(o.spec.range_max, 40.0);
  o.pattern.pan_steps = 400;  // 20000 readings
  const PointLaserSweep noisy = simulate_point_laser_sweep(room.grid, robot, o, 3);
  EXPECT_EQ(noisy.sigma_range, 0.025);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (const PanTiltReading& z : noisy.readings) {
    const Eigen::Isometry3d laser = laser_in_world(robot, o.calibration, z.pan, z.tilt);
    int near = 0;
    const double exact = room.oracle(laser.translation(), laser.linear().col(0), 2 * kRes, &near);
    if (near > 1) continue;
    const double e = z.range - exact;
    sum += e;
    sum2 += e * e;
    ++n;
  }
  ASSERT_GT(n, 19000);
  const double mean = sum / n, sd = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  EXPECT_LT(std::abs(mean), 4.0 * 0.025 / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(sd, 0.025, 0.025 * 0.04);

  // The same seed without noise differs by the same draws scaled by sigma: noisy - exact is
  // reproducible, and another seed gives other draws.
  o.noisy = false;
  const PointLaserSweep exact = simulate_point_laser_sweep(room.grid, robot, o, 3);
  o.noisy = true;
  const PointLaserSweep again = simulate_point_laser_sweep(room.grid, robot, o, 3);
  const PointLaserSweep other = simulate_point_laser_sweep(room.grid, robot, o, 4);
  int differ = 0;
  for (std::size_t k = 0; k < noisy.readings.size(); ++k) {
    EXPECT_EQ(again.readings[k].range, noisy.readings[k].range);
    differ += other.readings[k].range != noisy.readings[k].range;
    EXPECT_EQ(exact.readings[k].pan, noisy.readings[k].pan);
    EXPECT_EQ(exact.readings[k].tilt, noisy.readings[k].tilt);
  }
  EXPECT_GT(differ, static_cast<int>(noisy.readings.size()) - 10);
}

TEST(PointLaserSimulator, NoReturnReadsInfinityAndIsDropped) {
  // Only a floor: beams that look up or level leave the grid; beams that look down hit the floor.
  const BoxRoom floor_only(8.0, 8.0, 3.0, false);
  const Pose3 robot = tilted_robot(4.0, 4.0);
  const PointLaserSimOptions o = noise_free();
  const PointLaserSweep sweep = simulate_point_laser_sweep(floor_only.grid, robot, o, 5);
  std::size_t infinite = 0;
  for (const PanTiltReading& z : sweep.readings) {
    const Eigen::Isometry3d laser = laser_in_world(robot, o.calibration, z.pan, z.tilt);
    const Eigen::Vector3d d = laser.linear().col(0);
    const double t_floor = d.z() < 0 ? -laser.translation().z() / d.z() : kInf;
    const Eigen::Vector3d hit = laser.translation() + t_floor * d;
    const bool inside =
        std::isfinite(t_floor) && hit.x() > 0.1 && hit.x() < 7.9 && hit.y() > 0.1 && hit.y() < 7.9;
    if (d.z() >= 0) {
      EXPECT_EQ(z.range, kInf);
    }
    if (inside) {
      EXPECT_NEAR(z.range, t_floor, 1e-9);
    }
    infinite += std::isinf(z.range);
  }
  EXPECT_GT(infinite, 1000u);
  EXPECT_LT(infinite, sweep.readings.size());
  const ObservationSet3 obs = point_laser_observations(sweep.readings, o.calibration);
  EXPECT_EQ(obs.dropped_not_finite, infinite);
  EXPECT_EQ(obs.dropped_out_of_range, 0u);
  EXPECT_EQ(obs.size() + infinite, sweep.readings.size());

  // Beyond range_max nothing returns either.
  PointLaserSimOptions short_range = o;
  short_range.spec.range_max = 1.0;
  const PointLaserSweep near = simulate_point_laser_sweep(floor_only.grid, robot, short_range, 5);
  for (std::size_t k = 0; k < near.readings.size(); ++k) {
    if (sweep.readings[k].range < 1.0) {
      EXPECT_EQ(near.readings[k].range, sweep.readings[k].range);
    } else {
      EXPECT_EQ(near.readings[k].range, kInf);
    }
  }
}

TEST(PointLaserSimulator, ObservationsLieOnTheRoomSurfaces) {
  const BoxRoom room(8.0, 6.0, 3.0, true);
  const Pose3 robot = tilted_robot(5.2, 3.7);
  const PointLaserSimOptions o = noise_free();
  const PointLaserSweep sweep = simulate_point_laser_sweep(room.grid, robot, o, 1);
  const ObservationSet3 obs = point_laser_observations(sweep.readings, o.calibration);
  EXPECT_EQ(obs.size(), 5700u);  // a closed room: everything returns
  EXPECT_EQ(obs.sigma_range, 0.025);
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const Eigen::Vector3d p = robot * obs.points[k];  // world frame
    const double to_plane =
        std::min({std::abs(p.x()), std::abs(p.x() - 8.0), std::abs(p.y()), std::abs(p.y() - 6.0),
                  std::abs(p.z()), std::abs(p.z() - 3.0)});
    EXPECT_LT(to_plane, 1e-9);
    const PanTiltReading& z = sweep.readings[obs.beam[k]];
    const Eigen::Isometry3d laser = laser_in_world(robot, o.calibration, z.pan, z.tilt);
    EXPECT_LT((robot.linear() * obs.directions[k] - laser.linear().col(0)).norm(), 1e-12);
  }
}

TEST(PointLaserSimulator, TimesAndSweepsPerLocation) {
  const BoxRoom room(8.0, 6.0, 3.0, true);
  PointLaserSimOptions o;
  o.pattern.pan_steps = 10;
  o.pattern.tilt_steps = 10;
  const std::vector<Pose3> poses = {tilted_robot(2.0, 2.0), tilted_robot(2.0, 2.0),
                                    tilted_robot(6.0, 4.0)};
  const auto sweeps = simulate_point_laser_sweeps(room.grid, poses, o, 9);
  ASSERT_EQ(sweeps.size(), 3u);
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_TRUE(sweeps[s].truth.isApprox(poses[s]));
    ASSERT_EQ(sweeps[s].readings.size(), 100u);
    for (std::size_t k = 0; k < 100; ++k)
      EXPECT_DOUBLE_EQ(sweeps[s].readings[k].time, 0.002 * static_cast<double>(k));
  }
  // Same pose, independent noise.
  int same = 0;
  for (std::size_t k = 0; k < 100; ++k)
    same += sweeps[0].readings[k].range == sweeps[1].readings[k].range;
  EXPECT_LT(same, 5);
  const auto again = simulate_point_laser_sweeps(room.grid, poses, o, 9);
  for (std::size_t k = 0; k < 100; ++k)
    EXPECT_EQ(again[2].readings[k].range, sweeps[2].readings[k].range);
}

TEST(PointLaserSimulator, RejectsInvalidOptions) {
  const BoxRoom room(4.0, 4.0, 3.0, true);
  const Pose3 robot = tilted_robot(2.0, 2.0);
  PointLaserSimOptions o;
  o.spec.range_max = o.spec.range_min;
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, robot, o, 1), ConfigError);
  o = {};
  o.spec.sigma_range = -1.0;
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, robot, o, 1), ConfigError);
  o = {};
  o.pattern.tilt_steps = 0;
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, robot, o, 1), ConfigError);
  o = {};
  o.pattern.tilt_max = o.pattern.tilt_min - 0.1;
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, robot, o, 1), ConfigError);
  o = {};
  o.pattern.angles = {{0.0, std::nan("")}};
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, robot, o, 1), ConfigError);
  o = {};
  Pose3 bad = robot;
  bad.translation().x() = kInf;
  EXPECT_THROW((void)simulate_point_laser_sweep(room.grid, bad, o, 1), ConfigError);
}

}  // namespace
}  // namespace vdtnav::sim
