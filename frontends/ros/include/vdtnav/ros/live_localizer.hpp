#pragma once
/// \file
/// \brief Localization of a live scan stream, as a node runs it: scans and transforms arrive in
/// any order, each scan waits until the odometry (TF odom -> base) is known at its header stamp,
/// then it is localized exactly as `vdtnav localize --bag` localizes the same scan (the same
/// settings, the same odometry step from the previous scan, the same mounting), so that a node
/// and the CLI give the same poses. ROS-free: the ROS 1 node (`vdtnav_localizer`) feeds it
/// decoded messages (messages.hpp) and publishes what it returns; a ROS 2 node would do the
/// same.
///
/// What a scan becomes (LiveEstimate::event):
/// - localized: the localizer's result (status converged, not converged, lost, ...), or, while a
///   global localization is pending, the global search's (accepted: converged; else refused);
/// - skipped: the robot moved less than update_min_d and update_min_a since the last scan
///   localized (amcl's parameters; 0 and 0, the defaults, localize every scan);
/// - no_pose: no initial pose yet (set_pose() or start_global());
/// - no_odometry: the odometry is not known at the stamp and will not be (transforms newer than
///   the stamp arrived without connecting odom -> base, or more than max_queue scans wait);
/// - no_transform: the same for the mounting, base -> the scan's frame (a scan older than the
///   first mounting transform, as `vdtnav localize --bag` leaves it out). The mounting is looked
///   up once, at the first scan it is known at.
/// With odom_extrapolation > 0 a scan up to that much newer than the odometry is localized at
/// once, on the odometry extrapolated to its stamp (lower latency, poses no longer bit-equal to
/// the CLI's).
/// While a global localization is pending only the newest waiting scan is searched: the search
/// costs more than a scan period, and the older scans are no_pose.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/messages.hpp"
#include "vdtnav/ros/transform_buffer.hpp"

namespace vdtnav::ros {

/// \brief Frames, mounting and the update rule (amcl's names where the meaning is the same).
struct LiveLocalizerOptions {
  std::string method = "vdt-opt";   ///< a localizer_methods() name
  std::string odom_frame = "odom";  ///< odom_frame_id
  std::string base_frame = "base_link";
  /// The scanner's pose in base_frame (x, y, yaw) when TF has no base -> scan-frame transform.
  std::optional<Pose2> laser_pose;
  double update_min_d = 0.0;  ///< m: a scan is localized once the robot moved this far ...
  double update_min_a = 0.0;  ///< rad: ... or turned this much (0, 0: every scan)
  double sigma_range = 0.02;  ///< range noise standard deviation, m
  /// Readings at or beyond this are no returns (NaN: the message's own range_max).
  double max_range = std::numeric_limits<double>::quiet_NaN();
  /// Initial standard deviations (x, y, yaw) where no covariance is known: a pose found by a
  /// global search without one, or the last pose carried onto a new map (set_map()).
  Eigen::Vector3d init_sigma{0.1, 0.1, 0.05};
  /// Seconds a scan may be newer than the newest odometry and still be localized at once, with
  /// the odometry extrapolated at the velocity of its last 0.1 s. 0 (the default): a scan waits
  /// for the odometry after its stamp, as amcl does, and the poses are those of `vdtnav
  /// localize --bag`; a node's latency then includes that wait (up to one odometry period).
  double odom_extrapolation = 0.0;
  std::size_t max_queue = 200;  ///< scans that may wait for their odometry
  double tf_span = 30.0;        ///< seconds of transforms kept
};

/// \brief What became of one scan.
struct LiveEstimate {
  enum class Event { kLocalized, kSkipped, kNoPose, kNoOdometry, kNoTransform };
  Event event = Event::kNoPose;
  std::int64_t stamp_ns = 0;
  LocalizationResult result;  ///< kLocalized: status, pose, covariance, explained
  Pose2 odometry;             ///< base_frame in odom_frame at the stamp (not kNoOdometry)
  bool has_map_to_odom = false;
  /// odom_frame in the map frame from the last converged pose (pose (+) odometry^-1), eq. of
  /// REP 105: what a node broadcasts as map -> odom.
  Pose2 map_to_odom = Pose2::Zero();
  double seconds = 0.0;  ///< processing time of this scan
  std::string reason;    ///< kNoOdometry, kNoTransform: why
};

/// \return "localized", "skipped", "no_pose", "no_odometry" or "no_transform".
[[nodiscard]] const char* to_string(LiveEstimate::Event e);

/// \brief The stream localizer (see the file comment). Not thread-safe: one caller feeds it.
class LiveLocalizer {
 public:
  /// \brief Builds the VDT map of `map` and a localizer of `options.method` with `settings`.
  /// \throws ConfigError for an unknown method or bad settings.
  LiveLocalizer(RosMap map, const LocalizerSettings& settings, LiveLocalizerOptions options);
  ~LiveLocalizer();
  LiveLocalizer(const LiveLocalizer&) = delete;
  LiveLocalizer& operator=(const LiveLocalizer&) = delete;

