// vdtnav_localizer: a ROS 1 node that takes amcl's place in a launch file. The same topics,
// service and parameter names as amcl where the meaning is the same:
//   subscribes  scan (sensor_msgs/LaserScan), /tf, /tf_static, initialpose
//               (geometry_msgs/PoseWithCovarianceStamped), map (nav_msgs/OccupancyGrid, latched)
//               when use_map_topic, else the static_map service (nav_msgs/GetMap), unless
//               map_file names a map_server YAML to load;
//   publishes   amcl_pose (geometry_msgs/PoseWithCovarianceStamped, the 6x6 row-major covariance
//               over x, y, z, roll, pitch, yaw; z, roll and pitch are not estimated: 0), the
//               global_frame_id -> odom_frame_id transform stamped scan stamp + transform_tolerance
//               (unless tf_broadcast is false), and ~status (diagnostic_msgs/DiagnosticStatus:
//               one per scan, what became of it);
//   service     global_localization (std_srvs/Empty): find the pose anew in the whole map.
// The scans are localized by vdtnav::ros::LiveLocalizer, exactly as `vdtnav localize --bag`
// localizes them; README "A node in place of amcl" lists every parameter.
#include <diagnostic_msgs/DiagnosticStatus.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/live_localizer.hpp"

namespace vr = vdtnav::ros;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::int64_t to_ns(const ros::Time& t) {
  return static_cast<std::int64_t>(t.sec) * 1'000'000'000 + static_cast<std::int64_t>(t.nsec);
}

ros::Time from_ns(std::int64_t ns) {
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(ns));
  return t;
}

vr::LaserScanMsg to_vdtnav(const sensor_msgs::LaserScan& m) {
  vr::LaserScanMsg s;
  s.header.stamp_ns = to_ns(m.header.stamp);
  s.header.frame_id = m.header.frame_id;
  s.angle_min = m.angle_min;
  s.angle_max = m.angle_max;
  s.angle_increment = m.angle_increment;
  s.time_increment = m.time_increment;
  s.scan_time = m.scan_time;
  s.range_min = m.range_min;
  s.range_max = m.range_max;
  s.ranges = m.ranges;
  s.intensities = m.intensities;
  return s;
}

vr::TfMsg to_vdtnav(const tf2_msgs::TFMessage& m) {
  vr::TfMsg out;
  for (const geometry_msgs::TransformStamped& t : m.transforms) {
    vr::TransformStampedMsg v;
    v.header.stamp_ns = to_ns(t.header.stamp);
    v.header.frame_id = t.header.frame_id;
    v.child_frame_id = t.child_frame_id;
    v.translation = {t.transform.translation.x, t.transform.translation.y,
                     t.transform.translation.z};
    v.rotation = Eigen::Quaterniond(t.transform.rotation.w, t.transform.rotation.x,
                                    t.transform.rotation.y, t.transform.rotation.z);
    out.transforms.push_back(std::move(v));
  }
  return out;
}

/// The decimal a float32 field was rounded from (map_server writes the YAML's resolution, 0.05,
/// as the float 0.0500000007): the shortest decimal that reads back as the same float, so that a
/// map from the topic has the geometry of the same map loaded from its file.
double decimal_of(float f) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  return std::strtod(std::string(buf, r.ptr).c_str(), nullptr);
}

/// The yaw of a planar rotation quaternion (z up).
double yaw_of(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

/// x, y and yaw are rows and columns 0, 1 and 5 of a 6x6 pose covariance (x, y, z, roll, pitch,
/// yaw), row-major.
constexpr int kPlanarIndex[3] = {0, 1, 5};

/// An OccupancyGrid as a map_server map: data row-major from the origin cell, -1 unknown.
vdtnav::RosMap to_vdtnav(const nav_msgs::OccupancyGrid& m) {
  const int w = static_cast<int>(m.info.width), h = static_cast<int>(m.info.height);
  if (w <= 0 || h <= 0 || m.data.size() != static_cast<std::size_t>(w) * h ||
      !(m.info.resolution > 0.0F)) {
    throw vdtnav::ConfigError("map: an OccupancyGrid of " + std::to_string(w) + " x " +
                              std::to_string(h) + " cells of " + std::to_string(m.info.resolution) +
                              " m holds " + std::to_string(m.data.size()) + " values");
  }
  const double yaw = yaw_of(m.info.origin.orientation);
  const double resolution = decimal_of(m.info.resolution);
  vdtnav::RosMap map;
  map.metadata.resolution = resolution;
  map.metadata.origin = {m.info.origin.position.x, m.info.origin.position.y, yaw};
  map.cells = vdtnav::Grid<std::int8_t, 2>(
      Eigen::Vector2i(w, h),
      vdtnav::GridFrame<2>(
          resolution, Eigen::Vector2d(m.info.origin.position.x, m.info.origin.position.y), yaw));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      map.cells(Eigen::Vector2i(i, j)) = m.data[static_cast<std::size_t>(j) * w + i];
    }
  }
  return map;
}

