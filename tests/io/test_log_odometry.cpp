// The odometry `vdtnav localize` feeds its localizers: ODOM lines interpolated at the scan times
// (linear in x, y; the shorter arc in yaw, across ±π), the laser messages' odometry fields when
// the ODOM lines are unusable (each reason), and the steps between scans (the increment is the
// one that composes the previous pose onto the next; v signed by the direction of motion).
#include "vdtnav/io/log_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace vdtnav {
namespace {

CarmenOdometry odom(double t, const Pose2& p, std::size_t line) {
  CarmenOdometry o;
  o.time = t;
  o.pose = p;
  o.line = line;
  return o;
}

CarmenLaser laser(double t, const Pose2& odom_fields) {
  CarmenLaser l;
  l.time = t;
  l.odom = odom_fields;
  return l;
}

/// A log with ODOM lines at t = 10, 11, 12, 13 and lasers at 10.5, 11.25, 12.9 (laser odometry
/// fields deliberately different from the ODOM lines).
CarmenLog log_with_odom() {
  CarmenLog log;
  log.odometry = {odom(10.0, Pose2(0.0, 0.0, 0.0), 1), odom(11.0, Pose2(1.0, 0.0, 3.0), 2),
                  odom(12.0, Pose2(1.0, 2.0, -3.0), 3), odom(13.0, Pose2(4.0, 2.0, -2.0), 4)};
  log.lasers = {laser(10.5, Pose2(9.0, 9.0, 0.0)), laser(11.25, Pose2(9.0, 9.0, 0.1)),
                laser(12.9, Pose2(9.0, 9.0, 0.2))};
  return log;
}

void expect_pose_near(const Pose2& a, const Pose2& b, double tol) {
  EXPECT_NEAR(a[0], b[0], tol);
  EXPECT_NEAR(a[1], b[1], tol);
  EXPECT_NEAR(std::abs(wrap_angle(a[2] - b[2])), 0.0, tol) << a[2] << " vs " << b[2];
}

TEST(LogOdometry, InterpolatesOdomLinesAtTheScanTimes) {
  const CarmenLog log = log_with_odom();
  const LogOdometry o = log_odometry(log, {0, 1, 2});
  ASSERT_EQ(o.source, LogOdometrySource::kOdomMessages) << o.reason;
  EXPECT_TRUE(o.reason.empty());
  ASSERT_EQ(o.poses.size(), 3u);
  expect_pose_near(o.poses[0], Pose2(0.5, 0.0, 1.5), 1e-12);
  // 11 -> 12: yaw 3 -> -3 is +0.283 rad the short way (through π), not -6 the long way.
  const double short_arc = 2.0 * kPi - 6.0;
  expect_pose_near(o.poses[1], Pose2(1.0, 0.5, 3.0 + 0.25 * short_arc), 1e-12);
  expect_pose_near(o.poses[2], Pose2(1.0 + 0.9 * 3.0, 2.0, -3.0 + 0.9 * 1.0), 1e-12);
  EXPECT_LE(o.poses[1][2], kPi);  // wrapped to (-π, π]
  EXPECT_GT(o.poses[1][2], -kPi);
}

TEST(LogOdometry, OnlyTheSelectedScans) {
  const LogOdometry o = log_odometry(log_with_odom(), {2});
  ASSERT_EQ(o.poses.size(), 1u);
  expect_pose_near(o.poses[0], Pose2(3.7, 2.0, -2.1), 1e-12);
}

TEST(LogOdometry, FallsBackToTheLaserFieldsWithTheReason) {
  struct Case {
    const char* name;
    void (*spoil)(CarmenLog&);
    const char* reason;
  };
  const Case cases[] = {
      {"one ODOM line", [](CarmenLog& l) { l.odometry.resize(1); }, "fewer than two ODOM lines"},
      {"zeroed (corrected log)",
       [](CarmenLog& l) {
         for (auto& o : l.odometry) o.pose.setZero();
       },
       "all ODOM poses are zero"},
      {"time going back", [](CarmenLog& l) { l.odometry[2].time = 10.5; },
       "ODOM times decrease at line 3"},
      {"not spanning the scans", [](CarmenLog& l) { l.odometry.pop_back(); },
       "ODOM lines do not span the scans' times"},
  };
  for (const Case& c : cases) {
    CarmenLog log = log_with_odom();
    c.spoil(log);
    const LogOdometry o = log_odometry(log, {0, 1, 2});
    EXPECT_EQ(o.source, LogOdometrySource::kLaserOdomFields) << c.name;
    EXPECT_NE(o.reason.find(c.reason), std::string::npos) << c.name << ": " << o.reason;
    ASSERT_EQ(o.poses.size(), 3u) << c.name;
    for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(o.poses[k], log.lasers[k].odom) << c.name;
  }
  // Within the 0.5 s span tolerance the ODOM lines are still used (clamped at the end).
  CarmenLog log = log_with_odom();
  log.odometry.back().time = 12.5;
  log.lasers[2].time = 12.9;
  const LogOdometry o = log_odometry(log, {0, 1, 2});
  EXPECT_EQ(o.source, LogOdometrySource::kOdomMessages) << o.reason;
  expect_pose_near(o.poses[2], log.odometry.back().pose, 1e-12);
}

TEST(OdometrySteps, IncrementsComposeOntoThePreviousPose) {
  const std::vector<double> times = {0.0, 0.5, 1.5, 1.5, 1.4};
  const std::vector<Pose2> poses = {Pose2(1.0, 1.0, 0.5), Pose2(1.4, 1.3, 0.7),
                                    Pose2(1.0, 1.0, 3.1), Pose2(1.1, 1.0, -3.1),
                                    Pose2(1.2, 1.0, -3.0)};
  const std::vector<OdometryStep> steps = odometry_steps(times, poses);
  ASSERT_EQ(steps.size(), poses.size());
  EXPECT_EQ(steps[0].dt, 0.0);
  EXPECT_TRUE(steps[0].delta.isZero(0.0));
  for (std::size_t k = 1; k < poses.size(); ++k) {
    expect_pose_near(compose(poses[k - 1], steps[k].delta), poses[k], 1e-12);
    EXPECT_LE(std::abs(steps[k].delta[2]), kPi);
  }
  // Step 1: 0.5 m in 0.5 s, turning 0.2 rad; forward (the increment's x > 0): v > 0.
  EXPECT_DOUBLE_EQ(steps[1].dt, 0.5);
  EXPECT_NEAR(steps[1].v, 1.0, 1e-12);
  EXPECT_NEAR(steps[1].w, 0.4, 1e-12);
  // Step 2: backwards relative to the heading 0.7 (the increment's x < 0): v < 0; its turn
  // 2.4 rad over 1 s.
  EXPECT_LT(steps[2].delta[0], 0.0);
  EXPECT_NEAR(steps[2].v, -0.5, 1e-12);
  EXPECT_NEAR(steps[2].w, 2.4, 1e-12);
  // Steps 3 and 4: no time passes (equal stamps; a stamp going back is clamped to dt = 0):
  // the increment is kept, the rates are zero.
  for (std::size_t k : {3u, 4u}) {
    EXPECT_EQ(steps[k].dt, 0.0) << k;
    EXPECT_EQ(steps[k].v, 0.0) << k;
    EXPECT_EQ(steps[k].w, 0.0) << k;
    EXPECT_GT(steps[k].delta.head<2>().norm(), 0.0) << k;
  }
  EXPECT_NEAR(steps[3].delta[2], 2.0 * kPi - 6.2, 1e-12);  // across ±π, the short way
}

}  // namespace
}  // namespace vdtnav
