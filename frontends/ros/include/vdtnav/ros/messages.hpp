#pragma once
/// \file
/// \brief The ROS messages vdtnav reads and writes, as plain structs (no ROS type): the fields of
/// sensor_msgs, nav_msgs, geometry_msgs and tf2_msgs that a localizer needs, decoded from either
/// bag format (bag_reader.hpp) and encoded as ROS 2 CDR (cdr_writer.hpp); and the
/// lifecycle_msgs, bond, std_srvs and nav2_msgs messages and services a ROS 2 node answers nav2's
/// lifecycle manager and amcl's clients with, encoded and decoded as ROS 2 CDR (cdr_writer.hpp,
/// cdr_reader.hpp). The same structs serve a ROS 1 or ROS 2 node.
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

/// \brief lifecycle_msgs/Transition: a transition of a managed node (id: lifecycle_ids.hpp's
/// kTransition*; label as rcl_lifecycle names it, "configure", "activate", ...).
struct LifecycleTransitionMsg {
  std::uint8_t id = 0;
  std::string label;
};

/// \brief lifecycle_msgs/State: a state of a managed node (id: lifecycle_ids.hpp's
/// kPrimaryState* and kTransitionState*; label as rcl_lifecycle names it, "inactive", ...).
struct LifecycleStateMsg {
  std::uint8_t id = 0;
  std::string label;
};

/// \brief lifecycle_msgs/ChangeState's request: the transition the lifecycle manager asks for.
struct ChangeStateRequestMsg {
  LifecycleTransitionMsg transition;
};

/// \brief lifecycle_msgs/ChangeState's response: whether the transition was carried out.
struct ChangeStateResponseMsg {
  bool success = false;
};

/// \brief lifecycle_msgs/GetState's response (its request is an EmptyMsg).
struct GetStateResponseMsg {
  LifecycleStateMsg current_state;
};

/// \brief lifecycle_msgs/TransitionEvent: published on <node>/transition_event after each
/// transition.
struct TransitionEventMsg {
  std::uint64_t timestamp = 0;  ///< the event's time as its publisher stamps it (uint64)
  LifecycleTransitionMsg transition;
  LifecycleStateMsg start_state, goal_state;
};

/// \brief bond/Status: the heartbeat each side of a bond (nav2's lifecycle manager and a managed
/// node) publishes on /bond.
struct BondStatusMsg {
  Header header;
  std::string id;           ///< the bond's id (nav2: the node's name)
  std::string instance_id;  ///< this side's unique id within the bond
  bool active = false;
  float heartbeat_timeout = 0.0F, heartbeat_period = 0.0F;  ///< s
};

/// \brief Any message, request or response without fields: lifecycle_msgs/GetState's request,
/// std_srvs/Empty's request and response, nav2_msgs/SetInitialPose's response. ROS 2 still sends
/// one byte for it: rosidl gives every empty structure the member `uint8
/// structure_needs_at_least_one_member` (value 0), since an IDL struct needs a member
/// (cdr_writer.hpp).
struct EmptyMsg {};

/// \brief nav2_msgs/SetInitialPose's request (amcl's set_initial_pose service; the response is
/// an EmptyMsg).
struct SetInitialPoseRequestMsg {
  PoseWithCovarianceStampedMsg pose;
};

}  // namespace vdtnav::ros
