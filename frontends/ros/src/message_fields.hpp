#pragma once
// The fields of the messages vdtnav reads and writes, in the order of their .msg definitions,
// written once over an Io of any wire format: the readers of ROS 1 serialization
// (ros1_serialization.cpp: packed little-endian, Header with seq, time as uint32 sec + nsec) and
// ROS 2 CDR (ros2_cdr.cpp: aligned, either endianness, Header without seq), and the ROS 2 CDR
// writer (cdr_writer.cpp). The formats differ only in those primitives; the message layouts are
// the same, so one template decodes both and encodes CDR.
//
// An Io reads (Io::kWrites false: each call fills its argument in) or writes (kWrites true: the
// message is const, each call serializes its argument), with the same calls: value(x) for a
// primitive (bool travels as uint8), str(s) for a string, time(ns) for builtin time, header(h) for
// std_msgs/Header, sequence(v, field) for a sequence of primitives, size(v, min_element_bytes,
// field) for the length of a sequence of messages (a reader resizes v, refusing a length whose
// elements cannot fit in the bytes left before anything is allocated; a writer writes v.size()),
// and array(a) for a fixed float64 array.
//
// The lifecycle_msgs, bond, std_srvs and nav2_msgs layouts (from lifecycle_transition on) are
// instantiated by the ROS 2 CDR reader and writer only; they call nothing else than the ones
// above, so any Io would do.

#include <array>
#include <cstdint>
#include <type_traits>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros::fields {

/// A message or field as an Io sees it: const when it writes, filled in when it reads.
template <class Io, class T>
using Field = std::conditional_t<Io::kWrites, const T, T>;

// geometry_msgs/Vector3 or Point: float64 x, y, z.
template <class Io>
void vector3(Io& io, Field<Io, Eigen::Vector3d>& v) {
  io.value(v.x());
  io.value(v.y());
  io.value(v.z());
}

// geometry_msgs/Quaternion: float64 x, y, z, w.
template <class Io>
void quaternion(Io& io, Field<Io, Eigen::Quaterniond>& q) {
  io.value(q.x());
  io.value(q.y());
  io.value(q.z());
  io.value(q.w());
}

// geometry_msgs/Pose: Point position; Quaternion orientation.
template <class Io>
void pose(Io& io, Field<Io, PoseMsg>& p) {
  vector3(io, p.position);
  quaternion(io, p.orientation);
}

// geometry_msgs/PoseWithCovariance: Pose pose; float64[36] covariance.
template <class Io>
void pose_with_covariance(Io& io, Field<Io, PoseWithCovarianceMsg>& p) {
  pose(io, p.pose);
  io.array(p.covariance);
}

// sensor_msgs/LaserScan: Header header; float32 angle_min, angle_max, angle_increment,
// time_increment, scan_time, range_min, range_max; float32[] ranges; float32[] intensities.
template <class Io>
void laser_scan(Io& io, Field<Io, LaserScanMsg>& s) {
  io.header(s.header);
  io.value(s.angle_min);
  io.value(s.angle_max);
  io.value(s.angle_increment);
  io.value(s.time_increment);
  io.value(s.scan_time);
  io.value(s.range_min);
  io.value(s.range_max);
  io.sequence(s.ranges, "ranges");
  io.sequence(s.intensities, "intensities");
}

// sensor_msgs/PointCloud2: Header header; uint32 height, width; PointField[] fields;
// bool is_bigendian; uint32 point_step, row_step; uint8[] data; bool is_dense.
// sensor_msgs/PointField: string name; uint32 offset; uint8 datatype; uint32 count.
template <class Io>
void point_cloud2(Io& io, Field<Io, PointCloud2Msg>& c) {
  io.header(c.header);
  io.value(c.height);
  io.value(c.width);
  // A PointField takes at least 13 bytes: name length, offset, datatype, count.
  io.size(c.fields, 13, "fields");
  for (auto& f : c.fields) {
    io.str(f.name);
    io.value(f.offset);
    io.value(f.datatype);
    io.value(f.count);
  }
  io.value(c.is_bigendian);
  io.value(c.point_step);
  io.value(c.row_step);
  io.sequence(c.data, "data");
  io.value(c.is_dense);
}

// nav_msgs/Odometry: Header header; string child_frame_id; PoseWithCovariance pose;
// TwistWithCovariance twist (Twist twist {Vector3 linear, Vector3 angular}; float64[36]).
template <class Io>
void odometry(Io& io, Field<Io, OdometryMsg>& o) {
  io.header(o.header);
  io.str(o.child_frame_id);
  pose_with_covariance(io, o.pose);
  vector3(io, o.twist.linear);
  vector3(io, o.twist.angular);
  io.array(o.twist.covariance);
}

// tf2_msgs/TFMessage: geometry_msgs/TransformStamped[] transforms. TransformStamped: Header
// header; string child_frame_id; Transform transform {Vector3 translation; Quaternion rotation}.
template <class Io>
void tf(Io& io, Field<Io, TfMsg>& m) {
  // A TransformStamped takes at least 72 bytes: stamp 8, two string lengths 8, 7 float64.
  io.size(m.transforms, 72, "transforms");
  for (auto& t : m.transforms) {
    io.header(t.header);
    io.str(t.child_frame_id);
    vector3(io, t.translation);
    quaternion(io, t.rotation);
  }
}

