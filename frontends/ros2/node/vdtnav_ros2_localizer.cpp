// vdtnav_ros2_localizer: a ROS 2 node in nav2's amcl's place, without rclcpp: a Fast DDS
// participant with ROS 2's names, types and QoS (vdtnav/ros2/dds.hpp), started as a launch file
// starts amcl (`--ros-args -r __node:=amcl --params-file nav2_params.yaml -p ...`) and managed
// as nav2's lifecycle manager manages it (lifecycle.hpp: `~/change_state`, `~/get_state`,
// `~/transition_event`, and the bond heartbeat on `bond` while active):
//   subscribes  scan_topic (sensor_msgs/LaserScan, sensor-data QoS), map_topic
//               (nav_msgs/OccupancyGrid, transient local) unless map_file names a map_server
//               YAML to load, initialpose (geometry_msgs/PoseWithCovarianceStamped), /tf and
//               /tf_static (transient local);
//   publishes   amcl_pose (geometry_msgs/PoseWithCovarianceStamped, transient local, depth 1)
//               and global_frame_id -> odom_frame_id on /tf, stamped scan stamp +
//               transform_tolerance (unless tf_broadcast is false), while active;
//   services    reinitialize_global_localization, request_nomotion_update (std_srvs/Empty),
//               set_initial_pose (nav2_msgs/SetInitialPose).
// The node's work is vdtnav::ros::NodeCore's, the ROS 1 node's too: the scans localized exactly
// as `vdtnav localize --bag` localizes them. docs/ros2-node.md lists the parameters.
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/ros/cdr_reader.hpp"
#include "vdtnav/ros/cdr_writer.hpp"
#include "vdtnav/ros/node_core.hpp"
#include "vdtnav/ros/transform_buffer.hpp"
#include "vdtnav/ros2/dds.hpp"
#include "vdtnav/ros2/lifecycle.hpp"
#include "vdtnav/ros2/ros_args.hpp"
#include "vdtnav/ros2/service.hpp"

namespace vr = vdtnav::ros;
namespace v2 = vdtnav::ros2;
using Clock = std::chrono::steady_clock;

namespace {

constexpr const char* kLaserScan = "sensor_msgs/msg/LaserScan";
constexpr const char* kOccupancyGrid = "nav_msgs/msg/OccupancyGrid";
constexpr const char* kPoseCov = "geometry_msgs/msg/PoseWithCovarianceStamped";
constexpr const char* kTf = "tf2_msgs/msg/TFMessage";

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

std::uint64_t wall_ns() {
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                        std::chrono::system_clock::now().time_since_epoch())
                                        .count());
}

/// What the DDS threads hand the node's thread, in arrival order.
struct Input {
  enum class Kind {
    kScan,
    kTf,
    kTfStatic,
    kMap,
    kInitialPose,
    kChangeState,
    kGetState,
    kGlobal,
    kNoMotion,
    kSetInitialPose
  } kind = Kind::kScan;
  v2::Sample sample;    // topics
  v2::Request request;  // services
  Clock::time_point arrival;
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
  /// \return false when nothing arrived within `wait`.
  bool pop(Input* out, std::chrono::milliseconds wait) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!ready_.wait_for(lock, wait, [this] { return !queue_.empty(); })) return false;
    *out = std::move(queue_.front());
    queue_.pop_front();
    return true;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Input> queue_;
};

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

/// A random instance id for the bond (bondcpp: a UUID per Bond).
std::string instance_id() {
  std::random_device rd;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%08x-%04x-%04x-%04x-%08x%04x", rd(), rd() & 0xffffU,
                (rd() & 0x0fffU) | 0x4000U, (rd() & 0x3fffU) | 0x8000U, rd(), rd() & 0xffffU);
  return buf;
}

