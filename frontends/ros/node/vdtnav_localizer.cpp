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
#include "vdtnav/ros/node_core.hpp"

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

/// An OccupancyGrid as messages.hpp's struct (NodeCore makes the map of it).
vr::OccupancyGridMsg to_vdtnav(const nav_msgs::OccupancyGrid& m) {
  vr::OccupancyGridMsg g;
  g.header.stamp_ns = to_ns(m.header.stamp);
  g.header.frame_id = m.header.frame_id;
  g.info.resolution = m.info.resolution;
  g.info.width = m.info.width;
  g.info.height = m.info.height;
  g.info.origin.position = {m.info.origin.position.x, m.info.origin.position.y,
                            m.info.origin.position.z};
  g.info.origin.orientation =
      Eigen::Quaterniond(m.info.origin.orientation.w, m.info.origin.orientation.x,
                         m.info.origin.orientation.y, m.info.origin.orientation.z);
  g.data = m.data;
  return g;
}

vr::PoseWithCovarianceStampedMsg to_vdtnav(const geometry_msgs::PoseWithCovarianceStamped& m) {
  vr::PoseWithCovarianceStampedMsg p;
  p.header.stamp_ns = to_ns(m.header.stamp);
  p.header.frame_id = m.header.frame_id;
  p.pose.pose.position = {m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z};
  p.pose.pose.orientation =
      Eigen::Quaterniond(m.pose.pose.orientation.w, m.pose.pose.orientation.x,
                         m.pose.pose.orientation.y, m.pose.pose.orientation.z);
  std::copy(m.pose.covariance.begin(), m.pose.covariance.end(), p.pose.covariance.begin());
  return p;
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
    vr::NodeOptions o;
    pnh_.param<std::string>("global_frame_id", o.global_frame, "map");
    pnh_.param<std::string>("odom_frame_id", o.live.odom_frame, "odom");
    pnh_.param<std::string>("base_frame_id", o.live.base_frame, "base_link");
    pnh_.param("update_min_d", o.live.update_min_d, 0.0);
    pnh_.param("update_min_a", o.live.update_min_a, 0.0);
    double max_range = -1.0;
    pnh_.param("laser_max_range", max_range, -1.0);
    o.live.max_range = max_range > 0.0 ? max_range : std::nan("");
    pnh_.param("transform_tolerance", o.transform_tolerance, 0.1);
    pnh_.param("tf_broadcast", o.tf_broadcast, true);
    pnh_.param("use_map_topic", use_map_topic_, false);
    pnh_.param("first_map_only", o.first_map_only, false);
    pnh_.param("initial_pose_x", o.initial_pose[0], 0.0);
    pnh_.param("initial_pose_y", o.initial_pose[1], 0.0);
    pnh_.param("initial_pose_a", o.initial_pose[2], 0.0);
    Eigen::Vector3d cov;
    pnh_.param("initial_cov_xx", cov[0], 0.5 * 0.5);
    pnh_.param("initial_cov_yy", cov[1], 0.5 * 0.5);
    pnh_.param("initial_cov_aa", cov[2], (kPi / 12.0) * (kPi / 12.0));
    o.initial_covariance = cov.asDiagonal();
    // vdtnav's own: the settings file, the method, a map file, the scanner's mounting when TF
    // lacks it, the range noise, how far the odometry may be extrapolated to a scan's stamp.
    pnh_.param<std::string>("config", config_, "");
    pnh_.param<std::string>("method", o.live.method, "vdt-opt");
    pnh_.param<std::string>("map_file", map_file_, "");
    std::string laser_pose;
    pnh_.param<std::string>("laser_pose", laser_pose, "");
    o.live.laser_pose = parse_pose_param(laser_pose, "laser_pose");
    pnh_.param("sigma_range", o.live.sigma_range, 0.02);
    pnh_.param("odom_extrapolation", o.live.odom_extrapolation, 0.0);
    vdtnav::LocalizerSettings settings = vdtnav::log_settings();
    if (!config_.empty()) settings = vdtnav::load_localizer_config(config_, settings);
    core_ = std::make_unique<vr::NodeCore>(o, settings);

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
      if (ros::ok()) set_map(vr::to_ros_map(to_vdtnav(srv.response.map)), "service static_map");
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
    publish(core_->set_map(std::move(map), source));
    ROS_INFO("vdtnav_localizer: %s%s, starting at (%.3f, %.3f, %.3f)",
             core_->options().live.method.c_str(),
             config_.empty() ? "" : (" with " + config_).c_str(), core_->options().initial_pose[0],
             core_->options().initial_pose[1], core_->options().initial_pose[2]);
  }

  void on_map(const nav_msgs::OccupancyGrid::ConstPtr& m) {
    try {
      set_map(vr::to_ros_map(to_vdtnav(*m)), "topic " + map_sub_.getTopic());
    } catch (const vdtnav::Error& e) {
      ROS_ERROR("vdtnav_localizer: map refused: %s", e.what());
    }
  }

  void on_tf(const tf2_msgs::TFMessage::ConstPtr& m) {
    publish(core_->add_transforms(to_vdtnav(*m), false));
  }
  void on_tf_static(const tf2_msgs::TFMessage::ConstPtr& m) {
    publish(core_->add_transforms(to_vdtnav(*m), true));
  }
  void on_scan(const sensor_msgs::LaserScan::ConstPtr& m) {
    publish(core_->add_scan(to_vdtnav(*m)));
  }
  void on_initial_pose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) {
    publish(core_->set_initial_pose(to_vdtnav(*m)));
  }

  bool on_global(std_srvs::Empty::Request& /*req*/, std_srvs::Empty::Response& /*res*/) {
    if (!core_->has_map()) return false;
    core_->start_global();
    ROS_INFO("vdtnav_localizer: global localization: searching the whole map");
    return true;
  }

  void publish(const vr::NodeOutput& out) {
    for (const std::string& l : out.log) ROS_INFO("vdtnav_localizer: %s", l.c_str());
    for (const vr::PoseWithCovarianceStampedMsg& p : out.poses) {
      geometry_msgs::PoseWithCovarianceStamped m;
      m.header.stamp = from_ns(p.header.stamp_ns);
      m.header.frame_id = p.header.frame_id;
      m.pose.pose.position.x = p.pose.pose.position.x();
      m.pose.pose.position.y = p.pose.pose.position.y();
      m.pose.pose.orientation.z = p.pose.pose.orientation.z();
      m.pose.pose.orientation.w = p.pose.pose.orientation.w();
      std::copy(p.pose.covariance.begin(), p.pose.covariance.end(), m.pose.covariance.begin());
      pose_pub_.publish(m);
    }
    for (const vr::TransformStampedMsg& t : out.tf.transforms) {
      geometry_msgs::TransformStamped m;
      m.header.stamp = from_ns(t.header.stamp_ns);
      m.header.frame_id = t.header.frame_id;
      m.child_frame_id = t.child_frame_id;
      m.transform.translation.x = t.translation.x();
      m.transform.translation.y = t.translation.y();
      m.transform.rotation.z = t.rotation.z();
      m.transform.rotation.w = t.rotation.w();
      broadcaster_.sendTransform(m);
    }
    for (const vr::NodeStatus& st : out.statuses) publish_status(st);
  }

  void publish_status(const vr::NodeStatus& st) {
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "vdtnav_localizer";
    s.hardware_id = core_->options().live.method;
    s.message = st.token;
    s.level = st.level == 0 ? s.OK : st.level == 2 ? s.ERROR : s.WARN;
    auto kv = [&s](const std::string& k, const std::string& v) {
      diagnostic_msgs::KeyValue x;
      x.key = k;
      x.value = v;
      s.values.push_back(std::move(x));
    };
    char stamp[64], buf[64];
    std::snprintf(stamp, sizeof stamp, "%.9f", from_ns(st.stamp_ns).toSec());
    kv("stamp", stamp);
    std::snprintf(buf, sizeof buf, "%.4f", st.explained);
    kv("explained", buf);
    std::snprintf(buf, sizeof buf, "%.3f", st.processing_ms);
    kv("processing_ms", buf);
    std::snprintf(buf, sizeof buf, "%.3f", st.latency_ms);
    kv("latency_ms", buf);  // scan callback to this message: waiting for odometry included
    kv("waiting", std::to_string(st.waiting));
    if (!st.reason.empty()) kv("reason", st.reason);
    status_pub_.publish(s);
    if (st.token == "no_odometry" || st.token == "no_transform") {
      ROS_WARN_THROTTLE(5.0, "vdtnav_localizer: scan at %s not localized: %s", stamp,
                        st.reason.c_str());
    }
  }

  ros::NodeHandle nh_, pnh_;
  std::string config_, map_file_;
  bool use_map_topic_ = false;
  std::unique_ptr<vr::NodeCore> core_;
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
