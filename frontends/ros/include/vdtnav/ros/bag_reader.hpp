#pragma once
/// \file
/// \brief Reading ROS bags, both formats, behind one interface: ROS 1 bags v2.0 (through
/// Debian's rosbag_storage; chunks none, bz2, lz4) and ROS 2 bags (a folder with metadata.yaml
/// and sqlite3 .db3 files, CDR messages decoded with Fast CDR). Messages come out serialized;
/// decode() turns the ones vdtnav uses into the structs of messages.hpp.
///
/// Errors: a file that is not a bag, an older format (`#ROSRECORD V1.2`), `.mcap` storage, an
/// unknown compression or a truncated file throws FormatError naming the file and what was
/// expected; a message of another type than asked throws FormatError naming topic and type.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

enum class BagFormat { kRos1, kRos2 };

/// \brief One topic of a bag, as `rosbag info` / `ros2 bag info` list it.
struct BagTopic {
  std::string name;
  std::string type;  ///< ROS 1 spelling "sensor_msgs/LaserScan"; ROS 2 "sensor_msgs/msg/LaserScan"
  std::size_t count = 0;
  std::int64_t first_ns = 0, last_ns = 0;  ///< recorded (receive) times
};

/// \brief One message as stored: its topic, type, receive time and serialized bytes (ROS 1
/// serialization, or CDR with its 4-byte encapsulation header for ROS 2).
struct BagMessage {
  BagFormat format = BagFormat::kRos1;
  std::string topic;
  std::string type;  ///< as in BagTopic::type
  std::int64_t recorded_ns = 0;
  std::vector<std::uint8_t> data;
};

/// \brief A bag opened for reading.
class BagReader {
 public:
  virtual ~BagReader() = default;

  /// \brief Opens a ROS 1 bag file or a ROS 2 bag folder (or its metadata.yaml / .db3 file).
  [[nodiscard]] static std::unique_ptr<BagReader> open(const std::string& path);

  [[nodiscard]] virtual BagFormat format() const noexcept = 0;
  /// \return the path given to open().
  [[nodiscard]] virtual const std::string& path() const noexcept = 0;
  /// \return every topic with its message count and time span, sorted by name.
  [[nodiscard]] virtual const std::vector<BagTopic>& topics() const noexcept = 0;
  /// \return the bag's size on disk in bytes (all its files).
  [[nodiscard]] virtual std::uint64_t size_bytes() const = 0;

  /// \brief Calls visit on every message of the given topics (all when empty), in order of
  /// recorded time; stops early when visit returns false.
  virtual void read(const std::vector<std::string>& topics,
                    const std::function<bool(const BagMessage&)>& visit) const = 0;
};

/// \brief Decoders: throw FormatError when the message's type is not the one asked or its bytes
/// do not hold it (the message names the topic, the type and the bag time).
[[nodiscard]] LaserScanMsg decode_laser_scan(const BagMessage& m);
[[nodiscard]] PointCloud2Msg decode_point_cloud2(const BagMessage& m);
[[nodiscard]] OdometryMsg decode_odometry(const BagMessage& m);
[[nodiscard]] TfMsg decode_tf(const BagMessage& m);
[[nodiscard]] PoseStampedMsg decode_pose_stamped(const BagMessage& m);
[[nodiscard]] PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m);
[[nodiscard]] ImuMsg decode_imu(const BagMessage& m);
[[nodiscard]] OccupancyGridMsg decode_occupancy_grid(const BagMessage& m);

/// \return the type name in ROS 1 spelling ("sensor_msgs/msg/LaserScan" ->
/// "sensor_msgs/LaserScan").
[[nodiscard]] std::string ros1_type_name(const std::string& type);

}  // namespace vdtnav::ros