class Ros2Localizer {
 public:
  explicit Ros2Localizer(const v2::RosArgs& args)
      : args_(args),
        participant_(participant_options(args)),
        lifecycle_({[this] { return configure(); }, [this] { return activate(); },
                    [this] { return deactivate(); }, [this] { return cleanup(); },
                    [this] { return shutdown(); }}),
        bond_instance_(instance_id()) {
    scan_topic_ = args.resolve(args.text("scan_topic", "scan"));
    map_topic_ = args.resolve(args.text("map_topic", "map"));
    const auto into = [this](Input::Kind kind) {
      return [this, kind](const v2::Sample& s) {
        Input in;
        in.kind = kind;
        in.sample = s;
        in.arrival = Clock::now();
        inbox_.push(std::move(in));
      };
    };
    const auto request = [this](Input::Kind kind) {
      return [this, kind](const v2::Request& r) {
        Input in;
        in.kind = kind;
        in.request = r;
        in.arrival = Clock::now();
        inbox_.push(std::move(in));
      };
    };
    pose_out_ =
        participant_.writer(args.resolve("amcl_pose"), kPoseCov, v2::Qos::transient_local());
    tf_out_ = participant_.writer("/tf", kTf, v2::Qos::defaults());
    bond_out_ = participant_.writer(args.resolve("bond"), "bond/msg/Status", v2::Qos::defaults());
    events_out_ = participant_.writer(args.resolve("~/transition_event"),
                                      "lifecycle_msgs/msg/TransitionEvent", v2::Qos::defaults());
    readers_.push_back(participant_.reader("/tf_static", kTf, v2::Qos::transient_local(100),
                                           into(Input::Kind::kTfStatic)));
    readers_.push_back(participant_.reader(
        "/tf", kTf, v2::Qos{v2::Qos::Reliability::kReliable, v2::Qos::Durability::kVolatile, 100},
        into(Input::Kind::kTf)));
    readers_.push_back(participant_.reader(args.resolve("initialpose"), kPoseCov,
                                           v2::Qos::defaults(), into(Input::Kind::kInitialPose)));
    if (args.text("map_file", "").empty()) {
      readers_.push_back(participant_.reader(map_topic_, kOccupancyGrid, v2::Qos::transient_local(),
                                             into(Input::Kind::kMap)));
    }
    readers_.push_back(participant_.reader(scan_topic_, kLaserScan, v2::Qos::sensor_data(),
                                           into(Input::Kind::kScan)));
    services_.push_back(std::make_unique<v2::ServiceServer>(
        participant_, args.resolve("~/change_state"), "lifecycle_msgs/srv/ChangeState",
        request(Input::Kind::kChangeState)));
    services_.push_back(std::make_unique<v2::ServiceServer>(
        participant_, args.resolve("~/get_state"), "lifecycle_msgs/srv/GetState",
        request(Input::Kind::kGetState)));
    services_.push_back(std::make_unique<v2::ServiceServer>(
        participant_, args.resolve("reinitialize_global_localization"), "std_srvs/srv/Empty",
        request(Input::Kind::kGlobal)));
    services_.push_back(
        std::make_unique<v2::ServiceServer>(participant_, args.resolve("request_nomotion_update"),
                                            "std_srvs/srv/Empty", request(Input::Kind::kNoMotion)));
    services_.push_back(std::make_unique<v2::ServiceServer>(
        participant_, args.resolve("set_initial_pose"), "nav2_msgs/srv/SetInitialPose",
        request(Input::Kind::kSetInitialPose)));
    log("up on DDS domain " + std::to_string(participant_.domain()) +
        (participant_.loopback() ? " (loopback only)" : "") + ", " + args.fully_qualified_name() +
        " unconfigured");
    // A node started alone (no lifecycle manager) may bring itself up (vdtnav's `autostart`).
    if (args.boolean("autostart", false)) {
      change(1, "");
      change(3, "");
    }
  }

  ~Ros2Localizer() {
    // Endpoints before the participant (they are members declared after it).
    services_.clear();
    readers_.clear();
  }

