#pragma once
/// \file
/// \brief What a node in amcl's place does, whatever carries its messages: the ROS 1 node
/// (`vdtnav_localizer`, roscpp) and the ROS 2 node (`vdtnav_ros2_localizer`, Fast DDS) feed it
/// decoded messages (messages.hpp) and publish what it returns. Over LiveLocalizer (the scans
/// localized exactly as `vdtnav localize --bag` localizes them):
/// - the map: an OccupancyGrid (or a map file) becomes the localizer's map; transforms and
///   scans that arrive before the first map are kept (the latched static transforms above all;
///   the last kEarlyScans scans) and replayed in their order once it is there;
/// - the start: the initial pose of the parameters, then `initialpose` messages in the global
///   frame (others are refused with the reason), or a global search on request;
/// - out, per scan: `amcl_pose` for the poses of the default outputs (converged, or bridged
///   across a gap of the map with its grown covariance: published_by_default()), with the 6x6
///   row-major covariance over x, y, z, roll, pitch, yaw (z, roll, pitch not estimated: 0); the
///   global -> odom transform stamped scan stamp + transform_tolerance (amcl's convention) for
///   every scan localized or skipped once a pose is known; and a status row (what became of the
///   scan, its time, the latency from its arrival).

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/live_localizer.hpp"
#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

/// \brief A node's settings beyond the stream localizer's (amcl's names in the comments).
struct NodeOptions {
  LiveLocalizerOptions live;         ///< frames, mounting, update rule, method
  std::string global_frame = "map";  ///< global_frame_id
  double transform_tolerance = 0.1;  ///< s the map -> odom transform is post-dated by
  bool tf_broadcast = true;          ///< publish map -> odom
  bool first_map_only = false;       ///< ignore maps after the first
  /// Where tracking starts once the map is there (initial_pose_*), and its covariance.
  Pose2 initial_pose = Pose2::Zero();
  Eigen::Matrix3d initial_covariance = Eigen::Vector3d(0.25, 0.25, 0.0685).asDiagonal();
  /// Whether the initial pose is known (false: wait for `initialpose` or a global search).
  bool has_initial_pose = true;
};

/// \brief What became of one scan, for the node's status topic.
struct NodeStatus {
  std::int64_t stamp_ns = 0;
  std::string
      token;  ///< "converged", "bridged", "lost", ..., "skipped", "no_odometry", "no_transform"
  /// 0 OK (converged), 1 WARN, 2 ERROR (lost, diverged): diagnostic_msgs' levels.
  int level = 1;
  double explained = 0.0;      ///< NaN unless localized
  double processing_ms = 0.0;  ///< the localizer's time for this scan
  double latency_ms = 0.0;     ///< from the scan's arrival to now (NaN: arrival unknown)
  std::size_t waiting = 0;     ///< scans waiting for their odometry
  std::string reason;          ///< why not localized (no_odometry, no_transform)
};

/// \brief The messages a node publishes after one input.
struct NodeOutput {
  std::vector<PoseWithCovarianceStampedMsg> poses;  ///< amcl_pose
  TfMsg tf;                                         ///< global -> odom on /tf
  std::vector<NodeStatus> statuses;
  /// Said once, for the log: map loaded, initial pose taken or refused, ...
  std::vector<std::string> log;
};

/// \brief The node's core (see the file comment). Not thread-safe: one caller feeds it.
class NodeCore {
 public:
  NodeCore(NodeOptions options, LocalizerSettings settings);
  ~NodeCore();
  NodeCore(const NodeCore&) = delete;
  NodeCore& operator=(const NodeCore&) = delete;

  /// \brief A map from `source` ("topic /map", "file map.yaml"); the first builds the localizer.
  NodeOutput set_map(RosMap map, const std::string& source);
  /// \brief /tf or /tf_static.
  NodeOutput add_transforms(const TfMsg& tf, bool is_static);
  /// \brief A scan that arrived at `arrival` (for the latency).
  NodeOutput add_scan(const LaserScanMsg& scan, std::chrono::steady_clock::time_point arrival =
                                                    std::chrono::steady_clock::now());
  /// \brief `initialpose`: taken in the global frame (or with no frame), refused otherwise.
  NodeOutput set_initial_pose(const PoseWithCovarianceStampedMsg& pose);
  /// \brief Global localization: the next scans are searched for in the whole map (asked before
  /// the first map: once it is there, instead of the initial pose).
  void start_global();
  /// \brief The next scan is localized however little the robot moved.
  /// \return false before there is a map.
  bool request_update();

  [[nodiscard]] bool has_map() const noexcept { return localizer_ != nullptr; }
  [[nodiscard]] const NodeOptions& options() const noexcept { return options_; }
  [[nodiscard]] const LiveLocalizer* localizer() const noexcept { return localizer_.get(); }

 private:
  NodeOutput publish(const std::vector<LiveEstimate>& estimates);

  NodeOptions options_;
  LocalizerSettings settings_;
  std::unique_ptr<LiveLocalizer> localizer_;
  /// What arrived before the first map, in order: a transform message (is_static) or a scan.
  struct Early {
    std::optional<TfMsg> tf;
    bool is_static = false;
    std::optional<LaserScanMsg> scan;
    std::chrono::steady_clock::time_point arrival;
  };
  std::vector<Early> early_;
  std::size_t early_scans_ = 0;
  bool warned_early_ = false;
  bool global_requested_ = false;
  std::map<std::int64_t, std::chrono::steady_clock::time_point> arrival_;
};

/// Scans kept while there is no map (a bag played with its map: the map may come after them).
inline constexpr std::size_t kEarlyScans = 200;

/// \brief An OccupancyGrid as a map_server map (data row-major from the origin cell, -1
/// unknown; the resolution as the decimal the float32 was rounded from, so that the map from
/// the topic has the geometry of the same map loaded from its file).
/// \throws ConfigError when the sizes do not agree or the resolution is not positive.
[[nodiscard]] RosMap to_ros_map(const OccupancyGridMsg& grid);

/// \brief The yaw of a planar rotation (z up).
[[nodiscard]] double yaw_of(const Eigen::Quaterniond& q);

}  // namespace vdtnav::ros