// geometry_msgs/PoseStamped: Header header; Pose pose.
template <class Io>
void pose_stamped(Io& io, Field<Io, PoseStampedMsg>& p) {
  io.header(p.header);
  pose(io, p.pose);
}

// geometry_msgs/PoseWithCovarianceStamped: Header header; PoseWithCovariance pose.
template <class Io>
void pose_with_covariance_stamped(Io& io, Field<Io, PoseWithCovarianceStampedMsg>& p) {
  io.header(p.header);
  pose_with_covariance(io, p.pose);
}

// sensor_msgs/Imu: Header header; Quaternion orientation; float64[9] orientation_covariance;
// Vector3 angular_velocity; float64[9] angular_velocity_covariance; Vector3 linear_acceleration;
// float64[9] linear_acceleration_covariance.
template <class Io>
void imu(Io& io, Field<Io, ImuMsg>& i) {
  io.header(i.header);
  quaternion(io, i.orientation);
  io.array(i.orientation_covariance);
  vector3(io, i.angular_velocity);
  io.array(i.angular_velocity_covariance);
  vector3(io, i.linear_acceleration);
  io.array(i.linear_acceleration_covariance);
}

// nav_msgs/MapMetaData: time map_load_time; float32 resolution; uint32 width; uint32 height;
// geometry_msgs/Pose origin.
template <class Io>
void map_meta_data(Io& io, Field<Io, MapMetaDataMsg>& m) {
  io.time(m.map_load_time_ns);
  io.value(m.resolution);
  io.value(m.width);
  io.value(m.height);
  pose(io, m.origin);
}

// nav_msgs/OccupancyGrid: Header header; MapMetaData info; int8[] data.
template <class Io>
void occupancy_grid(Io& io, Field<Io, OccupancyGridMsg>& g) {
  io.header(g.header);
  map_meta_data(io, g.info);
  io.sequence(g.data, "data");
}

// lifecycle_msgs/Transition: uint8 id; string label.
template <class Io>
void lifecycle_transition(Io& io, Field<Io, LifecycleTransitionMsg>& t) {
  io.value(t.id);
  io.str(t.label);
}

// lifecycle_msgs/State: uint8 id; string label.
template <class Io>
void lifecycle_state(Io& io, Field<Io, LifecycleStateMsg>& s) {
  io.value(s.id);
  io.str(s.label);
}

// lifecycle_msgs/ChangeState_Request: Transition transition.
template <class Io>
void change_state_request(Io& io, Field<Io, ChangeStateRequestMsg>& r) {
  lifecycle_transition(io, r.transition);
}

// lifecycle_msgs/ChangeState_Response: bool success.
template <class Io>
void change_state_response(Io& io, Field<Io, ChangeStateResponseMsg>& r) {
  io.value(r.success);
}

// lifecycle_msgs/GetState_Response: State current_state.
template <class Io>
void get_state_response(Io& io, Field<Io, GetStateResponseMsg>& r) {
  lifecycle_state(io, r.current_state);
}

// lifecycle_msgs/TransitionEvent: uint64 timestamp; Transition transition; State start_state;
// State goal_state.
template <class Io>
void transition_event(Io& io, Field<Io, TransitionEventMsg>& e) {
  io.value(e.timestamp);
  lifecycle_transition(io, e.transition);
  lifecycle_state(io, e.start_state);
  lifecycle_state(io, e.goal_state);
}

// bond/Status: Header header; string id; string instance_id; bool active;
// float32 heartbeat_timeout; float32 heartbeat_period.
template <class Io>
void bond_status(Io& io, Field<Io, BondStatusMsg>& b) {
  io.header(b.header);
  io.str(b.id);
  io.str(b.instance_id);
  io.value(b.active);
  io.value(b.heartbeat_timeout);
  io.value(b.heartbeat_period);
}

// A message, request or response without fields (std_srvs/Empty_Request, ...): rosidl generates
// it with the one member uint8 structure_needs_at_least_one_member, 0 when written, ignored when
// read (rosidl_adapter's struct.idl.em, for a .msg or .srv part with no fields;
// rosidl_parser.definition.EMPTY_STRUCTURE_REQUIRED_MEMBER_NAME).
template <class Io>
void empty(Io& io, Field<Io, EmptyMsg>& /*m*/) {
  std::uint8_t structure_needs_at_least_one_member = 0;
  io.value(structure_needs_at_least_one_member);
}

// nav2_msgs/SetInitialPose_Request: geometry_msgs/PoseWithCovarianceStamped pose.
template <class Io>
void set_initial_pose_request(Io& io, Field<Io, SetInitialPoseRequestMsg>& r) {
  pose_with_covariance_stamped(io, r.pose);
}

}  // namespace vdtnav::ros::fields