  int run() {
    auto next_beat = Clock::now();
    while (g_stop == 0 && lifecycle_.state() != 4) {
      Input in;
      if (inbox_.pop(&in, std::chrono::milliseconds(20))) handle(in);
      if (lifecycle_.state() == 3 && Clock::now() >= next_beat) {
        heartbeat(true);
        next_beat = Clock::now() + std::chrono::milliseconds(100);
      }
    }
    if (lifecycle_.state() == 3) heartbeat(false);
    std::string summary = "scans:";
    for (const auto& [token, n] : statuses_) summary += " " + std::to_string(n) + " " + token;
    log(statuses_.empty() ? "no scan localized" : summary);
    // The reply to a shutdown request is still in flight: delivered before the process ends.
    for (const auto& service : services_) service->flush(3.0);
    return 0;
  }

 private:
  static v2::ParticipantOptions participant_options(const v2::RosArgs& args) {
    v2::ParticipantOptions po;
    po.name = args.node_name();
    return po;
  }

  void log(const std::string& line) const {
    std::fprintf(stderr, "[%s] %s\n", args_.node_name().c_str(), line.c_str());
  }

  // ---- lifecycle hooks
  bool configure() {
    try {
      vr::NodeOptions options = node_options(args_);
      vdtnav::LocalizerSettings settings = vdtnav::log_settings();
      const std::string config = args_.text("config", "");
      if (!config.empty()) settings = vdtnav::load_localizer_config(config, settings);
      core_ = std::make_unique<vr::NodeCore>(options, settings);
      const std::string map_file = args_.text("map_file", "");
      if (!map_file.empty()) {
        emit(core_->set_map(vdtnav::load_ros_map(map_file), "file " + map_file));
      } else {
        log("waiting for the map on " + map_topic_);
      }
      // What the latched topics gave before (they are not sent again to the same reader).
      for (const Input& in : latched_) consume(in);
      log("configured: " + options.live.method + (config.empty() ? "" : " with " + config));
      return true;
    } catch (const vdtnav::Error& e) {
      log(std::string("configure failed: ") + e.what());
      core_.reset();
      return false;
    }
  }
  bool activate() {
    log("active");
    return true;
  }
  bool deactivate() {
    heartbeat(false);
    log("inactive");
    return true;
  }
  bool cleanup() {
    core_.reset();
    log("unconfigured");
    return true;
  }
  bool shutdown() {
    if (lifecycle_.state() == 3) heartbeat(false);
    core_.reset();
    log("finalized");
    return true;
  }

  bool change(std::uint8_t id, const std::string& label) {
    const v2::Lifecycle::Result r = lifecycle_.change(id, label, wall_ns());
    if (r.success) events_out_->write(vr::encode_cdr(r.event));
    return r.success;
  }

  /// bond/msg/Status as bondcpp sends it (nav2_util's LifecycleNode: period 0.1 s, timeout 4 s).
  void heartbeat(bool active) {
    vr::BondStatusMsg s;
    s.header.stamp_ns = static_cast<std::int64_t>(wall_ns());
    s.id = args_.node_name();
    s.instance_id = bond_instance_;
    s.active = active;
    s.heartbeat_timeout = 4.0F;
    s.heartbeat_period = 0.1F;
    bond_out_->write(vr::encode_cdr(s));
  }

