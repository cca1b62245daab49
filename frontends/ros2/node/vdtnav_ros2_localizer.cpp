// vdtnav_ros2_localizer: a ROS 2 node in nav2's amcl's place, without rclcpp: a Fast DDS
// participant with ROS 2's names, types and QoS (vdtnav/ros2/dds.hpp), started as a launch file
// starts amcl (`--ros-args -r __node:=amcl --params-file nav2_params.yaml -p ...`):
//   subscribes  scan_topic (sensor_msgs/LaserScan, sensor-data QoS), map_topic
//               (nav_msgs/OccupancyGrid, transient local) unless map_file names a map_server
//               YAML to load, initialpose (geometry_msgs/PoseWithCovarianceStamped), /tf and
//               /tf_static (transient local);
//   publishes   amcl_pose (geometry_msgs/PoseWithCovarianceStamped, transient local, depth 1)
//               and global_frame_id -> odom_frame_id on /tf, stamped scan stamp +
//               transform_tolerance (unless tf_broadcast is false).
// The node's work is vdtnav::ros::NodeCore's, the ROS 1 node's too: the scans localized exactly
// as `vdtnav localize --bag` localizes them. docs/ros2-node.md lists the parameters.
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cdr_writer.hpp"
#include "vdtnav/ros/node_core.hpp"
#include "vdtnav/ros2/dds.hpp"
#include "vdtnav/ros2/ros_args.hpp"

namespace vr = vdtnav::ros;
namespace v2 = vdtnav::ros2;

namespace {

constexpr const char* kLaserScan = "sensor_msgs/msg/LaserScan";
constexpr const char* kOccupancyGrid = "nav_msgs/msg/OccupancyGrid";
constexpr const char* kPoseCov = "geometry_msgs/msg/PoseWithCovarianceStamped";
constexpr const char* kTf = "tf2_msgs/msg/TFMessage";

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

/// What the DDS threads hand the node's thread, in arrival order.
struct Input {
  enum class Kind { kScan, kTf, kTfStatic, kMap, kInitialPose } kind;
  v2::Sample sample;
  std::chrono::steady_clock::time_point arrival;
};

class Inbox {
 public:
  void push(Input in) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(std::move(in));
    }
    ready_.notify_one();
  }
  /// \return false when nothing arrived within 100 ms.
  bool pop(Input* out) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!ready_.wait_for(lock, std::chrono::milliseconds(100), [this] { return !queue_.empty(); }))
      return false;
    *out = std::move(queue_.front());
    queue_.pop_front();
    return true;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Input> queue_;
};

/// The bytes of a sample as a ROS 2 bag message, for the decoders of bag_reader.hpp.
vr::BagMessage as_message(const v2::Sample& s, const std::string& topic, const char* type) {
  vr::BagMessage m;
  m.format = vr::BagFormat::kRos2;
  m.topic = topic;
  m.type = type;
  m.recorded_ns = s.source_ns;
  m.data = s.cdr;
  return m;
}

/// "x,y,yaw" as a pose (laser_pose); empty: none.
std::optional<vdtnav::Pose2> pose_param(const v2::RosArgs& args, const std::string& name) {
  const std::string text = args.text(name, "");
  if (text.empty()) return std::nullopt;
  vdtnav::Pose2 p;
  char c1 = 0, c2 = 0;
  if (std::sscanf(text.c_str(), "%lf %c %lf %c %lf", &p[0], &c1, &p[1], &c2, &p[2]) != 5 ||
      c1 != ',' || c2 != ',' || !p.allFinite()) {
    throw vdtnav::ConfigError("parameter " + name + ": expected x,y,yaw (m, m, rad), got '" + text +
                              "'");
  }
  return p;
}

/// nav2_amcl's parameters where the meaning is the same (nav2's defaults but for the update
/// rule: every scan is localized unless update_min_d / update_min_a say otherwise), and
/// vdtnav's own (config, method, map_file, laser_pose, sigma_range, odom_extrapolation).
vr::NodeOptions node_options(const v2::RosArgs& args) {
  vr::NodeOptions o;
  o.global_frame = vr::strip_slash(args.text("global_frame_id", "map"));
  o.live.odom_frame = vr::strip_slash(args.text("odom_frame_id", "odom"));
  o.live.base_frame = vr::strip_slash(args.text("base_frame_id", "base_footprint"));
  o.live.update_min_d = args.number("update_min_d", 0.0);
  o.live.update_min_a = args.number("update_min_a", 0.0);
  const double max_range = args.number("laser_max_range", -1.0);
  o.live.max_range = max_range > 0.0 ? max_range : std::nan("");
  o.transform_tolerance = args.number("transform_tolerance", 1.0);
  o.tf_broadcast = args.boolean("tf_broadcast", true);
  o.first_map_only = args.boolean("first_map_only", false);
  o.has_initial_pose = args.boolean("set_initial_pose", false);
  o.initial_pose =
      vdtnav::Pose2(args.number("initial_pose.x", 0.0), args.number("initial_pose.y", 0.0),
                    args.number("initial_pose.yaw", 0.0));
  o.live.method = args.text("method", "vdt-opt");
  o.live.laser_pose = pose_param(args, "laser_pose");
  o.live.sigma_range = args.number("sigma_range", o.live.sigma_range);
  o.live.odom_extrapolation = args.number("odom_extrapolation", 0.0);
  // nav2's amcl has no initial covariance parameters: `vdtnav localize`'s --init-sigma default.
  o.initial_covariance = o.live.init_sigma.cwiseAbs2().asDiagonal();
  return o;
}

