#pragma once
/// \file
/// \brief A 2D LiDAR run read from a bag: each LaserScan with the robot's odometry pose at its
/// header stamp and the scanner's mounting pose — what `vdtnav localize --bag` localizes.
///
/// Where things come from (REP 105 names by default):
/// - scans: `scan_topic`, or the bag's only sensor_msgs/LaserScan topic, or of several the one
///   named `scan` (`/scan`), as nav2's amcl subscribes `scan` (ScanSequence::scan_topic_choice says
///   so);
/// - odometry: `odom_topic` when given; otherwise TF odom_frame -> base_frame when the bag's /tf
///   connects them; otherwise the bag's only nav_msgs/Odometry topic; interpolated at each scan's
///   stamp. A transform tree that does not connect the robot's frames (another node's map -> odom)
///   is ignored;
/// - mounting: `laser_pose` when given (x, y, yaw), else base_frame -> the scan's frame from TF
///   (planar part: x, y, yaw), looked up at the first scan it is known at: scans older than the
///   first mounting transform (a real Neato bag's first scan is 79 µs older than its first /tf)
///   are left out and counted (`no_transform`), as are scans outside the odometry (`no_odometry`).
/// A missing topic, or a transform the bag never holds, is a ConfigError naming the topics or
/// frames the bag has.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::ros {

/// \brief Which topics and frames make up the run.
struct ScanSequenceOptions {
  std::string scan_topic;           ///< "" = the only LaserScan topic
  std::string odom_topic;           ///< "" = TF odom_frame -> base_frame, else the only Odometry
  std::string odom_frame = "odom";  ///< REP 105
  std::string base_frame = "base_link";
  std::optional<Pose2> laser_pose;  ///< mounting in base_frame; "" = from TF
  double sigma_range = 0.02;        ///< range noise standard deviation given to every scan, m
  /// Readings at or beyond this are no returns (NaN: the message's own range_max).
  double max_range = std::numeric_limits<double>::quiet_NaN();
};

/// \brief The run: scans in stamp order, each with its odometry pose.
struct ScanSequence {
  std::vector<LaserScan> scans;  ///< time = header stamp (s); mount set; invalid beams kept
  std::vector<Pose2> odometry;   ///< base_frame in odom_frame at each scan's stamp
  std::string scan_topic, scan_frame;
  std::string odometry_source;          ///< "TF odom -> base_link" or "topic /odom"
  std::string mount_source;             ///< "TF base_link -> laser" or "--laser-pose"
  std::string scan_topic_choice;        ///< "" or why scan_topic was taken among several
  std::size_t skipped_no_odometry = 0;  ///< scans outside the odometry's time span
  std::vector<double> skipped_times;    ///< their stamps, s
  /// Scans older than the first mounting transform (status no_transform), and their stamps, s.
  std::size_t skipped_no_transform = 0;
  std::vector<double> no_transform_times;
};

/// \brief Reads the run (see the file comment).
[[nodiscard]] ScanSequence read_scan_sequence(const BagReader& bag,
                                              const ScanSequenceOptions& options);

/// \brief A LaserScan message as vdtnav's LaserScan: beam i at angle_min + i angle_increment
/// (either sign), readings outside [range_min, range_max], 0, inf and NaN left to be dropped by
/// scan_points() (range_min raised above 0; range_max the message's or `max_range`).
[[nodiscard]] LaserScan to_laser_scan(const LaserScanMsg& m, const Pose2& mount, double sigma_range,
                                      double max_range);

/// \return the planar part (x, y, yaw) of a 3D pose.
[[nodiscard]] Pose2 planar(const Pose3& p);

}  // namespace vdtnav::ros
