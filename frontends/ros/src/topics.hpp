#pragma once
// What the sequence readers (scan_sequence.cpp, cloud_sequence.cpp) share: picking a topic by
// name or type, naming the bag's topics in errors, the TF topics and the bag's time span.

#include <algorithm>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"

namespace vdtnav::ros::detail {

/// The topics of a given type (ROS 1 spelling compared), as "name (type)" for messages too.
inline std::vector<const BagTopic*> topics_of(const BagReader& bag, const std::string& type) {
  std::vector<const BagTopic*> out;
  for (const BagTopic& t : bag.topics()) {
    if (ros1_type_name(t.type) == type) out.push_back(&t);
  }
  return out;
}

inline std::string list_topics(const BagReader& bag) {
  std::string s;
  for (const BagTopic& t : bag.topics()) {
    if (!s.empty()) s += ", ";
    s += t.name + " (" + t.type + ", " + std::to_string(t.count) + ")";
  }
  return s.empty() ? "none" : s;
}

/// The topic named, checked to be of `type`; or the only one of that type; or of several, the
/// one named `preferred` (with or without the leading slash; "" = none preferred).
inline const BagTopic* pick_topic(const BagReader& bag, const std::string& name,
                                  const std::string& type, const std::string& flag, bool required,
                                  const std::string& preferred = "") {
  if (!name.empty()) {
    for (const BagTopic& t : bag.topics()) {
      if (t.name != name) continue;
      if (ros1_type_name(t.type) != type) {
        throw ConfigError(bag.path() + ": " + flag + " " + name + " is a " + t.type +
                          " topic, not " + type);
      }
      return &t;
    }
    throw ConfigError(bag.path() + ": no topic " + name + " (" + flag +
                      "); the bag has: " + list_topics(bag));
  }
  const auto found = topics_of(bag, type);
  if (found.size() == 1) return found.front();
  for (const BagTopic* t : found) {
    if (!preferred.empty() && (t->name == preferred || t->name == "/" + preferred)) return t;
  }
  if (!required && found.empty()) return nullptr;
  throw ConfigError(bag.path() + ": " +
                    (found.empty() ? "no " + type + " topic"
                                   : std::to_string(found.size()) + " " + type +
                                         " topics: name one with " + flag) +
                    "; the bag has: " + list_topics(bag));
}

/// The bag's /tf and /tf_static topics (tf2_msgs/TFMessage).
inline std::vector<std::string> tf_topics_of(const BagReader& bag) {
  std::vector<std::string> out;
  for (const BagTopic& t : bag.topics()) {
    if (ros1_type_name(t.type) == "tf2_msgs/TFMessage" &&
        (t.name == "/tf" || t.name == "/tf_static")) {
      out.push_back(t.name);
    }
  }
  return out;
}

/// How long a transform buffer must hold the bag's transforms: its longest topic, and a minute.
inline double span_seconds(const BagReader& bag) {
  double span = 60.0;
  for (const BagTopic& t : bag.topics()) {
    span = std::max(span, 1e-9 * static_cast<double>(t.last_ns - t.first_ns) + 60.0);
  }
  return span;
}

}  // namespace vdtnav::ros::detail