/// "x,y,yaw" as a pose; empty: none.
std::optional<vdtnav::Pose2> parse_pose_param(const std::string& text, const std::string& name) {
  if (text.empty()) return std::nullopt;
  std::istringstream in(text);
  vdtnav::Pose2 p;
  char c1 = 0, c2 = 0;
  if (!(in >> p[0] >> c1 >> p[1] >> c2 >> p[2]) || c1 != ',' || c2 != ',' || !p.allFinite()) {
    throw vdtnav::ConfigError("~" + name + ": expected x,y,yaw (metres, metres, radians), got '" +
                              text + "'");
  }
  return p;
}

class LocalizerNode {
 public:
  LocalizerNode() : pnh_("~") {
    pnh_.param<std::string>("global_frame_id", global_frame_, "map");
    pnh_.param<std::string>("odom_frame_id", options_.odom_frame, "odom");
    pnh_.param<std::string>("base_frame_id", options_.base_frame, "base_link");
    pnh_.param("update_min_d", options_.update_min_d, 0.0);
    pnh_.param("update_min_a", options_.update_min_a, 0.0);
    double max_range = -1.0;
    pnh_.param("laser_max_range", max_range, -1.0);
    options_.max_range = max_range > 0.0 ? max_range : std::nan("");
    pnh_.param("transform_tolerance", transform_tolerance_, 0.1);
    pnh_.param("tf_broadcast", tf_broadcast_, true);
    pnh_.param("use_map_topic", use_map_topic_, false);
    pnh_.param("first_map_only", first_map_only_, false);
    pnh_.param("initial_pose_x", initial_pose_[0], 0.0);
    pnh_.param("initial_pose_y", initial_pose_[1], 0.0);
    pnh_.param("initial_pose_a", initial_pose_[2], 0.0);
    pnh_.param("initial_cov_xx", initial_cov_[0], 0.5 * 0.5);
    pnh_.param("initial_cov_yy", initial_cov_[1], 0.5 * 0.5);
    pnh_.param("initial_cov_aa", initial_cov_[2], (kPi / 12.0) * (kPi / 12.0));
    // vdtnav's own: the settings file, the method, a map file, the scanner's mounting when TF
    // lacks it, the range noise, how far the odometry may be extrapolated to a scan's stamp.
    pnh_.param<std::string>("config", config_, "");
    pnh_.param<std::string>("method", options_.method, "vdt-opt");
    pnh_.param<std::string>("map_file", map_file_, "");
    std::string laser_pose;
    pnh_.param<std::string>("laser_pose", laser_pose, "");
    options_.laser_pose = parse_pose_param(laser_pose, "laser_pose");
    pnh_.param("sigma_range", options_.sigma_range, 0.02);
    pnh_.param("odom_extrapolation", options_.odom_extrapolation, 0.0);
    settings_ = vdtnav::log_settings();
    if (!config_.empty()) settings_ = vdtnav::load_localizer_config(config_, settings_);

    pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("amcl_pose", 10, true);
    status_pub_ = pnh_.advertise<diagnostic_msgs::DiagnosticStatus>("status", 100);
    if (!map_file_.empty()) {
      set_map(vdtnav::load_ros_map(map_file_), "file " + map_file_);
    } else if (use_map_topic_) {
      map_sub_ = nh_.subscribe("map", 1, &LocalizerNode::on_map, this);
      ROS_INFO("vdtnav_localizer: waiting for the map on %s", map_sub_.getTopic().c_str());
    } else {
      // amcl's default: the map_server's static_map service.
      nav_msgs::GetMap srv;
      ROS_INFO("vdtnav_localizer: requesting the map from static_map (use_map_topic false)");
      while (ros::ok() && !ros::service::call("static_map", srv)) {
        ROS_WARN_THROTTLE(5.0, "vdtnav_localizer: static_map not answering yet; waiting");
        ros::Duration(0.5).sleep();
      }
      if (ros::ok()) set_map(to_vdtnav(srv.response.map), "service static_map");
    }
    // Subscribed once a map file or the static map is loaded. Queues long enough that a bag
    // played fast loses nothing while a scan is localized.
    scan_sub_ = nh_.subscribe("scan", 1000, &LocalizerNode::on_scan, this);
    tf_sub_ = nh_.subscribe("/tf", 1000, &LocalizerNode::on_tf, this);
    tf_static_sub_ = nh_.subscribe("/tf_static", 100, &LocalizerNode::on_tf_static, this);
    initial_pose_sub_ = nh_.subscribe("initialpose", 2, &LocalizerNode::on_initial_pose, this);
    global_srv_ = nh_.advertiseService("global_localization", &LocalizerNode::on_global, this);
  }

