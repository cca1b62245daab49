// A node in amcl's place, ROS-free (node_core.hpp): what both node generations share.
#include "vdtnav/ros/node_core.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::ros {
namespace {

/// x, y and yaw are rows and columns 0, 1 and 5 of a 6x6 pose covariance (x, y, z, roll, pitch,
/// yaw), row-major.
constexpr int kPlanarIndex[3] = {0, 1, 5};

/// The shortest decimal that reads back as the same float (map_server writes the YAML's
/// resolution, 0.05, as the float 0.0500000007).
double decimal_of(float f) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, f);
  return std::strtod(std::string(buf, r.ptr).c_str(), nullptr);
}

Eigen::Quaterniond planar(double yaw) {
  return Eigen::Quaterniond(std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw));
}

}  // namespace

double yaw_of(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                    1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

RosMap to_ros_map(const OccupancyGridMsg& m) {
  const auto w = static_cast<int>(m.info.width), h = static_cast<int>(m.info.height);
  if (w <= 0 || h <= 0 || m.data.size() != static_cast<std::size_t>(w) * h ||
      !(m.info.resolution > 0.0F)) {
    throw ConfigError("map: an OccupancyGrid of " + std::to_string(w) + " x " + std::to_string(h) +
                      " cells of " + std::to_string(m.info.resolution) + " m holds " +
                      std::to_string(m.data.size()) + " values");
  }
  const double yaw = yaw_of(m.info.origin.orientation);
  const double resolution = decimal_of(m.info.resolution);
  const Eigen::Vector2d origin = m.info.origin.position.head<2>();
  RosMap map;
  map.metadata.resolution = resolution;
  map.metadata.origin = {origin.x(), origin.y(), yaw};
  map.cells = Grid<std::int8_t, 2>(Eigen::Vector2i(w, h), GridFrame<2>(resolution, origin, yaw));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      map.cells(Eigen::Vector2i(i, j)) = m.data[static_cast<std::size_t>(j) * w + i];
    }
  }
  return map;
}

NodeCore::NodeCore(NodeOptions options, LocalizerSettings settings)
    : options_(std::move(options)), settings_(std::move(settings)) {}

NodeCore::~NodeCore() = default;

NodeOutput NodeCore::set_map(RosMap map, const std::string& source) {
  NodeOutput out;
  if (options_.first_map_only && localizer_) return out;
  const auto t0 = std::chrono::steady_clock::now();
  const int w = map.cells.size().x(), h = map.cells.size().y();
  const double res = map.cells.resolution();
  if (localizer_) {
    localizer_->set_map(std::move(map));
  } else {
    localizer_ = std::make_unique<LiveLocalizer>(std::move(map), settings_, options_.live);
    if (global_requested_) {
      localizer_->start_global();
    } else if (options_.has_initial_pose) {
      localizer_->set_pose(options_.initial_pose, options_.initial_covariance);
    }
    // What arrived before the map (the latched static transforms above all), in its order.
    for (const Early& e : early_) {
      const NodeOutput o = e.tf ? add_transforms(*e.tf, e.is_static) : add_scan(*e.scan, e.arrival);
      out.poses.insert(out.poses.end(), o.poses.begin(), o.poses.end());
      out.tf.transforms.insert(out.tf.transforms.end(), o.tf.transforms.begin(),
                               o.tf.transforms.end());
      out.statuses.insert(out.statuses.end(), o.statuses.begin(), o.statuses.end());
    }
    early_.clear();
    early_scans_ = 0;
  }
  char line[256];
  std::snprintf(line, sizeof line, "map from %s, %d x %d cells of %.3f m, VDT built in %.2f s",
                source.c_str(), w, h, res,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  out.log.emplace_back(line);
  return out;
}

NodeOutput NodeCore::add_transforms(const TfMsg& tf, bool is_static) {
  if (!localizer_) {
    if (is_static || early_.size() < 10000) early_.push_back({tf, is_static, std::nullopt, {}});
    return {};
  }
  return publish(localizer_->add_transforms(tf, is_static));
}

NodeOutput NodeCore::add_scan(const LaserScanMsg& scan,
                              std::chrono::steady_clock::time_point arrival) {
  if (!localizer_) {
    NodeOutput out;
    if (early_scans_ == kEarlyScans) {
      // The oldest scan kept goes (the transforms stay: the odometry of the scans kept).
      const auto oldest = std::find_if(early_.begin(), early_.end(),
                                       [](const Early& e) { return e.scan.has_value(); });
      early_.erase(oldest);
      --early_scans_;
      if (!warned_early_) out.log.emplace_back("no map yet: keeping the last scans until it comes");
      warned_early_ = true;
    }
    early_.push_back({std::nullopt, false, scan, arrival});
    ++early_scans_;
    return out;
  }
  arrival_[scan.header.stamp_ns] = arrival;
  return publish(localizer_->add_scan(scan));
}

NodeOutput NodeCore::set_initial_pose(const PoseWithCovarianceStampedMsg& m) {
  NodeOutput out;
  const std::string frame = strip_slash(m.header.frame_id);
  if (!frame.empty() && frame != options_.global_frame) {
    out.log.push_back("initial pose in frame '" + frame + "' ignored: expected '" +
                      options_.global_frame + "'");
    return out;
  }
  const Pose2 pose(m.pose.pose.position.x(), m.pose.pose.position.y(),
                   yaw_of(m.pose.pose.orientation));
  Eigen::Matrix3d cov;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      cov(r, c) = m.pose.covariance[kPlanarIndex[r] * 6 + kPlanarIndex[c]];
  }
  if (!localizer_) {
    options_.initial_pose = pose;
    options_.initial_covariance = cov;
    options_.has_initial_pose = true;
    return out;
  }
  try {
    localizer_->set_pose(pose, cov);
    char line[128];
    std::snprintf(line, sizeof line, "initial pose (%.3f, %.3f, %.3f)", pose[0], pose[1], pose[2]);
    out.log.emplace_back(line);
  } catch (const Error& e) {
    out.log.push_back(std::string("initial pose ignored: ") + e.what());
  }
  return out;
}