void log_line(const v2::RosArgs& args, const std::string& line) {
  std::fprintf(stderr, "[%s] %s\n", args.node_name().c_str(), line.c_str());
}

int run(int argc, char** argv) {
  const v2::RosArgs args(argc, argv, "amcl");
  vr::NodeOptions options = node_options(args);
  vdtnav::LocalizerSettings settings = vdtnav::log_settings();
  const std::string config = args.text("config", "");
  if (!config.empty()) settings = vdtnav::load_localizer_config(config, settings);
  vr::NodeCore core(options, settings);

  const std::string scan_topic = args.resolve(args.text("scan_topic", "scan"));
  const std::string map_topic = args.resolve(args.text("map_topic", "map"));
  const std::string map_file = args.text("map_file", "");

  v2::ParticipantOptions po;
  po.name = args.node_name();
  v2::Participant participant(po);
  Inbox inbox;
  const auto into = [&inbox](Input::Kind kind) {
    return [&inbox, kind](const v2::Sample& s) {
      inbox.push({kind, s, std::chrono::steady_clock::now()});
    };
  };
  // Writers first: declared after the participant, destroyed before it.
  auto pose_out =
      participant.writer(args.resolve("amcl_pose"), kPoseCov, v2::Qos::transient_local());
  auto tf_out = participant.writer("/tf", kTf, v2::Qos::defaults());
  std::vector<std::unique_ptr<v2::Reader>> readers;
  readers.push_back(participant.reader("/tf_static", kTf, v2::Qos::transient_local(100),
                                       into(Input::Kind::kTfStatic)));
  readers.push_back(participant.reader(
      "/tf", kTf, v2::Qos{v2::Qos::Reliability::kReliable, v2::Qos::Durability::kVolatile, 100},
      into(Input::Kind::kTf)));
  readers.push_back(participant.reader(args.resolve("initialpose"), kPoseCov, v2::Qos::defaults(),
                                       into(Input::Kind::kInitialPose)));
  if (map_file.empty()) {
    readers.push_back(participant.reader(map_topic, kOccupancyGrid, v2::Qos::transient_local(),
                                         into(Input::Kind::kMap)));
    log_line(args, "waiting for the map on " + map_topic);
  } else {
    for (const std::string& l :
         core.set_map(vdtnav::load_ros_map(map_file), "file " + map_file).log)
      log_line(args, l);
  }
  readers.push_back(
      participant.reader(scan_topic, kLaserScan, v2::Qos::sensor_data(), into(Input::Kind::kScan)));
  log_line(args, std::string("up on DDS domain ") + std::to_string(participant.domain()) +
                     (participant.loopback() ? " (loopback only)" : "") + ", " +
                     options.live.method + (config.empty() ? "" : " with " + config));

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  while (g_stop == 0) {
    Input in;
    if (!inbox.pop(&in)) continue;
    vr::NodeOutput out;
    try {
      switch (in.kind) {
        case Input::Kind::kScan:
          out = core.add_scan(vr::decode_laser_scan(as_message(in.sample, scan_topic, kLaserScan)),
                              in.arrival);
          break;
        case Input::Kind::kTf:
        case Input::Kind::kTfStatic: {
          const bool is_static = in.kind == Input::Kind::kTfStatic;
          out = core.add_transforms(
              vr::decode_tf(as_message(in.sample, is_static ? "/tf_static" : "/tf", kTf)),
              is_static);
          break;
        }
        case Input::Kind::kMap:
          out = core.set_map(vr::to_ros_map(vr::decode_occupancy_grid(
                                 as_message(in.sample, map_topic, kOccupancyGrid))),
                             "topic " + map_topic);
          break;
        case Input::Kind::kInitialPose:
          out = core.set_initial_pose(vr::decode_pose_with_covariance_stamped(
              as_message(in.sample, "initialpose", kPoseCov)));
          break;
      }
    } catch (const vdtnav::Error& e) {
      log_line(args, std::string("message refused: ") + e.what());
      continue;
    }
    for (const vr::PoseWithCovarianceStampedMsg& p : out.poses) pose_out->write(vr::encode_cdr(p));
    if (!out.tf.transforms.empty()) tf_out->write(vr::encode_cdr(out.tf));
    for (const std::string& l : out.log) log_line(args, l);
  }
  readers.clear();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "vdtnav_ros2_localizer: %s\n", e.what());
    return 2;
  }
}
