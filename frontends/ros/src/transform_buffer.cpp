// TransformBuffer: tf2::BufferCore holding a bag's transforms; lookups at a stamp interpolate
// (tf2: linear in translation, slerp in rotation, between the two transforms around the stamp).

#include "vdtnav/ros/transform_buffer.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>

#include "vdtnav/core/error.hpp"

namespace vdtnav::ros {

namespace {

::ros::Time ros_time(std::int64_t ns) {
  ::ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(std::max<std::int64_t>(ns, 0)));
  return t;
}

std::string stamp_text(std::int64_t ns) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f s", static_cast<double>(ns) * 1e-9);
  return buf;
}

}  // namespace

struct TransformBuffer::Impl {
  explicit Impl(double span) : core(::ros::Duration(span)) {}
  tf2::BufferCore core;
  std::map<std::string, std::string> parent;  // child -> parent, as last seen
};

TransformBuffer::TransformBuffer(double span_seconds)
    : impl_(std::make_unique<Impl>(span_seconds)) {}
TransformBuffer::~TransformBuffer() = default;
TransformBuffer::TransformBuffer(TransformBuffer&&) noexcept = default;
TransformBuffer& TransformBuffer::operator=(TransformBuffer&&) noexcept = default;

std::string strip_slash(const std::string& frame) {
  return !frame.empty() && frame.front() == '/' ? frame.substr(1) : frame;
}

Pose3 to_pose3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Pose3 p = Pose3::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = t;
  return p;
}

void TransformBuffer::add(const TransformStampedMsg& t, bool is_static) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = ros_time(t.header.stamp_ns);
  m.header.frame_id = strip_slash(t.header.frame_id);
  m.child_frame_id = strip_slash(t.child_frame_id);
  if (m.header.frame_id.empty() || m.child_frame_id.empty() ||
      m.header.frame_id == m.child_frame_id) {
    return;  // tf2 refuses these; so does every ROS consumer
  }
  m.transform.translation.x = t.translation.x();
  m.transform.translation.y = t.translation.y();
  m.transform.translation.z = t.translation.z();
  const Eigen::Quaterniond q = t.rotation.normalized();
  m.transform.rotation.x = q.x();
  m.transform.rotation.y = q.y();
  m.transform.rotation.z = q.z();
  m.transform.rotation.w = q.w();
  if (impl_->core.setTransform(m, "bag", is_static)) {
    impl_->parent[m.child_frame_id] = m.header.frame_id;
  }
}

void TransformBuffer::add(const TfMsg& tf, bool is_static) {
  for (const TransformStampedMsg& t : tf.transforms) add(t, is_static);
}

void TransformBuffer::add(const OdometryMsg& odom) {
  TransformStampedMsg t;
  t.header = odom.header;
  t.child_frame_id = odom.child_frame_id;
  t.translation = odom.pose.pose.position;
  t.rotation = odom.pose.pose.orientation;
  add(t, false);
}

bool TransformBuffer::can_lookup(const std::string& parent, const std::string& child,
                                 std::int64_t stamp_ns) const {
  return impl_->core.canTransform(strip_slash(parent), strip_slash(child), ros_time(stamp_ns));
}

bool TransformBuffer::connected(const std::string& parent, const std::string& child) const {
  // Time 0 asks for the latest common time: true when a chain joins them at all.
  return impl_->core.canTransform(strip_slash(parent), strip_slash(child), ::ros::Time(0));
}

Pose3 TransformBuffer::lookup(const std::string& parent, const std::string& child,
                              std::int64_t stamp_ns) const {
  try {
    const geometry_msgs::TransformStamped m =
        impl_->core.lookupTransform(strip_slash(parent), strip_slash(child), ros_time(stamp_ns));
    const auto& tr = m.transform.translation;
    const auto& q = m.transform.rotation;
    return to_pose3(Eigen::Vector3d(tr.x, tr.y, tr.z), Eigen::Quaterniond(q.w, q.x, q.y, q.z));
  } catch (const tf2::TransformException& e) {
    throw ConfigError("no transform " + strip_slash(parent) + " -> " + strip_slash(child) + " at " +
                      stamp_text(stamp_ns) + " (" + e.what() + "); the frames: " + describe());
  }
}

std::optional<std::int64_t> TransformBuffer::latest_stamp(const std::string& parent,
                                                          const std::string& child) const {
  try {
    // Time 0: tf2 answers at the latest time the whole chain is known, and stamps it so.
    const geometry_msgs::TransformStamped m =
        impl_->core.lookupTransform(strip_slash(parent), strip_slash(child), ::ros::Time(0));
    return static_cast<std::int64_t>(m.header.stamp.toNSec());
  } catch (const tf2::TransformException&) {
    return std::nullopt;
  }
}

std::vector<std::pair<std::string, std::string>> TransformBuffer::frames() const {
  std::set<std::string> all;
  for (const auto& [c, p] : impl_->parent) {
    all.insert(c);
    all.insert(p);
  }
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& f : all) {
    const auto it = impl_->parent.find(f);
    out.emplace_back(f, it == impl_->parent.end() ? std::string() : it->second);
  }
  return out;
}

std::string TransformBuffer::describe() const {
  const auto f = frames();
  if (f.empty()) return "none";
  std::string s;
  for (const auto& [child, parent] : f) {
    if (parent.empty()) continue;
    if (!s.empty()) s += ", ";
    s += parent + " -> " + child;
  }
  return s.empty() ? "none" : s;
}

}  // namespace vdtnav::ros
