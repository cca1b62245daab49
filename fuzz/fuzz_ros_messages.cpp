// The message decoders of both bag formats (ROS 1 serialization, ROS 2 CDR) and cloud_points on
// fuzzed bytes: the first byte picks the format and the message type, the rest is the message.
// Only vdtnav::Error may come out.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_points.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using namespace vdtnav::ros;
  static const char* const kTypes[] = {"sensor_msgs/LaserScan",
                                       "sensor_msgs/PointCloud2",
                                       "nav_msgs/Odometry",
                                       "tf2_msgs/TFMessage",
                                       "geometry_msgs/PoseStamped",
                                       "geometry_msgs/PoseWithCovarianceStamped",
                                       "sensor_msgs/Imu"};
  BagMessage m;
  m.format = (data[0] & 0x80) != 0 ? BagFormat::kRos2 : BagFormat::kRos1;
  const int kind = (data[0] & 0x7F) % 7;
  m.type = kTypes[kind];
  m.topic = "/fuzz";
  m.data.assign(data + 1, data + size);
  try {
    switch (kind) {
      case 0:
        (void)decode_laser_scan(m);
        break;
      case 1:
        (void)cloud_points(decode_point_cloud2(m), m.topic);
        break;
      case 2:
        (void)decode_odometry(m);
        break;
      case 3:
        (void)decode_tf(m);
        break;
      case 4:
        (void)decode_pose_stamped(m);
        break;
      case 5:
        (void)decode_pose_with_covariance_stamped(m);
        break;
      default:
        (void)decode_imu(m);
        break;
    }
  } catch (const vdtnav::Error&) {
  }
  return 0;
}
