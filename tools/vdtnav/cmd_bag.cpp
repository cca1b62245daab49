// vdtnav bag info BAG: what `rosbag info` and `ros2 bag info` show, for both formats — the
// format, duration, size, every topic with its type, message count and rate, and the TF frames
// with their parents (from /tf and /tf_static).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include "common.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/transform_buffer.hpp"

namespace vdtnav::tools {

namespace {

void run_bag_info(const std::string& path) {
  const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(path);
  std::int64_t first = 0, last = 0;
  std::size_t messages = 0;
  bool any = false;
  for (const ros::BagTopic& t : bag->topics()) {
    if (t.count == 0) continue;
    first = any ? std::min(first, t.first_ns) : t.first_ns;
    last = any ? std::max(last, t.last_ns) : t.last_ns;
    messages += t.count;
    any = true;
  }
  const double duration = 1e-9 * static_cast<double>(last - first);
  std::printf("path:       %s\n", bag->path().c_str());
  std::printf("format:     %s\n",
              bag->format() == ros::BagFormat::kRos1 ? "ROS 1 bag v2.0" : "ROS 2 bag (sqlite3)");
  std::printf("duration:   %.3f s\n", duration);
  std::printf("start:      %.6f\nend:        %.6f\n", 1e-9 * static_cast<double>(first),
              1e-9 * static_cast<double>(last));
  std::printf("size:       %.2f MB\n", 1e-6 * static_cast<double>(bag->size_bytes()));
  std::printf("messages:   %zu\n", messages);
  std::printf("topics:\n");
  std::size_t width = 0;
  for (const ros::BagTopic& t : bag->topics()) width = std::max(width, t.name.size());
  for (const ros::BagTopic& t : bag->topics()) {
    const double span = 1e-9 * static_cast<double>(t.last_ns - t.first_ns);
    const double rate = t.count > 1 && span > 0.0 ? static_cast<double>(t.count - 1) / span : 0.0;
    std::printf("  %-*s %7zu msgs  %8.2f Hz  %s\n", static_cast<int>(width), t.name.c_str(),
                t.count, rate, t.type.c_str());
  }
  // TF frames: every transform of /tf and /tf_static, child <- parent.
  std::vector<std::string> tf_topics;
  for (const ros::BagTopic& t : bag->topics()) {
    if (ros::ros1_type_name(t.type) == "tf2_msgs/TFMessage") tf_topics.push_back(t.name);
  }
  std::printf("tf frames:\n");
  if (tf_topics.empty()) {
    std::printf("  (no tf2_msgs/TFMessage topic)\n");
    return;
  }
  ros::TransformBuffer tf(duration + 60.0);
  bag->read(tf_topics, [&](const ros::BagMessage& m) {
    tf.add(ros::decode_tf(m), m.topic == "/tf_static");
    return true;
  });
  for (const auto& [child, parent] : tf.frames()) {
    if (parent.empty()) continue;
    std::printf("  %s <- %s\n", child.c_str(), parent.c_str());
  }
}

}  // namespace

void add_bag_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("bag", "ROS bags (ROS 1 and ROS 2)");
  cmd->require_subcommand(1);
  auto path = std::make_shared<std::string>();
  CLI::App* info =
      cmd->add_subcommand("info", "Topics, types, counts, duration, rates and TF frames of a bag");
  info->add_option("bag", *path, "ROS 1 bag file or ROS 2 bag folder")
      ->required()
      ->check(input_path("bag"));
  info->callback([path] { run_bag_info(*path); });
#ifdef VDTNAV_CLI_ROS2
  add_bag_play_command(*cmd);
#endif
}

}  // namespace vdtnav::tools
