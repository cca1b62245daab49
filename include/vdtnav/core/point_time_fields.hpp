#pragma once
/// \file
/// \brief The per-point time fields LiDAR drivers write into their clouds (ROS PointCloud2, PCD,
/// PLY, text columns), and how each reads as seconds: what deskewing (sensor/sweep_motion.hpp)
/// needs, read the same way by the ROS and the point cloud front ends.
///
/// Looked for in this order: `time` (Velodyne, Hesai relative), `t` (Ouster), `offset_time`
/// (Livox) — relative to the cloud's stamp — and `timestamp` (Livox, Hesai, Robosense) — absolute.
/// A value of an integer type is nanoseconds; of a floating type, seconds, except an absolute one
/// past 1e14, which can only be nanoseconds (Livox writes them as FLOAT64).

#include <array>
#include <string>

namespace vdtnav {

/// \brief A time field's name and whether its values are absolute (else after the stamp).
struct PointTimeField {
  const char* name;
  bool absolute;
};

/// \brief The fields looked for, in order (the file comment).
inline constexpr std::array<PointTimeField, 4> kPointTimeFields = {
    {{"time", false}, {"t", false}, {"offset_time", false}, {"timestamp", true}}};

/// \return a field value in seconds: integer types are nanoseconds, floating ones seconds unless
/// absolute and past 1e14 (nanoseconds).
[[nodiscard]] inline double point_time_seconds(double value, bool is_integer, bool absolute) {
  if (is_integer || (absolute && value > 1e14)) return value * 1e-9;
  return value;
}

}  // namespace vdtnav
