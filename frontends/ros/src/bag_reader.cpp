// BagReader::open picks the format from what is on disk; decode_* dispatch on the message's.

#include "vdtnav/ros/bag_reader.hpp"

#include <filesystem>
#include <fstream>

#include "bag_formats.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros {

std::unique_ptr<BagReader> BagReader::open(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw IoError(path + ": no such file or folder");
  const fs::path p(path);
  if (fs::is_directory(p, ec) || p.filename() == "metadata.yaml" || p.extension() == ".db3" ||
      p.extension() == ".mcap") {
    return ros2::open(path);
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open");
  std::string magic(13, '\0');
  in.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (magic.rfind("#ROS", 0) == 0) return ros1::open(path);
  throw FormatError(path, 0,
                    "not a bag: expected a ROS 1 bag (starting '#ROSBAG V2.0') or a ROS 2 bag "
                    "folder with metadata.yaml");
}

std::string ros1_type_name(const std::string& type) {
  const std::string::size_type at = type.find("/msg/");
  return at == std::string::npos ? type : type.substr(0, at) + "/" + type.substr(at + 5);
}

#define VDTNAV_ROS_DISPATCH(Msg, fn) \
  Msg fn(const BagMessage& m) { return m.format == BagFormat::kRos1 ? ros1::fn(m) : ros2::fn(m); }
VDTNAV_ROS_DISPATCH(LaserScanMsg, decode_laser_scan)
VDTNAV_ROS_DISPATCH(PointCloud2Msg, decode_point_cloud2)
VDTNAV_ROS_DISPATCH(OdometryMsg, decode_odometry)
VDTNAV_ROS_DISPATCH(TfMsg, decode_tf)
VDTNAV_ROS_DISPATCH(PoseStampedMsg, decode_pose_stamped)
VDTNAV_ROS_DISPATCH(PoseWithCovarianceStampedMsg, decode_pose_with_covariance_stamped)
VDTNAV_ROS_DISPATCH(ImuMsg, decode_imu)
VDTNAV_ROS_DISPATCH(OccupancyGridMsg, decode_occupancy_grid)
#undef VDTNAV_ROS_DISPATCH

}  // namespace vdtnav::ros
