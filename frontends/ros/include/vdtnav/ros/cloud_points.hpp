#pragma once
/// \file
/// \brief A sensor_msgs/PointCloud2 as points in its frame with each point's time: x, y, z found
/// by name (FLOAT32 or FLOAT64), any point_step and row_step, organized (height > 1) or not;
/// points with a non-finite coordinate dropped and counted; big-endian data refused. A per-point
/// time is kept (for deskewing) when the cloud has one of the fields drivers write:
/// `time` / `t` / `offset_time` (relative) or `timestamp` / `time_sec` + `time_nsec` (absolute),
/// read as core/point_time_fields.hpp says and returned in seconds relative to the header stamp.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

/// \brief The decoded cloud.
struct CloudPoints {
  std::vector<Eigen::Vector3d> points;  ///< in the cloud's frame
  std::vector<double> times;            ///< per point, s after the header stamp; empty: none
  std::string time_field;               ///< the field the times came from ("" none)
  std::size_t dropped_not_finite = 0;
};

/// \brief Decodes the cloud (see the file comment). \throws FormatError (file = `source`) when
/// x, y or z is missing or not FLOAT32/FLOAT64, the data is big-endian, or the declared layout
/// (width, height, point_step, row_step, field offsets) does not fit the data.
[[nodiscard]] CloudPoints cloud_points(const PointCloud2Msg& m, const std::string& source);

}  // namespace vdtnav::ros