 private:
  void set_map(vdtnav::RosMap map, const std::string& source) {
    const auto t0 = std::chrono::steady_clock::now();
    const int w = map.cells.size().x(), h = map.cells.size().y();
    const double res = map.cells.resolution();
    if (localizer_) {
      localizer_->set_map(std::move(map));
    } else {
      localizer_ = std::make_unique<vr::LiveLocalizer>(std::move(map), settings_, options_);
      localizer_->set_pose(initial_pose_, initial_cov_.asDiagonal());
      // What arrived before the map (the latched static transforms above all).
      for (const auto& [tf, is_static] : early_tf_)
        publish(localizer_->add_transforms(tf, is_static));
      early_tf_.clear();
    }
    ROS_INFO(
        "vdtnav_localizer: map from %s, %d x %d cells of %.3f m, VDT built in %.2f s; "
        "%s%s, starting at (%.3f, %.3f, %.3f)",
        source.c_str(), w, h, res,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
        options_.method.c_str(), config_.empty() ? "" : (" with " + config_).c_str(),
        initial_pose_[0], initial_pose_[1], initial_pose_[2]);
  }

  void on_map(const nav_msgs::OccupancyGrid::ConstPtr& m) {
    if (first_map_only_ && localizer_) return;
    try {
      set_map(to_vdtnav(*m), "topic " + map_sub_.getTopic());
    } catch (const vdtnav::Error& e) {
      ROS_ERROR("vdtnav_localizer: map refused: %s", e.what());
    }
  }

  void on_tf(const tf2_msgs::TFMessage::ConstPtr& m) { add_tf(*m, false); }
  void on_tf_static(const tf2_msgs::TFMessage::ConstPtr& m) { add_tf(*m, true); }
  void add_tf(const tf2_msgs::TFMessage& m, bool is_static) {
    if (!localizer_) {
      if (is_static || early_tf_.size() < 10000) early_tf_.emplace_back(to_vdtnav(m), is_static);
      return;
    }
    publish(localizer_->add_transforms(to_vdtnav(m), is_static));
  }

  void on_scan(const sensor_msgs::LaserScan::ConstPtr& m) {
    if (!localizer_) {
      ROS_WARN_THROTTLE(5.0, "vdtnav_localizer: no map yet; scans ignored");
      return;
    }
    arrival_[to_ns(m->header.stamp)] = std::chrono::steady_clock::now();
    publish(localizer_->add_scan(to_vdtnav(*m)));
  }

