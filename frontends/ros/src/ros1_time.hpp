#pragma once
// Internal to the ROS 1 bag reader (ros1_bag.cpp) and decoders (ros1_serialization.cpp): ROS 1
// time (uint32 sec, uint32 nsec) as nanoseconds.

#include <cstdint>

namespace vdtnav::ros::ros1::detail {

inline std::int64_t to_ns(std::uint32_t sec, std::uint32_t nsec) {
  return static_cast<std::int64_t>(sec) * 1000000000LL + static_cast<std::int64_t>(nsec);
}

}  // namespace vdtnav::ros::ros1::detail
