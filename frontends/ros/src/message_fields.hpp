#pragma once
// The fields of the messages vdtnav reads, in the order of their .msg definitions, over a reader
// of either wire format: ROS 1 serialization (ros1_serialization.cpp: packed little-endian,
// Header with seq, time as uint32 sec + nsec) and ROS 2 CDR (ros2_cdr.cpp: aligned, either
// endianness, Header without seq). The formats differ only in those primitives; the message layouts
// are the same, so one template decodes both.
//
// A Reader provides get<T>() for a primitive, str() for a string, header() for std_msgs/Header,
// length(min_element_bytes, field) for a sequence's length (refused when that many elements
// cannot fit in the bytes left, before anything is allocated), sequence(vector, field) for a
// sequence of primitives and array(std::array<double, N>) for a fixed float64 array.

#include <array>
#include <cstdint>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros::fields {

// geometry_msgs/Vector3 or Point: float64 x, y, z.
template <class Reader>
Eigen::Vector3d vector3(Reader& r) {
  Eigen::Vector3d v;
  v.x() = r.template get<double>();
  v.y() = r.template get<double>();
  v.z() = r.template get<double>();
  return v;
}

// geometry_msgs/Quaternion: float64 x, y, z, w.
template <class Reader>
Eigen::Quaterniond quaternion(Reader& r) {
  const double x = r.template get<double>(), y = r.template get<double>();
  const double z = r.template get<double>(), w = r.template get<double>();
  return Eigen::Quaterniond(w, x, y, z);
}

// geometry_msgs/Pose: Point position; Quaternion orientation.
template <class Reader>
PoseMsg pose(Reader& r) {
  PoseMsg p;
  p.position = vector3(r);
  p.orientation = quaternion(r);
  return p;
}

// geometry_msgs/PoseWithCovariance: Pose pose; float64[36] covariance.
template <class Reader>
PoseWithCovarianceMsg pose_with_covariance(Reader& r) {
  PoseWithCovarianceMsg p;
  p.pose = pose(r);
  r.array(p.covariance);
  return p;
}

// sensor_msgs/LaserScan: Header header; float32 angle_min, angle_max, angle_increment,
// time_increment, scan_time, range_min, range_max; float32[] ranges; float32[] intensities.
template <class Reader>
LaserScanMsg laser_scan(Reader& r) {
  LaserScanMsg s;
  s.header = r.header();
  s.angle_min = r.template get<float>();
  s.angle_max = r.template get<float>();
  s.angle_increment = r.template get<float>();
  s.time_increment = r.template get<float>();
  s.scan_time = r.template get<float>();
  s.range_min = r.template get<float>();
  s.range_max = r.template get<float>();
  r.sequence(s.ranges, "ranges");
  r.sequence(s.intensities, "intensities");
  return s;
}

// sensor_msgs/PointCloud2: Header header; uint32 height, width; PointField[] fields;
// bool is_bigendian; uint32 point_step, row_step; uint8[] data; bool is_dense.
// sensor_msgs/PointField: string name; uint32 offset; uint8 datatype; uint32 count.
template <class Reader>
PointCloud2Msg point_cloud2(Reader& r) {
  PointCloud2Msg c;
  c.header = r.header();
  c.height = r.template get<std::uint32_t>();
  c.width = r.template get<std::uint32_t>();
  // A PointField takes at least 13 bytes: name length, offset, datatype, count.
  c.fields.resize(r.length(13, "fields"));
  for (PointFieldMsg& f : c.fields) {
    f.name = r.str();
    f.offset = r.template get<std::uint32_t>();
    f.datatype = r.template get<std::uint8_t>();
    f.count = r.template get<std::uint32_t>();
  }
  c.is_bigendian = r.template get<std::uint8_t>() != 0;
  c.point_step = r.template get<std::uint32_t>();
  c.row_step = r.template get<std::uint32_t>();
  r.sequence(c.data, "data");
  c.is_dense = r.template get<std::uint8_t>() != 0;
  return c;
}

// nav_msgs/Odometry: Header header; string child_frame_id; PoseWithCovariance pose;
// TwistWithCovariance twist (Twist twist {Vector3 linear, Vector3 angular}; float64[36]).
template <class Reader>
OdometryMsg odometry(Reader& r) {
  OdometryMsg o;
  o.header = r.header();
  o.child_frame_id = r.str();
  o.pose = pose_with_covariance(r);
  o.twist.linear = vector3(r);
  o.twist.angular = vector3(r);
  r.array(o.twist.covariance);
  return o;
}

// tf2_msgs/TFMessage: geometry_msgs/TransformStamped[] transforms. TransformStamped: Header
// header; string child_frame_id; Transform transform {Vector3 translation; Quaternion rotation}.
template <class Reader>
TfMsg tf(Reader& r) {
  TfMsg tf;
  // A TransformStamped takes at least 72 bytes: stamp 8, two string lengths 8, 7 float64.
  tf.transforms.resize(r.length(72, "transforms"));
  for (TransformStampedMsg& t : tf.transforms) {
    t.header = r.header();
    t.child_frame_id = r.str();
    t.translation = vector3(r);
    t.rotation = quaternion(r);
  }
  return tf;
}

// geometry_msgs/PoseStamped: Header header; Pose pose.
template <class Reader>
PoseStampedMsg pose_stamped(Reader& r) {
  PoseStampedMsg p;
  p.header = r.header();
  p.pose = pose(r);
  return p;
}

// geometry_msgs/PoseWithCovarianceStamped: Header header; PoseWithCovariance pose.
template <class Reader>
PoseWithCovarianceStampedMsg pose_with_covariance_stamped(Reader& r) {
  PoseWithCovarianceStampedMsg p;
  p.header = r.header();
  p.pose = pose_with_covariance(r);
  return p;
}

// sensor_msgs/Imu: Header header; Quaternion orientation; float64[9] orientation_covariance;
// Vector3 angular_velocity; float64[9] angular_velocity_covariance; Vector3 linear_acceleration;
// float64[9] linear_acceleration_covariance.
template <class Reader>
ImuMsg imu(Reader& r) {
  ImuMsg i;
  i.header = r.header();
  i.orientation = quaternion(r);
  r.array(i.orientation_covariance);
  i.angular_velocity = vector3(r);
  r.array(i.angular_velocity_covariance);
  i.linear_acceleration = vector3(r);
  r.array(i.linear_acceleration_covariance);
  return i;
}

}  // namespace vdtnav::ros::fields