  /// \brief A new map: the localizer restarts on it from the last pose known (or waits for one).
  void set_map(RosMap map);
  /// \brief Starts tracking at `pose` (map frame) with `covariance` at the next scan.
  void set_pose(const Pose2& pose, const Eigen::Matrix3d& covariance);
  /// \brief Forgets the pose: the next scans are searched for in the whole map (branch and
  /// bound, settings section global:) until one is accepted.
  void start_global();
  [[nodiscard]] bool global_pending() const noexcept { return global_pending_; }
  /// \brief The next scan is localized however little the robot moved (amcl's
  /// request_nomotion_update).
  void request_update() noexcept { force_update_ = true; }

  /// \brief Adds transforms (from /tf, or /tf_static when is_static); returns the scans this
  /// made localizable, in stamp order.
  [[nodiscard]] std::vector<LiveEstimate> add_transforms(const TfMsg& tf, bool is_static);
  /// \brief Queues a scan; returns the scans now localizable (this one if its odometry is known).
  [[nodiscard]] std::vector<LiveEstimate> add_scan(const LaserScanMsg& scan);

  /// \return the scans waiting for their odometry.
  [[nodiscard]] std::size_t waiting() const noexcept { return queue_.size(); }
  [[nodiscard]] const RosMap& map() const noexcept { return map_; }
  [[nodiscard]] const LocalizerSettings& settings() const noexcept { return settings_; }
  /// \return where the mounting came from ("TF base_link -> laser", "laser_pose", ...); empty
  /// before the first scan.
  [[nodiscard]] const std::string& mount_source() const noexcept { return mount_source_; }

 private:
  void build();
  std::vector<LiveEstimate> drain();
  LiveEstimate localize(const LaserScanMsg& msg, const Pose2& odometry);
  [[nodiscard]] std::optional<Pose2> mount_for(const LaserScanMsg& msg);
  [[nodiscard]] std::optional<Pose2> odometry_at(std::int64_t stamp) const;

  RosMap map_;
  LocalizerSettings settings_;
  LiveLocalizerOptions options_;
  struct MapState;
  std::unique_ptr<MapState> state_;  // occupancy, VDT map, knowledge, localizer, global search
  TransformBuffer tf_;
  std::deque<LaserScanMsg> queue_;
  std::int64_t newest_tf_ns_ = std::numeric_limits<std::int64_t>::min();

  // The track.
  std::optional<Pose2> mount_;
  std::string mount_source_;
  std::optional<std::pair<Pose2, Eigen::Matrix3d>> pending_reset_;
  bool global_pending_ = false;
  bool force_update_ = false;
  bool tracking_ = false;
  Pose2 last_pose_ = Pose2::Zero();
  bool has_last_pose_ = false;
  Pose2 last_odometry_ = Pose2::Zero();  // at the last scan localized
  double last_time_ = 0.0;
  std::optional<Pose2> map_to_odom_;
};

}  // namespace vdtnav::ros
