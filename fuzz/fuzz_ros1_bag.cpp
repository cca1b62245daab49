// A ROS 1 bag (ros::BagReader::open on a .bag file, frontends/ros/src/ros1_bag.cpp) on fuzzed
// bytes: opened, every message read and decoded by its type. Only vdtnav::Error may come out.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_points.hpp"

namespace {

void decode(const vdtnav::ros::BagMessage& m) {
  using namespace vdtnav::ros;
  const std::string t = ros1_type_name(m.type);
  if (t == "sensor_msgs/LaserScan") (void)decode_laser_scan(m);
  if (t == "sensor_msgs/PointCloud2") (void)cloud_points(decode_point_cloud2(m), m.topic);
  if (t == "nav_msgs/Odometry") (void)decode_odometry(m);
  if (t == "tf2_msgs/TFMessage") (void)decode_tf(m);
  if (t == "geometry_msgs/PoseStamped") (void)decode_pose_stamped(m);
  if (t == "geometry_msgs/PoseWithCovarianceStamped") (void)decode_pose_with_covariance_stamped(m);
  if (t == "sensor_msgs/Imu") (void)decode_imu(m);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "fuzz.bag");
  try {
    const auto bag = vdtnav::ros::BagReader::open(path);
    bag->read({}, [](const vdtnav::ros::BagMessage& m) {
      try {
        decode(m);
      } catch (const vdtnav::Error&) {
      }
      return true;
    });
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
