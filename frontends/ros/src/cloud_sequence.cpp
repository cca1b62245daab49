// read_cloud_sequence: a bag's PointCloud2 topic, cloud by cloud, with mounting, odometry and the
// IMU's roll and pitch at each stamp (cloud_sequence.hpp says where each comes from).

#include "vdtnav/ros/cloud_sequence.hpp"

#include <algorithm>
#include <memory>
#include <vector>

#include "topics.hpp"
#include "vdtnav/ros/transform_buffer.hpp"

namespace vdtnav::ros {

using detail::list_topics;
using detail::pick_topic;
using detail::span_seconds;
using detail::tf_topics_of;

namespace {

struct ImuOrientation {
  std::int64_t t;
  Eigen::Quaterniond q;
};

/// The IMU's orientation at t: slerp between the samples around it; none outside their span.
std::optional<Eigen::Quaterniond> imu_at(const std::vector<ImuOrientation>& s, std::int64_t t) {
  const auto after = std::lower_bound(
      s.begin(), s.end(), t, [](const ImuOrientation& a, std::int64_t x) { return a.t < x; });
  if (after == s.end()) return std::nullopt;
  if (after->t == t || after == s.begin()) {
    if (after->t != t) return std::nullopt;
    return after->q;
  }
  const auto before = after - 1;
  const double f = static_cast<double>(t - before->t) / static_cast<double>(after->t - before->t);
  return before->q.slerp(f, after->q);
}

}  // namespace

CloudSequenceInfo read_cloud_sequence(const BagReader& bag, const CloudSequenceOptions& o,
                                      const std::function<bool(const CloudFrame&)>& visit) {
  CloudSequenceInfo info;
  const BagTopic* cloud_topic =
      pick_topic(bag, o.cloud_topic, "sensor_msgs/PointCloud2", "--cloud-topic", true);
  info.cloud_topic = cloud_topic->name;
  info.clouds = cloud_topic->count;
  const bool no_odometry = o.odom_topic == "none";
  const BagTopic* odom_topic =
      no_odometry ? nullptr
                  : pick_topic(bag, o.odom_topic, "nav_msgs/Odometry", "--odom-topic", false);
  const BagTopic* imu_topic =
      o.imu_topic.empty() ? nullptr
                          : pick_topic(bag, o.imu_topic, "sensor_msgs/Imu", "--imu-topic", true);

  // First pass: transforms, odometry and IMU (small), then the clouds one by one.
  const double span = span_seconds(bag);
  TransformBuffer tf(span), odom_tf(span);
  std::vector<std::string> topics = tf_topics_of(bag);
  if (odom_topic != nullptr) topics.push_back(odom_topic->name);
  if (imu_topic != nullptr) topics.push_back(imu_topic->name);
  std::string odom_parent, odom_child, imu_frame;
  std::vector<ImuOrientation> imu;
  std::vector<vdtnav::ImuSample> rates;  // the IMU frame's; in base_frame below
  if (!topics.empty()) {
    bag.read(topics, [&](const BagMessage& m) {
      if (odom_topic != nullptr && m.topic == odom_topic->name) {
        const OdometryMsg od = decode_odometry(m);
        odom_parent = strip_slash(od.header.frame_id);
        odom_child = strip_slash(od.child_frame_id);
        odom_tf.add(od);
      } else if (imu_topic != nullptr && m.topic == imu_topic->name) {
        const ImuMsg i = decode_imu(m);
        imu_frame = strip_slash(i.header.frame_id);
        imu.push_back({i.header.stamp_ns, i.orientation.normalized()});
        vdtnav::ImuSample r;
        r.t = 1e-9 * static_cast<double>(i.header.stamp_ns);
        r.gyro = i.angular_velocity;
        r.accel = i.linear_acceleration;
        rates.push_back(r);
      } else {
        tf.add(decode_tf(m), m.topic == "/tf_static");
      }
      return true;
    });
  }
  std::stable_sort(imu.begin(), imu.end(),
                   [](const ImuOrientation& a, const ImuOrientation& b) { return a.t < b.t; });
  std::stable_sort(
      rates.begin(), rates.end(),
      [](const vdtnav::ImuSample& a, const vdtnav::ImuSample& b) { return a.t < b.t; });

  const TransformBuffer* odom_source = nullptr;
  std::string parent = o.odom_frame, child = o.base_frame;
  if (no_odometry) {
    info.odometry_source = "none (--odom-topic none: constant velocity)";
  } else if (!o.odom_topic.empty() || (!tf.connected(o.odom_frame, o.base_frame) && odom_topic)) {
    odom_source = &odom_tf;
    parent = odom_parent;
    child = odom_child;
    info.odometry_source = "topic " + odom_topic->name;
  } else if (tf.connected(o.odom_frame, o.base_frame)) {
    odom_source = &tf;
    info.odometry_source = "TF " + o.odom_frame + " -> " + o.base_frame;
  } else {
    info.odometry_source = "none in the bag (constant velocity)";
  }
  // The IMU's mounting: its orientation is the IMU frame's; the robot's is R_imu R_mount^-1.
  Eigen::Matrix3d imu_mount = Eigen::Matrix3d::Identity();
  if (imu_topic != nullptr) {
    info.imu_source = "topic " + imu_topic->name;
    if (!imu_frame.empty() && imu_frame != o.base_frame && tf.connected(o.base_frame, imu_frame)) {
      imu_mount = tf.lookup(o.base_frame, imu_frame, imu.empty() ? 0 : imu.front().t).linear();
      info.imu_source += " (mounted as TF " + o.base_frame + " -> " + imu_frame + ")";
    }
  }
  // The rates and specific forces in base_frame (the lever arm left out: the IMU is taken at the
  // robot's origin), one sample per stamp (a repeated stamp keeps the first).
  auto imu_samples = std::make_shared<std::vector<vdtnav::ImuSample>>();
  for (vdtnav::ImuSample r : rates) {
    if (!imu_samples->empty() && !(r.t > imu_samples->back().t)) continue;
    if (!r.gyro.allFinite() || !r.accel.allFinite()) continue;
    r.gyro = imu_mount * r.gyro;
    r.accel = imu_mount * r.accel;
    imu_samples->push_back(r);
  }

  std::optional<Pose3> mount = o.lidar_pose;
  if (mount) info.mount_source = "--lidar-pose";
  bag.read({cloud_topic->name}, [&](const BagMessage& m) {
    CloudFrame f;
    const PointCloud2Msg msg = decode_point_cloud2(m);
    f.stamp_ns = msg.header.stamp_ns;
    f.frame = strip_slash(msg.header.frame_id);
    if (!mount) {
      if (f.frame == o.base_frame) {
        mount = Pose3::Identity();
        info.mount_source = "the clouds are in " + o.base_frame;
      } else if (tf.connected(o.base_frame, f.frame)) {
        mount = tf.lookup(o.base_frame, f.frame, f.stamp_ns);
        info.mount_source = "TF " + o.base_frame + " -> " + f.frame;
      } else {
        throw ConfigError(bag.path() + ": no transform " + o.base_frame + " -> " + f.frame +
                          " (the clouds' frame) in the bag; give --lidar-pose "
                          "x,y,z,roll,pitch,yaw (the frames: " +
                          tf.describe() + ")");
      }
    }
    f.mount = *mount;
    f.cloud = cloud_points(msg, m.topic);
    if (odom_source != nullptr && odom_source->can_lookup(parent, child, f.stamp_ns)) {
      f.odometry = odom_source->lookup(parent, child, f.stamp_ns);
    }
    if (imu_topic != nullptr) f.imu = imu_samples;
    if (const auto q = imu_at(imu, f.stamp_ns)) {
      const Eigen::Vector3d rpy = rpy_of(q->toRotationMatrix() * imu_mount.transpose());
      f.roll = rpy.x();
      f.pitch = rpy.y();
    }
    return visit(f);
  });
  return info;
}

}  // namespace vdtnav::ros
