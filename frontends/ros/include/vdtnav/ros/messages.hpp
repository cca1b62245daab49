#pragma once
/// \file
/// \brief The ROS messages vdtnav reads and writes, as plain structs (no ROS type): the fields of
/// sensor_msgs, nav_msgs, geometry_msgs and tf2_msgs that a localizer needs, decoded from either
/// bag format (bag_reader.hpp) and encoded as ROS 2 CDR (cdr_writer.hpp). The same structs serve
/// a ROS 1 or ROS 2 node.
///
/// Times are nanoseconds since the epoch (ROS 1 time: sec * 1e9 + nsec; ROS 2's builtin
/// Time likewise). Orientations are unit quaternions (x, y, z, w as ROS writes them).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vdtnav::ros {

/// \brief std_msgs/Header (ROS 1's seq is read and dropped).
struct Header {
  std::int64_t stamp_ns = 0;
  std::string frame_id;
};

/// \brief sensor_msgs/LaserScan.
struct LaserScanMsg {
  Header header;
  float angle_min = 0.0F, angle_max = 0.0F, angle_increment = 0.0F;
  float time_increment = 0.0F, scan_time = 0.0F;
  float range_min = 0.0F, range_max = 0.0F;
  std::vector<float> ranges, intensities;
};

/// \brief sensor_msgs/PointField.
struct PointFieldMsg {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype =
      0;  ///< 1 INT8, 2 UINT8, 3 INT16, 4 UINT16, 5 INT32, 6 UINT32, 7 FLOAT32, 8 FLOAT64
  std::uint32_t count = 0;
};

/// \brief sensor_msgs/PointCloud2 (data as recorded; decode with cloud_observations.hpp).
struct PointCloud2Msg {
  Header header;
  std::uint32_t height = 0, width = 0;
  std::vector<PointFieldMsg> fields;
  bool is_bigendian = false;
  std::uint32_t point_step = 0, row_step = 0;
  std::vector<std::uint8_t> data;
  bool is_dense = false;
};

/// \brief geometry_msgs/Pose.
struct PoseMsg {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// \brief geometry_msgs/PoseWithCovariance (covariance row-major over x, y, z, rotX, rotY, rotZ).
struct PoseWithCovarianceMsg {
  PoseMsg pose;
  std::array<double, 36> covariance{};
};

/// \brief geometry_msgs/Twist (with covariance, as in nav_msgs/Odometry).
struct TwistWithCovarianceMsg {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
  std::array<double, 36> covariance{};
};

/// \brief nav_msgs/Odometry.
struct OdometryMsg {
  Header header;
  std::string child_frame_id;
  PoseWithCovarianceMsg pose;
  TwistWithCovarianceMsg twist;
};

/// \brief geometry_msgs/PoseStamped.
struct PoseStampedMsg {
  Header header;
  PoseMsg pose;
};

/// \brief geometry_msgs/PoseWithCovarianceStamped.
struct PoseWithCovarianceStampedMsg {
  Header header;
  PoseWithCovarianceMsg pose;
};

/// \brief geometry_msgs/TransformStamped: the pose of child_frame_id in header.frame_id.
struct TransformStampedMsg {
  Header header;
  std::string child_frame_id;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

/// \brief tf2_msgs/TFMessage.
struct TfMsg {
  std::vector<TransformStampedMsg> transforms;
};

/// \brief sensor_msgs/Imu (covariances row-major; element 0 = -1 means "not given").
struct ImuMsg {
  Header header;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::array<double, 9> orientation_covariance{};
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  std::array<double, 9> angular_velocity_covariance{};
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();
  std::array<double, 9> linear_acceleration_covariance{};
};

/// \brief nav_msgs/MapMetaData: where a grid lies and how fine it is.
struct MapMetaDataMsg {
  std::int64_t map_load_time_ns = 0;
  float resolution = 0.0F;              ///< m/cell
  std::uint32_t width = 0, height = 0;  ///< cells
  /// The pose of cell (0, 0)'s corner in header.frame_id.
  PoseMsg origin;
};

/// \brief nav_msgs/OccupancyGrid (data row-major from cell (0, 0): occupancy 0..100, -1 unknown).
struct OccupancyGridMsg {
  Header header;
  MapMetaDataMsg info;
  std::vector<std::int8_t> data;
};

}  // namespace vdtnav::ros