void NodeCore::start_global() {
  if (localizer_) {
    localizer_->start_global();
  } else {
    global_requested_ = true;
  }
}

bool NodeCore::request_update() {
  if (!localizer_) return false;
  localizer_->request_update();
  return true;
}

NodeOutput NodeCore::publish(const std::vector<LiveEstimate>& estimates) {
  NodeOutput out;
  const auto now = std::chrono::steady_clock::now();
  for (const LiveEstimate& e : estimates) {
    const bool localized = e.event == LiveEstimate::Event::kLocalized;
    if (localized && published_by_default(e.result.status)) {
      PoseWithCovarianceStampedMsg p;
      p.header.stamp_ns = e.stamp_ns;
      p.header.frame_id = options_.global_frame;
      p.pose.pose.position = Eigen::Vector3d(e.result.pose[0], e.result.pose[1], 0.0);
      p.pose.pose.orientation = planar(e.result.pose[2]);
      if (e.result.has_covariance) {
        // Symmetric to the last bit, as consumers of the message assume.
        const Eigen::Matrix3d c = 0.5 * (e.result.covariance + e.result.covariance.transpose());
        for (int r = 0; r < 3; ++r) {
          for (int k = 0; k < 3; ++k)
            p.pose.covariance[kPlanarIndex[r] * 6 + kPlanarIndex[k]] = c(r, k);
        }
      }
      out.poses.push_back(std::move(p));
    }
    if (options_.tf_broadcast && e.has_map_to_odom &&
        (localized || e.event == LiveEstimate::Event::kSkipped)) {
      TransformStampedMsg t;
      // amcl's convention: valid transform_tolerance into the future.
      t.header.stamp_ns =
          e.stamp_ns + static_cast<std::int64_t>(std::llround(1e9 * options_.transform_tolerance));
      t.header.frame_id = options_.global_frame;
      t.child_frame_id = options_.live.odom_frame;
      t.translation = Eigen::Vector3d(e.map_to_odom[0], e.map_to_odom[1], 0.0);
      t.rotation = planar(e.map_to_odom[2]);
      out.tf.transforms.push_back(std::move(t));
    }
    NodeStatus s;
    s.stamp_ns = e.stamp_ns;
    const LocalizationStatus st = e.result.status;
    s.token = localized ? to_string(st) : to_string(e.event);
    for (char& c : s.token) c = c == ' ' ? '_' : c;
    s.level =
        localized && st == LocalizationStatus::kConverged                                       ? 0
        : localized && (st == LocalizationStatus::kLost || st == LocalizationStatus::kDiverged) ? 2
                                                                                                : 1;
    s.explained = localized ? e.result.explained : std::nan("");
    s.processing_ms = 1e3 * e.seconds;
    s.latency_ms = std::nan("");
    const auto it = arrival_.find(e.stamp_ns);
    if (it != arrival_.end()) {
      s.latency_ms = std::chrono::duration<double, std::milli>(now - it->second).count();
      arrival_.erase(arrival_.begin(), std::next(it));
    }
    s.waiting = localizer_->waiting();
    s.reason = e.reason;
    out.statuses.push_back(std::move(s));
  }
  return out;
}

}  // namespace vdtnav::ros
