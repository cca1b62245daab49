// Deskewing (sensor/sweep_motion.hpp): readings taken by a sensor moving at constant velocity,
// each in the sensor's frame at its own time, moved to the stamp's frame by (2), against the world
// points they measured (exact); the velocity recovered from an increment; the errors.
#include "vdtnav/sensor/sweep_motion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

SweepMotion brisk() {
  SweepMotion m;
  m.velocity = Eigen::Vector3d(2.0, 0.3, -0.1);  // m/s
  m.rates = Eigen::Vector3d(0.05, -0.08, 0.52);  // rad/s (30 deg/s of yaw)
  return m;
}

TEST(SweepMotion, DeskewingPutsEachReadingWhereASensorAtRestAtTheStampSeesIt) {
  const SweepMotion m = brisk();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-20.0, 20.0), when(0.0, 0.1);
  ObservationSet3 scan;
  scan.sigma_range = 0.03;
  std::vector<Eigen::Vector3d> world;  // in the stamp's frame
  std::vector<Pose3> sensor;           // the sensor at each reading's time, stamp's frame
  for (std::size_t i = 0; i < 500; ++i) {
    world.emplace_back(coord(rng), coord(rng), coord(rng));
    const double tau = when(rng);
    sensor.push_back(m.at(tau));
    const Eigen::Vector3d p = sensor.back().inverse() * world.back();  // as the driver writes it
    scan.add(Eigen::Vector3d::Zero(), p.normalized(), p.norm(), i);
    scan.times.push_back(tau);
  }
  ObservationSet3 moved = scan;
  EXPECT_EQ(deskew(moved, m), 500u);
  double before = 0.0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    before = std::max(before, (scan.points[i] - world[i]).norm());
    EXPECT_LT((moved.points[i] - world[i]).norm(), 1e-9) << i;
    // The beam now leaves from where the sensor was, along the same line.
    const Eigen::Vector3d u = (world[i] - sensor[i].translation()).normalized();
    EXPECT_LT((moved.directions[i] - u).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(moved.ranges[i], scan.ranges[i]);
  }
  EXPECT_GT(before, 0.5);  // the distortion undone: up to 0.2 m of travel and 3 deg at 20 m
}

TEST(SweepMotion, TheVelocityOfAnIncrementIsTheOneThatMakesIt) {
  const SweepMotion m = brisk();
  const SweepMotion back = SweepMotion::from_increment(m.at(0.1), 0.1);
  EXPECT_LT((back.velocity - m.velocity).norm(), 1e-12);
  EXPECT_LT((back.rates - m.rates).norm(), 1e-12);
  EXPECT_THROW((void)SweepMotion::from_increment(Pose3::Identity(), 0.0), ConfigError);
}

TEST(SweepMotion, AScanWithoutTimesIsInstantaneousAndBadTimesAreRefused) {
  ObservationSet3 scan;
  scan.add(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 5.0, 0);
  EXPECT_EQ(deskew(scan, brisk()), 0u);
  EXPECT_EQ(scan.points[0], Eigen::Vector3d(5.0, 0.0, 0.0));
  scan.times = {0.05, 0.06};
  EXPECT_THROW(deskew(scan, brisk()), ConfigError);
  scan.times = {std::numeric_limits<double>::quiet_NaN()};
  EXPECT_THROW(deskew(scan, brisk()), ConfigError);
}

}  // namespace
}  // namespace vdtnav
