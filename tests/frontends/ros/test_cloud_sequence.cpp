// read_cloud_sequence on a ROS 1 bag written here with rosbag::Bag, whose truth is known: a LiDAR
// mounted 1 m ahead and 0.5 m up (/tf_static), the robot driving along x at 1 m/s (/tf
// odom -> base_link), an IMU reporting roll 0.1 and pitch -0.05 rad, two clouds between the
// odometry stamps; the IMU's rates and accelerations come with every cloud.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_sequence.hpp"

namespace vdtnav::ros {
namespace {

namespace fs = std::filesystem;

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child,
                                          double t, double x, double z) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = ::ros::Time(t);
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = x;
  m.transform.translation.z = z;
  m.transform.rotation.w = 1.0;
  return m;
}

sensor_msgs::PointCloud2 cloud(double t) {
  sensor_msgs::PointCloud2 c;
  c.header.stamp = ::ros::Time(t);
  c.header.frame_id = "lidar";
  c.height = 1;
  c.width = 2;
  c.point_step = 12;
  c.row_step = 24;
  for (const auto& [name, offset] : {std::pair<const char*, int>{"x", 0}, {"y", 4}, {"z", 8}}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  const float xyz[6] = {3.0F, 0.0F, 0.0F, 0.0F, 4.0F, 1.0F};
  c.data.resize(24);
  std::memcpy(c.data.data(), xyz, sizeof xyz);
  return c;
}

fs::path write_bag() {
  const fs::path p =
      fs::temp_directory_path() / ("vdtnav_cloud_sequence_" + std::to_string(::getpid()) + ".bag");
  rosbag::Bag bag(p.string(), rosbag::bagmode::Write);
  tf2_msgs::TFMessage fixed;
  fixed.transforms.push_back(transform("base_link", "lidar", 100.0, 1.0, 0.5));
  bag.write("/tf_static", ::ros::Time(100.0), fixed);
  // roll 0.1, pitch -0.05 (R = Rz Ry Rx) as a quaternion.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  for (int k = 0; k <= 2; ++k) {
    const double t = 100.0 + k;
    tf2_msgs::TFMessage moving;
    moving.transforms.push_back(transform("odom", "base_link", t, k, 0.0));
    bag.write("/tf", ::ros::Time(t), moving);
    sensor_msgs::Imu imu;
    imu.header.stamp = ::ros::Time(t);
    imu.header.frame_id = "base_link";
    imu.orientation.x = q.x();
    imu.orientation.y = q.y();
    imu.orientation.z = q.z();
    imu.orientation.w = q.w();
    imu.angular_velocity.x = 0.01 * k;
    imu.angular_velocity.y = -0.02;
    imu.angular_velocity.z = 0.3;
    imu.linear_acceleration.x = 0.1 * k;
    imu.linear_acceleration.y = 0.2;
    imu.linear_acceleration.z = 9.8;
    bag.write("/imu", ::ros::Time(t), imu);
  }
  bag.write("/points", ::ros::Time(100.5), cloud(100.5));
  bag.write("/points", ::ros::Time(101.25), cloud(101.25));
  bag.close();
  return p;
}

TEST(CloudSequence, MountOdometryAndImuAtEachCloudsStamp) {
  const fs::path path = write_bag();
  const auto bag = BagReader::open(path.string());
  CloudSequenceOptions o;
  o.imu_topic = "/imu";
  std::vector<CloudFrame> frames;
  const CloudSequenceInfo info = read_cloud_sequence(*bag, o, [&](const CloudFrame& f) {
    frames.push_back(f);
    return true;
  });
  EXPECT_EQ(info.cloud_topic, "/points");
  EXPECT_EQ(info.odometry_source, "TF odom -> base_link");
  EXPECT_EQ(info.mount_source, "TF base_link -> lidar");
  ASSERT_EQ(frames.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    const CloudFrame& f = frames[k];
    const double t = k == 0 ? 100.5 : 101.25;
    EXPECT_NEAR(1e-9 * static_cast<double>(f.stamp_ns), t, 1e-9);
    EXPECT_EQ(f.frame, "lidar");
    EXPECT_NEAR((f.mount.translation() - Eigen::Vector3d(1.0, 0.0, 0.5)).norm(), 0.0, 1e-12);
    ASSERT_TRUE(f.odometry.has_value());
    EXPECT_NEAR(f.odometry->translation().x(), t - 100.0, 1e-9);  // 1 m/s, interpolated
    EXPECT_NEAR(f.roll, 0.1, 1e-9);
    EXPECT_NEAR(f.pitch, -0.05, 1e-9);
    ASSERT_EQ(f.cloud.points.size(), 2U);
    EXPECT_EQ(f.cloud.points[1], Eigen::Vector3d(0.0, 4.0, 1.0));
    // The IMU's rates and accelerations, every sample of the bag, for the preintegration.
    ASSERT_NE(f.imu, nullptr);
    ASSERT_EQ(f.imu->size(), 3U);
    for (int i = 0; i < 3; ++i) {
      const vdtnav::ImuSample& s = (*f.imu)[static_cast<std::size_t>(i)];
      EXPECT_NEAR(s.t, 100.0 + i, 1e-9);
      EXPECT_NEAR((s.gyro - Eigen::Vector3d(0.01 * i, -0.02, 0.3)).norm(), 0.0, 1e-12);
      EXPECT_NEAR((s.accel - Eigen::Vector3d(0.1 * i, 0.2, 9.8)).norm(), 0.0, 1e-12);
    }
  }
  // Without TF from base_link to the clouds' frame, --lidar-pose is asked for.
  CloudSequenceOptions other = o;
  other.base_frame = "chassis";
  try {
    (void)read_cloud_sequence(*bag, other, [](const CloudFrame&) { return true; });
    FAIL() << "no mounting";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--lidar-pose"), std::string::npos) << e.what();
  }
  fs::remove(path);
}

}  // namespace
}  // namespace vdtnav::ros