  void on_initial_pose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) {
    const std::string frame = vr::strip_slash(m->header.frame_id);
    if (!frame.empty() && frame != global_frame_) {
      ROS_WARN("vdtnav_localizer: initial pose in frame '%s' ignored: expected '%s'", frame.c_str(),
               global_frame_.c_str());
      return;
    }
    const vdtnav::Pose2 pose(m->pose.pose.position.x, m->pose.pose.position.y,
                             yaw_of(m->pose.pose.orientation));
    // Rows and columns x, y, yaw of the 6x6 (x, y, z, roll, pitch, yaw).
    Eigen::Matrix3d cov;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        cov(r, c) = m->pose.covariance[kPlanarIndex[r] * 6 + kPlanarIndex[c]];
    }
    if (!localizer_) {
      initial_pose_ = pose;
      initial_cov_ = cov.diagonal();
      return;
    }
    try {
      localizer_->set_pose(pose, cov);
      ROS_INFO("vdtnav_localizer: initial pose (%.3f, %.3f, %.3f)", pose[0], pose[1], pose[2]);
    } catch (const vdtnav::Error& e) {
      ROS_WARN("vdtnav_localizer: initial pose ignored: %s", e.what());
    }
  }

  bool on_global(std_srvs::Empty::Request& /*req*/, std_srvs::Empty::Response& /*res*/) {
    if (!localizer_) return false;
    localizer_->start_global();
    ROS_INFO("vdtnav_localizer: global localization: searching the whole map");
    return true;
  }

  void publish(const std::vector<vr::LiveEstimate>& estimates) {
    for (const vr::LiveEstimate& e : estimates) {
      const ros::Time stamp = from_ns(e.stamp_ns);
      const bool localized = e.event == vr::LiveEstimate::Event::kLocalized;
      // amcl_pose: the poses of the default outputs (converged, or bridged across a gap of the map
      // with its grown covariance: vdtnav::published_by_default()).
      if (localized && vdtnav::published_by_default(e.result.status)) publish_pose(stamp, e);
      if (tf_broadcast_ && e.has_map_to_odom &&
          (localized || e.event == vr::LiveEstimate::Event::kSkipped)) {
        geometry_msgs::TransformStamped t;
        // amcl's convention: valid transform_tolerance into the future.
        t.header.stamp = stamp + ros::Duration(transform_tolerance_);
        t.header.frame_id = global_frame_;
        t.child_frame_id = options_.odom_frame;
        t.transform.translation.x = e.map_to_odom[0];
        t.transform.translation.y = e.map_to_odom[1];
        t.transform.rotation.z = std::sin(0.5 * e.map_to_odom[2]);
        t.transform.rotation.w = std::cos(0.5 * e.map_to_odom[2]);
        broadcaster_.sendTransform(t);
      }
      publish_status(stamp, e);
      if (e.event == vr::LiveEstimate::Event::kNoOdometry) {
        ROS_WARN_THROTTLE(5.0, "vdtnav_localizer: scan at %.3f not localized: %s", stamp.toSec(),
                          e.reason.c_str());
      }
    }
  }

  void publish_pose(const ros::Time& stamp, const vr::LiveEstimate& e) {
    geometry_msgs::PoseWithCovarianceStamped p;
    p.header.stamp = stamp;
    p.header.frame_id = global_frame_;
    p.pose.pose.position.x = e.result.pose[0];
    p.pose.pose.position.y = e.result.pose[1];
    p.pose.pose.orientation.z = std::sin(0.5 * e.result.pose[2]);
    p.pose.pose.orientation.w = std::cos(0.5 * e.result.pose[2]);
    if (e.result.has_covariance) {
      // Symmetric to the last bit, as consumers of the message assume.
      const Eigen::Matrix3d c = 0.5 * (e.result.covariance + e.result.covariance.transpose());
      for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 3; ++k)
          p.pose.covariance[kPlanarIndex[r] * 6 + kPlanarIndex[k]] = c(r, k);
      }
    }
    pose_pub_.publish(p);
  }

  void publish_status(const ros::Time& stamp, const vr::LiveEstimate& e) {
    double latency_ms = std::nan("");
    const auto it = arrival_.find(e.stamp_ns);
    if (it != arrival_.end()) {
      latency_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - it->second)
              .count();
      arrival_.erase(arrival_.begin(), std::next(it));
    }
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "vdtnav_localizer";
    s.hardware_id = options_.method;
    const bool localized = e.event == vr::LiveEstimate::Event::kLocalized;
    const vdtnav::LocalizationStatus st = e.result.status;
    std::string token = localized ? vdtnav::to_string(st) : vr::to_string(e.event);
    for (char& c : token) c = c == ' ' ? '_' : c;
    s.message = token;
    s.level = localized && st == vdtnav::LocalizationStatus::kConverged ? s.OK
              : localized && (st == vdtnav::LocalizationStatus::kLost ||
                              st == vdtnav::LocalizationStatus::kDiverged)
                  ? s.ERROR
                  : s.WARN;
    auto kv = [&s](const std::string& k, const std::string& v) {
      diagnostic_msgs::KeyValue x;
      x.key = k;
      x.value = v;
      s.values.push_back(std::move(x));
    };
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9f", stamp.toSec());
    kv("stamp", buf);
    std::snprintf(buf, sizeof buf, "%.4f", localized ? e.result.explained : std::nan(""));
    kv("explained", buf);
    std::snprintf(buf, sizeof buf, "%.3f", 1e3 * e.seconds);
    kv("processing_ms", buf);
    std::snprintf(buf, sizeof buf, "%.3f", latency_ms);
    kv("latency_ms", buf);  // scan callback to this message: waiting for odometry included
    kv("waiting", std::to_string(localizer_->waiting()));
    if (!e.reason.empty()) kv("reason", e.reason);
    status_pub_.publish(s);
  }

  ros::NodeHandle nh_, pnh_;
  std::string global_frame_, config_, map_file_;
  double transform_tolerance_ = 0.1;
  bool tf_broadcast_ = true, use_map_topic_ = false, first_map_only_ = false;
  vdtnav::Pose2 initial_pose_ = vdtnav::Pose2::Zero();
  Eigen::Vector3d initial_cov_ = Eigen::Vector3d::Zero();
  vr::LiveLocalizerOptions options_;
  vdtnav::LocalizerSettings settings_;
  std::unique_ptr<vr::LiveLocalizer> localizer_;
  std::vector<std::pair<vr::TfMsg, bool>> early_tf_;
  std::map<std::int64_t, std::chrono::steady_clock::time_point> arrival_;
  ros::Publisher pose_pub_, status_pub_;
  ros::Subscriber scan_sub_, tf_sub_, tf_static_sub_, initial_pose_sub_, map_sub_;
  ros::ServiceServer global_srv_;
  tf2_ros::TransformBroadcaster broadcaster_;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "vdtnav_localizer");
  try {
    LocalizerNode node;
    ros::spin();
  } catch (const vdtnav::Error& e) {
    ROS_FATAL("vdtnav_localizer: %s", e.what());
    return 2;
  }
  return 0;
}
