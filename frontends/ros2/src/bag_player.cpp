// A bag played onto a ROS 2 graph (bag_player.hpp).
#include "vdtnav/ros2/bag_player.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <thread>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/cdr_writer.hpp"

namespace vdtnav::ros2 {
namespace {

using Clock = std::chrono::steady_clock;

/// A ROS 1 message as ROS 2 CDR: decoded to messages.hpp's struct, encoded (empty: a type this
/// cannot carry).
std::vector<std::uint8_t> as_cdr(const ros::BagMessage& m) {
  const std::string type = ros::ros1_type_name(m.type);
  if (type == "sensor_msgs/LaserScan") return ros::encode_cdr(ros::decode_laser_scan(m));
  if (type == "sensor_msgs/PointCloud2") return ros::encode_cdr(ros::decode_point_cloud2(m));
  if (type == "nav_msgs/Odometry") return ros::encode_cdr(ros::decode_odometry(m));
  if (type == "tf2_msgs/TFMessage") return ros::encode_cdr(ros::decode_tf(m));
  if (type == "geometry_msgs/PoseStamped") return ros::encode_cdr(ros::decode_pose_stamped(m));
  if (type == "geometry_msgs/PoseWithCovarianceStamped") {
    return ros::encode_cdr(ros::decode_pose_with_covariance_stamped(m));
  }
  if (type == "sensor_msgs/Imu") return ros::encode_cdr(ros::decode_imu(m));
  if (type == "nav_msgs/OccupancyGrid") return ros::encode_cdr(ros::decode_occupancy_grid(m));
  return {};
}

bool ros1_playable(const std::string& type) {
  const std::string t = ros::ros1_type_name(type);
  for (const char* k :
       {"sensor_msgs/LaserScan", "sensor_msgs/PointCloud2", "nav_msgs/Odometry",
        "tf2_msgs/TFMessage", "geometry_msgs/PoseStamped",
        "geometry_msgs/PoseWithCovarianceStamped", "sensor_msgs/Imu", "nav_msgs/OccupancyGrid"}) {
    if (t == k) return true;
  }
  return false;
}

Qos qos_of(const ros::BagTopic& t) {
  // Latched, and every message kept for late joiners: a bag holds one /tf_static message per
  // static broadcaster, each with its own transforms.
  if (t.name == "/tf_static")
    return Qos::transient_local(static_cast<int>(std::max<std::size_t>(t.count, 1)));
  return Qos{Qos::Reliability::kReliable, Qos::Durability::kVolatile, 100};
}

}  // namespace

std::string ros2_type_name(const std::string& type) {
  const std::string t = ros::ros1_type_name(type);
  const std::size_t slash = t.find('/');
  if (slash == std::string::npos) throw ConfigError("a ROS type: expected pkg/Type, got " + type);
  return t.substr(0, slash) + "/msg/" + t.substr(slash + 1);
}

ros::OccupancyGridMsg occupancy_grid(const RosMap& map, std::int64_t stamp_ns,
                                     const std::string& frame) {
  ros::OccupancyGridMsg g;
  g.header.stamp_ns = stamp_ns;
  g.header.frame_id = frame;
  const int w = map.cells.size().x(), h = map.cells.size().y();
  g.info.map_load_time_ns = stamp_ns;
  g.info.resolution = static_cast<float>(map.metadata.resolution);
  g.info.width = static_cast<std::uint32_t>(w);
  g.info.height = static_cast<std::uint32_t>(h);
  g.info.origin.position = Eigen::Vector3d(map.metadata.origin[0], map.metadata.origin[1], 0.0);
  const double yaw = map.metadata.origin[2];
  g.info.origin.orientation =
      Eigen::Quaterniond(std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw));
  g.data.resize(static_cast<std::size_t>(w) * h);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i)
      g.data[static_cast<std::size_t>(j) * w + i] = map.cells(Eigen::Vector2i(i, j));
  }
  return g;
}

PlayReport play_bag(const ros::BagReader& bag, Participant& participant,
                    const PlayOptions& options) {
  PlayReport report;
  const bool ros1 = bag.format() == ros::BagFormat::kRos1;
  std::vector<std::string> topics;
  std::map<std::string, std::unique_ptr<Writer>> writers;
  for (const ros::BagTopic& t : bag.topics()) {
    const bool asked =
        options.topics.empty() ||
        std::find(options.topics.begin(), options.topics.end(), t.name) != options.topics.end();
    if (!asked || t.count == 0) continue;
    if (ros1 && !ros1_playable(t.type)) {
      report.skipped_types.push_back(t.name + " (" + t.type + ")");
      continue;
    }
    writers[t.name] = participant.writer(t.name, ros2_type_name(t.type), qos_of(t));
    topics.push_back(t.name);
  }
  for (const std::string& asked : options.topics) {
    if (std::find(topics.begin(), topics.end(), asked) == topics.end() &&
        std::none_of(report.skipped_types.begin(), report.skipped_types.end(),
                     [&](const std::string& s) { return s.rfind(asked + " (", 0) == 0; })) {
      throw ConfigError("bag play: " + bag.path() + " has no messages on " + asked);
    }
  }
  std::unique_ptr<Writer> map_writer;
  if (options.map) {
    map_writer =
        participant.writer(options.map_topic, "nav_msgs/msg/OccupancyGrid", Qos::transient_local());
  }
  const Clock::time_point t0 = Clock::now();
  if (options.wait_for_readers > 0.0) {
    const auto end = t0 + std::chrono::duration<double>(options.wait_for_readers);
    const auto all_matched = [&] {
      if (map_writer && map_writer->matched() == 0) return false;
      return std::all_of(writers.begin(), writers.end(),
                         [](const auto& w) { return w.second->matched() > 0; });
    };
    while (!all_matched() && Clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // A writer sees its match before the reader's side has it: a grace before the first sample.
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  if (map_writer) {
    map_writer->write(ros::encode_cdr(occupancy_grid(*options.map)));
    ++report.published;
  }
  const Clock::time_point start = Clock::now();
  std::int64_t first_ns = -1;
  bag.read(topics, [&](const ros::BagMessage& m) {
    if (first_ns < 0) first_ns = m.recorded_ns;
    if (options.rate > 0.0) {
      const double due = 1e-9 * static_cast<double>(m.recorded_ns - first_ns) / options.rate;
      std::this_thread::sleep_until(
          start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(due)));
    }
    const std::vector<std::uint8_t> cdr = ros1 ? as_cdr(m) : m.data;
    if (!writers.at(m.topic)->write(cdr))
      throw Error("bag play: DDS refused a message on " + m.topic);
    ++report.published;
    if (options.on_message) options.on_message(m);
    return true;
  });
  report.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
}

}  // namespace vdtnav::ros2
