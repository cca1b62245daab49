// The simulated VLP-16 against an analytic ray-plane oracle in an empty box room: the ring and
// azimuth of every ray, the range to the first plane, NaN where nothing returns, and the noise.
#include "vdtnav/sim/lidar3d_simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "box_room.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

using test::BoxRoom;

TEST(Lidar3dSimulator, RaysHitTheRoomsPlanesWhereTheOracleSays) {
  const BoxRoom room(6.0, 5.0, 3.0, true);
  sim::Lidar3dSpec spec;  // VLP-16
  spec.sigma_range = 0.0;
  spec.azimuth_step = 2.0 * kPi / 360;  // 1 degree: 5760 rays
  const Pose3 pose = pose3_from_xyz_rpy(2.2, 1.9, 1.1, 0.05, -0.08, 0.7);
  std::mt19937 rng(1);
  const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(room.grid, pose, spec, rng);
  ASSERT_EQ(scan.points.size(), 16u * 360u);
  int checked = 0;
  for (int k = 0; k < 16; ++k) {
    const double e = (-15.0 + 2.0 * k) * kPi / 180.0;  // 16 rings 2 degrees apart
    for (int j = 0; j < 360; ++j) {
      const Eigen::Vector3d& p = scan.points[static_cast<std::size_t>(k * 360 + j)];
      ASSERT_TRUE(p.allFinite()) << k << " " << j;  // a closed room: every ray returns
      const double a = j * 2.0 * kPi / 360;
      const Eigen::Vector3d u(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      EXPECT_LT((p.normalized() - u).norm(), 1e-12);
      int near = 0;
      const double t = room.oracle(pose.translation(), pose.linear() * u, 0.2, &near);
      if (near > 1) continue;  // within a cell of an edge: the voxel staircase decides
      EXPECT_NEAR(p.norm(), t, 0.5 * test::kBoxRes * std::sqrt(3.0) + 1e-9) << k << " " << j;
      ++checked;
    }
  }
  EXPECT_GT(checked, 5000);
  EXPECT_EQ(scan.returns, scan.points.size());
}

TEST(Lidar3dSimulator, NoReturnIsNaNAndTheRangeNoiseHasTheSpecsSigma) {
  const BoxRoom room(40.0, 40.0, 3.0, false);  // a floor only: upward rays never return
  sim::Lidar3dSpec spec;
  spec.azimuth_step = 2.0 * kPi / 90;
  const Pose3 pose = pose3_from_xyz_rpy(20, 20, 1.0, 0, 0, 0);
  std::mt19937 rng(3);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (int rep = 0; rep < 20; ++rep) {
    const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(room.grid, pose, spec, rng);
    for (int k = 0; k < 16; ++k) {
      const double e = (-15.0 + 2.0 * k) * kPi / 180.0;
      for (int j = 0; j < 90; ++j) {
        const Eigen::Vector3d& p = scan.points[static_cast<std::size_t>(k * 90 + j)];
        if (e >= 0.0) {
          EXPECT_FALSE(p.allFinite());  // level and upward rings see no floor
          continue;
        }
        const double exact = -1.0 / std::sin(e);  // the floor plane z = 0, 1 m below
        if (exact > 19.0) continue;               // may leave the 40 m floor
        ASSERT_TRUE(p.allFinite());
        const double err = p.norm() - exact;
        sum += err;
        sum2 += err * err;
        ++n;
      }
    }
  }
  ASSERT_GT(n, 5000);
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // The voxel staircase adds at most half a cell's spread (uniform: 0.05 / sqrt(12) ~ 0.014 m).
  EXPECT_NEAR(sd, std::hypot(0.03, 0.5 * test::kBoxRes / std::sqrt(3.0)), 0.006);
  EXPECT_LT(std::abs(mean), 0.01);
}

TEST(Lidar3dSimulator, ASweepFiresEachColumnFromWhereTheMovingSensorIsThen) {
  // 2 m/s and 30 deg/s of yaw: column j's rays leave from stamp * T(j / (360 * 10 Hz)), and hit
  // the oracle's planes from there; each point is in the sensor's frame at its own time.
  const BoxRoom room(6.0, 5.0, 3.0, true);
  sim::Lidar3dSpec spec;
  spec.sigma_range = 0.0;
  spec.azimuth_step = 2.0 * kPi / 360;
  SweepMotion motion;
  motion.velocity = Eigen::Vector3d(2.0, 0.0, 0.0);
  motion.rates = Eigen::Vector3d(0.0, 0.0, 30.0 * kPi / 180.0);
  const Pose3 stamp = pose3_from_xyz_rpy(2.2, 1.9, 1.1, 0.05, -0.08, 0.7);
  std::mt19937 rng(1);
  const sim::Lidar3dScan scan = sim::simulate_lidar3d_sweep(room.grid, stamp, motion, spec, rng);
  ASSERT_EQ(scan.times.size(), scan.points.size());
  int checked = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const std::size_t j = i % 360;
    ASSERT_DOUBLE_EQ(scan.times[i], static_cast<double>(j) / 3600.0);
    const Pose3 sensor = stamp * motion.at(scan.times[i]);
    const Eigen::Vector3d u = scan.points[i].normalized();
    int near = 0;
    const double t = room.oracle(sensor.translation(), sensor.linear() * u, 0.2, &near);
    if (near > 1) continue;
    EXPECT_NEAR(scan.points[i].norm(), t, 0.5 * test::kBoxRes * std::sqrt(3.0) + 1e-9) << i;
    ++checked;
  }
  EXPECT_GT(checked, 5000);
  // At rest, a sweep is the scan (same rays, same noise draws).
  spec.sigma_range = 0.03;
  std::mt19937 a(7), b(7);
  const sim::Lidar3dScan still = sim::simulate_lidar3d_sweep(room.grid, stamp, {}, spec, a);
  const sim::Lidar3dScan once = sim::simulate_lidar3d_scan(room.grid, stamp, spec, b);
  ASSERT_EQ(still.points.size(), once.points.size());
  for (std::size_t i = 0; i < once.points.size(); ++i)
    EXPECT_LT((still.points[i] - once.points[i]).norm(), 1e-12) << i;
  EXPECT_EQ(sim::lidar3d_observations(still, spec).times.size(), still.returns);
}

TEST(Lidar3dSimulator, RefusesASpecOutOfItsDomain) {
  const BoxRoom room(4.0, 4.0, 3.0, true);
  std::mt19937 rng(1);
  sim::Lidar3dSpec bad;
  bad.rings = 0;
  EXPECT_THROW((void)sim::simulate_lidar3d_scan(room.grid, Pose3::Identity(), bad, rng),
               ConfigError);
  bad = {};
  bad.azimuth_step = 0.0;
  EXPECT_THROW((void)sim::simulate_lidar3d_scan(room.grid, Pose3::Identity(), bad, rng),
               ConfigError);
}

}  // namespace
}  // namespace vdtnav