  // ---- inputs
  void handle(const Input& in) {
    try {
      switch (in.kind) {
        case Input::Kind::kChangeState: {
          vr::ChangeStateRequestMsg req;
          vr::decode_cdr(in.request.cdr, &req, "change_state request");
          vr::ChangeStateResponseMsg res;
          res.success = change(req.transition.id, req.transition.label);
          reply(0, in.request, vr::encode_cdr(res));
          return;
        }
        case Input::Kind::kGetState: {
          vr::GetStateResponseMsg res;
          res.current_state = lifecycle_.state_msg();
          reply(1, in.request, vr::encode_cdr(res));
          return;
        }
        case Input::Kind::kGlobal:
          if (core_) {
            core_->start_global();
            log(core_->has_map() ? "global localization: searching the whole map"
                                 : "global localization: once the map is there");
          }
          reply(2, in.request, vr::encode_cdr(vr::EmptyMsg{}));
          return;
        case Input::Kind::kNoMotion:
          if (core_) core_->request_update();
          reply(3, in.request, vr::encode_cdr(vr::EmptyMsg{}));
          return;
        case Input::Kind::kSetInitialPose: {
          vr::SetInitialPoseRequestMsg req;
          vr::decode_cdr(in.request.cdr, &req, "set_initial_pose request");
          if (core_) emit(core_->set_initial_pose(req.pose));
          reply(4, in.request, vr::encode_cdr(vr::EmptyMsg{}));
          return;
        }
        default:
          break;
      }
      // Latched topics are kept for the next configure; the rest needs a configured node.
      if (in.kind == Input::Kind::kTfStatic || in.kind == Input::Kind::kMap) {
        if (in.kind == Input::Kind::kMap) {
          latched_.erase(std::remove_if(latched_.begin(), latched_.end(),
                                        [](const Input& x) { return x.kind == Input::Kind::kMap; }),
                         latched_.end());
        }
        latched_.push_back(in);
      }
      if (!core_) return;
      if (in.kind == Input::Kind::kScan && lifecycle_.state() != 3) return;  // not active
      consume(in);
    } catch (const vdtnav::Error& e) {
      log(std::string("message refused: ") + e.what());
    }
  }

  void reply(std::size_t service, const v2::Request& r, const std::vector<std::uint8_t>& cdr) {
    if (!services_[service]->reply(r, cdr))
      log("a reply on " + services_[service]->name() + " was refused");
  }

  /// A topic's sample into the core (configured).
  void consume(const Input& in) {
    switch (in.kind) {
      case Input::Kind::kScan: {
        vr::LaserScanMsg scan;
        vr::decode_cdr(in.sample.cdr, &scan, scan_topic_);
        emit(core_->add_scan(scan, in.arrival));
        break;
      }
      case Input::Kind::kTf:
      case Input::Kind::kTfStatic: {
        vr::TfMsg tf;
        vr::decode_cdr(in.sample.cdr, &tf, "/tf");
        emit(core_->add_transforms(tf, in.kind == Input::Kind::kTfStatic));
        break;
      }
      case Input::Kind::kMap: {
        vr::OccupancyGridMsg grid;
        vr::decode_cdr(in.sample.cdr, &grid, map_topic_);
        emit(core_->set_map(vr::to_ros_map(grid), "topic " + map_topic_));
        break;
      }
      case Input::Kind::kInitialPose: {
        vr::PoseWithCovarianceStampedMsg p;
        vr::decode_cdr(in.sample.cdr, &p, "initialpose");
        emit(core_->set_initial_pose(p));
        break;
      }
      default:
        break;
    }
  }

  void emit(const vr::NodeOutput& out) {
    if (lifecycle_.state() == 3) {
      for (const vr::PoseWithCovarianceStampedMsg& p : out.poses)
        pose_out_->write(vr::encode_cdr(p));
      if (!out.tf.transforms.empty()) tf_out_->write(vr::encode_cdr(out.tf));
    }
    for (const std::string& l : out.log) log(l);
    for (const vr::NodeStatus& st : out.statuses) {
      if (++statuses_[st.token] == 1 && !st.reason.empty()) log(st.token + ": " + st.reason);
    }
  }

  const v2::RosArgs& args_;
  v2::Participant participant_;
  v2::Lifecycle lifecycle_;
  std::string bond_instance_, scan_topic_, map_topic_;
  Inbox inbox_;
  std::unique_ptr<vr::NodeCore> core_;
  std::vector<Input> latched_;
  std::map<std::string, std::size_t> statuses_;  // what became of the scans, for the exit log
  std::unique_ptr<v2::Writer> pose_out_, tf_out_, bond_out_, events_out_;
  std::vector<std::unique_ptr<v2::Reader>> readers_;
  std::vector<std::unique_ptr<v2::ServiceServer>> services_;
};

}  // namespace

int main(int argc, char** argv) {
  try {
    const v2::RosArgs args(argc, argv, "amcl");
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    Ros2Localizer node(args);
    return node.run();
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "vdtnav_ros2_localizer: %s\n", e.what());
    return 2;
  }
}
