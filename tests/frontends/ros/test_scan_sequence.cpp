// The ROS-free half of vdtnav::ros: LaserScan messages as scans (beam geometry of either sign,
// invalid readings dropped) and the transform buffer's interpolation and chaining, against
// values computed here by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/scan_sequence.hpp"
#include "vdtnav/ros/transform_buffer.hpp"

namespace vdtnav::ros {
namespace {

constexpr std::int64_t kSecond = 1000000000;

TEST(ToLaserScan, BeamsOfANegativeIncrementLandWhereTheMessageSaysAndInvalidOnesAreDropped) {
  LaserScanMsg m;
  m.header.stamp_ns = 12 * kSecond + 500000000;
  m.angle_min = 1.5F;
  m.angle_increment = -0.5F;  // a scanner mounted upside down: beams run clockwise
  m.angle_max = 1.5F - 0.5F * 6;
  m.range_min = 0.2F;
  m.range_max = 10.0F;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  m.ranges = {1.0F, nan, 0.0F, 0.1F, 11.0F, inf, 2.0F};
  const Pose2 mount(0.3, -0.1, 0.25);
  const LaserScan s = to_laser_scan(m, mount, 0.03, std::nan(""));
  EXPECT_DOUBLE_EQ(s.time, 12.5);
  EXPECT_DOUBLE_EQ(s.sigma_range, 0.03);
  const ScanPoints p = scan_points(s);
  ASSERT_EQ(p.size(), 2U);                // beams 0 and 6
  EXPECT_EQ(p.dropped_not_finite, 2U);    // NaN, inf
  EXPECT_EQ(p.dropped_out_of_range, 3U);  // 0, below range_min, above range_max
  // Beam 6 at 1.5 - 3 = -1.5 rad in the sensor frame, 2 m, then the mounting (x, y, yaw).
  for (const auto& [beam, range] : {std::pair<std::size_t, double>{0, 1.0}, {6, 2.0}}) {
    const double a = 1.5 - 0.5 * static_cast<double>(beam);
    const double c = std::cos(mount[2]), sn = std::sin(mount[2]);
    const Eigen::Vector2d in_sensor(range * std::cos(a), range * std::sin(a));
    const Eigen::Vector2d expected(mount[0] + c * in_sensor.x() - sn * in_sensor.y(),
                                   mount[1] + sn * in_sensor.x() + c * in_sensor.y());
    const std::size_t k = beam == 0 ? 0 : 1;
    EXPECT_EQ(p.beam[k], beam);
    EXPECT_NEAR((p.points[k] - expected).norm(), 0.0, 1e-6) << beam;
  }
  // --max-range below the message's: 2 m is then a no-return.
  EXPECT_EQ(scan_points(to_laser_scan(m, mount, 0.03, 2.0)).size(), 1U);
}

TEST(ToLaserScan, AZeroRangeMinStillDropsZeroReadings) {
  LaserScanMsg m;
  m.angle_increment = 0.1F;
  m.range_min = 0.0F;
  m.range_max = 5.0F;
  m.ranges = {0.0F, 1.0F};
  EXPECT_EQ(scan_points(to_laser_scan(m, Pose2::Zero(), 0.02, std::nan(""))).size(), 1U);
}

TransformStampedMsg transform(const std::string& parent, const std::string& child, double t,
                              const Eigen::Vector3d& xyz, double yaw) {
  TransformStampedMsg m;
  m.header.frame_id = parent;
  m.header.stamp_ns = static_cast<std::int64_t>(std::llround(t * 1e9));
  m.child_frame_id = child;
  m.translation = xyz;
  m.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return m;
}

TEST(TransformBuffer, InterpolatesBetweenStampsAndChainsAStaticMount) {
  TransformBuffer tf(100.0);
  TfMsg moving;
  moving.transforms = {transform("odom", "base_link", 10.0, {0.0, 0.0, 0.0}, 0.0),
                       transform("odom", "base_link", 11.0, {1.0, 2.0, 0.0}, 0.4)};
  tf.add(moving, false);
  tf.add(transform("/base_link", "/laser", 0.0, {0.2, 0.0, 0.1}, kPi / 2), true);
  // A tree that does not touch the robot's frames.
  tf.add(transform("world", "camera", 10.0, {5.0, 5.0, 0.0}, 0.0), true);

  const std::int64_t t = 10 * kSecond + 250000000;  // a quarter of the way
  const Pose3 base = tf.lookup("odom", "base_link", t);
  EXPECT_NEAR(base.translation().x(), 0.25, 1e-9);
  EXPECT_NEAR(base.translation().y(), 0.5, 1e-9);
  EXPECT_NEAR(planar(base)[2], 0.1, 1e-9);  // slerp about one axis: linear in the angle
  // odom -> laser = odom -> base (at t) * base -> laser (static), frames given with '/'.
  const Pose3 laser = tf.lookup("/odom", "laser", t);
  const Pose3 expected =
      base * to_pose3(Eigen::Vector3d(0.2, 0.0, 0.1),
                      Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ())));
  EXPECT_NEAR((laser.matrix() - expected.matrix()).norm(), 0.0, 1e-9);

  EXPECT_TRUE(tf.connected("odom", "laser"));
  EXPECT_FALSE(tf.connected("odom", "camera"));
  EXPECT_FALSE(tf.can_lookup("odom", "base_link", 12 * kSecond));  // after the last stamp
  try {
    (void)tf.lookup("odom", "camera", t);
    FAIL() << "a lookup across two trees must throw";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("odom -> camera"), std::string::npos) << what;
    EXPECT_NE(what.find("base_link -> laser"), std::string::npos) << what;  // the frames held
    EXPECT_NE(what.find("world -> camera"), std::string::npos) << what;
  }
}

TEST(TransformBuffer, OdometryMessagesAreTheirFramesTransforms) {
  TransformBuffer tf(100.0);
  OdometryMsg o;
  o.header.frame_id = "odom";
  o.child_frame_id = "base_footprint";
  for (int k = 0; k < 3; ++k) {
    o.header.stamp_ns = k * kSecond;
    o.pose.pose.position = Eigen::Vector3d(k, -k, 0.0);
    o.pose.pose.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d::UnitZ()));
    tf.add(o);
  }
  const Pose2 p = planar(tf.lookup("odom", "base_footprint", kSecond + kSecond / 2));
  EXPECT_NEAR(p[0], 1.5, 1e-9);
  EXPECT_NEAR(p[1], -1.5, 1e-9);
  EXPECT_NEAR(p[2], 0.45, 1e-9);
}

}  // namespace
}  // namespace vdtnav::ros
