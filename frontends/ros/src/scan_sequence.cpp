// read_scan_sequence: a bag's LaserScan topic with odometry and mounting from TF or topics
// (scan_sequence.hpp says which, in what order).

#include "vdtnav/ros/scan_sequence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "topics.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/transform_buffer.hpp"

namespace vdtnav::ros {

using detail::list_topics;
using detail::pick_topic;
using detail::span_seconds;
using detail::tf_topics_of;

Pose2 planar(const Pose3& p) {
  const Eigen::Matrix3d& r = p.linear();
  return Pose2(p.translation().x(), p.translation().y(), std::atan2(r(1, 0), r(0, 0)));
}

LaserScan to_laser_scan(const LaserScanMsg& m, const Pose2& mount, double sigma_range,
                        double max_range) {
  LaserScan s;
  s.time = static_cast<double>(m.header.stamp_ns) * 1e-9;
  s.angle_min = m.angle_min;
  s.angle_increment = m.angle_increment;
  s.ranges.assign(m.ranges.begin(), m.ranges.end());
  // [range_min, range_max] are the valid readings (sensor_msgs/LaserScan); 0 is no reading.
  s.range_min = std::max(static_cast<double>(m.range_min), 1e-6);
  const double msg_max = std::isfinite(m.range_max) && m.range_max > 0.0F
                             ? static_cast<double>(m.range_max)
                             : std::numeric_limits<double>::infinity();
  s.range_max = std::isnan(max_range) ? msg_max : std::min(max_range, msg_max);
  s.mount = mount;
  s.sigma_range = sigma_range;
  return s;
}

ScanSequence read_scan_sequence(const BagReader& bag, const ScanSequenceOptions& o) {
  ScanSequence out;
  const BagTopic* scan_topic =
      pick_topic(bag, o.scan_topic, "sensor_msgs/LaserScan", "--scan-topic", true, "scan");
  out.scan_topic = scan_topic->name;
  if (const auto all = detail::topics_of(bag, "sensor_msgs/LaserScan");
      o.scan_topic.empty() && all.size() > 1) {
    std::string names;
    for (const BagTopic* t : all) names += (names.empty() ? "" : ", ") + t->name;
    out.scan_topic_choice = scan_topic->name + " of " + std::to_string(all.size()) +
                            " LaserScan topics (" + names +
                            "), as amcl subscribes scan; --scan-topic takes another";
  }
  const BagTopic* odom_topic =
      pick_topic(bag, o.odom_topic, "nav_msgs/Odometry", "--odom-topic", false);
  const std::vector<std::string> tf_topics = tf_topics_of(bag);
  const double span = span_seconds(bag);

  // One pass: TF (and the odometry topic, as odom -> base transforms) into buffers, scans kept.
  TransformBuffer tf(span), odom_tf(span);
  std::vector<LaserScanMsg> msgs;
  std::vector<std::string> read_topics = tf_topics;
  read_topics.push_back(scan_topic->name);
  if (odom_topic != nullptr) read_topics.push_back(odom_topic->name);
  std::string odom_child, odom_parent;
  bag.read(read_topics, [&](const BagMessage& m) {
    if (m.topic == scan_topic->name) {
      msgs.push_back(decode_laser_scan(m));
    } else if (odom_topic != nullptr && m.topic == odom_topic->name) {
      OdometryMsg od = decode_odometry(m);
      odom_parent = strip_slash(od.header.frame_id);
      odom_child = strip_slash(od.child_frame_id);
      odom_tf.add(od);
    } else {
      tf.add(decode_tf(m), m.topic == "/tf_static");
    }
    return true;
  });
  std::stable_sort(msgs.begin(), msgs.end(), [](const LaserScanMsg& a, const LaserScanMsg& b) {
    return a.header.stamp_ns < b.header.stamp_ns;
  });
  if (msgs.empty()) throw ConfigError(bag.path() + ": " + scan_topic->name + " holds no message");
  out.scan_frame = strip_slash(msgs.front().header.frame_id);

  // Odometry: the topic named, else TF odom -> base, else the only Odometry topic.
  const TransformBuffer* odom_source = nullptr;
  std::string parent = o.odom_frame, child = o.base_frame;
  if (!o.odom_topic.empty()) {
    odom_source = &odom_tf;
    parent = odom_parent;
    child = odom_child;
    out.odometry_source = "topic " + odom_topic->name;
  } else if (tf.connected(o.odom_frame, o.base_frame)) {
    odom_source = &tf;
    out.odometry_source = "TF " + o.odom_frame + " -> " + o.base_frame;
  } else if (odom_topic != nullptr) {
    odom_source = &odom_tf;
    parent = odom_parent;
    child = odom_child;
    out.odometry_source = "topic " + odom_topic->name;
  } else {
    throw ConfigError(bag.path() + ": no odometry: TF does not connect " + o.odom_frame + " -> " +
                      o.base_frame + " (--odom-frame, --base-frame; the frames: " + tf.describe() +
                      ") and no nav_msgs/Odometry topic (the bag has: " + list_topics(bag) + ")");
  }

  // Mounting: given, or TF base -> the scan's frame (a static transform, or the one at the first
  // scan it is known at; older scans are left out, no_transform).
  std::optional<Pose2> mount;
  if (o.laser_pose) {
    mount = *o.laser_pose;
    out.mount_source = "--laser-pose";
  } else if (out.scan_frame == o.base_frame) {
    mount = Pose2::Zero();
    out.mount_source = "the scans are in " + o.base_frame;
  } else if (!tf.connected(o.base_frame, out.scan_frame)) {
    throw ConfigError(bag.path() + ": no transform " + o.base_frame + " -> " + out.scan_frame +
                      " (the scans' frame) in the bag; give --laser-pose x,y,yaw (the frames: " +
                      tf.describe() + ")");
  } else {
    out.mount_source = "TF " + o.base_frame + " -> " + out.scan_frame;
  }

  for (const LaserScanMsg& m : msgs) {
    const std::int64_t t = m.header.stamp_ns;
    if (!mount) {
      if (!tf.can_lookup(o.base_frame, out.scan_frame, t)) {
        ++out.skipped_no_transform;
        out.no_transform_times.push_back(static_cast<double>(t) * 1e-9);
        continue;
      }
      mount = planar(tf.lookup(o.base_frame, out.scan_frame, t));
    }
    if (!odom_source->can_lookup(parent, child, t)) {
      ++out.skipped_no_odometry;
      out.skipped_times.push_back(static_cast<double>(t) * 1e-9);
      continue;
    }
    out.odometry.push_back(planar(odom_source->lookup(parent, child, t)));
    out.scans.push_back(to_laser_scan(m, *mount, o.sigma_range, o.max_range));
  }
  if (!mount) {
    throw ConfigError(bag.path() + ": the transform " + o.base_frame + " -> " + out.scan_frame +
                      " is not known at any scan's stamp; give --laser-pose x,y,yaw (the frames: " +
                      tf.describe() + ")");
  }
  if (out.scans.empty()) {
    throw ConfigError(bag.path() + ": no scan of " + scan_topic->name +
                      " lies in the odometry's time span (" + out.odometry_source + ")");
  }
  return out;
}

}  // namespace vdtnav::ros
