#pragma once
/// \file
/// \brief A bag played onto a ROS 2 graph (`vdtnav bag play`): every message of the chosen
/// topics published over DDS with ROS 2's conventions (dds.hpp), at the bag's pace scaled by a
/// rate, in recorded order. A ROS 2 bag's messages go out as recorded (its CDR bytes as they
/// are); a ROS 1 bag's are decoded and encoded as ROS 2 CDR (the types of messages.hpp; other
/// types are not played, and said). QoS: what a ROS 2 bag recorded for the topic when it says
/// (metadata.yaml's offered_qos_profiles: not read yet), else `/tf_static` reliable, transient
/// local, keeping all its messages (one per static broadcaster of the recording) for late
/// joiners, and every other topic reliable, volatile, keep last 100 (a reliable writer serves
/// best-effort readers too).

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros2/dds.hpp"

namespace vdtnav::ros2 {

struct PlayOptions {
  double rate = 1.0;                ///< 2: twice the bag's pace; <= 0: as fast as DDS takes them
  std::vector<std::string> topics;  ///< empty: every topic of a type that can be played
  /// Before the first message, wait up to this many seconds until every topic's writer has a
  /// matched reader (0: do not wait).
  double wait_for_readers = 0.0;
  /// A map published first on map_topic (nav_msgs/OccupancyGrid, transient local), as nav2's
  /// map_server does: what a node in amcl's place needs besides the bag.
  std::optional<RosMap> map;
  std::string map_topic = "/map";
  /// Called after each message published (for progress).
  std::function<void(const ros::BagMessage&)> on_message;
};

struct PlayReport {
  std::size_t published = 0;
  std::vector<std::string> skipped_types;  ///< "topic (type)" not played
  double seconds = 0.0;                    ///< wall time of the play
};

/// \brief The ROS 2 type name of a bag's type ("sensor_msgs/LaserScan" or
/// "sensor_msgs/msg/LaserScan" -> "sensor_msgs/msg/LaserScan").
[[nodiscard]] std::string ros2_type_name(const std::string& type);

/// \brief An OccupancyGrid of a map_server map, stamped `stamp_ns` in `frame` (the inverse of
/// ros::to_ros_map()).
[[nodiscard]] ros::OccupancyGridMsg occupancy_grid(const RosMap& map, std::int64_t stamp_ns = 0,
                                                   const std::string& frame = "map");

/// \brief Plays `bag` onto `participant` (see the file comment).
/// \throws ConfigError for a topic asked for that the bag lacks, Error when DDS refuses.
PlayReport play_bag(const ros::BagReader& bag, Participant& participant,
                    const PlayOptions& options);

}  // namespace vdtnav::ros2
