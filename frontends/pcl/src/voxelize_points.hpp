#pragma once
// Internal: the voxelization shared by the file and the in-memory paths. Two passes over the
// points through an accessor (bounding box, then fill), so no cloud is copied into Eigen vectors.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "vdtnav/core/error.hpp"
#include "vdtnav/pcl/point_cloud_map.hpp"

namespace vdtnav::detail {

/// Where the points come from, for the messages: a file (content errors are FormatError with the
/// file name) or memory (ConfigError prefixed with the function name).
struct PointSource {
  std::string name;
  bool is_file = false;

  [[noreturn]] void content_error(const std::string& what) const {
    if (is_file) throw FormatError(name, 0, what);
    throw ConfigError(name + ": " + what);
  }
  [[noreturn]] void config_error(const std::string& what) const {
    throw ConfigError(name + ": " + what);
  }
};

inline void check_options(const PointCloudOccupancyOptions& options, const PointSource& source) {
  if (!(std::isfinite(options.resolution) && options.resolution > 0.0)) {
    std::ostringstream s;
    s << "resolution must be finite and > 0, got " << options.resolution;
    source.config_error(s.str());
  }
  if (!(std::isfinite(options.margin) && options.margin >= 0.0)) {
    std::ostringstream s;
    s << "margin must be finite and >= 0, got " << options.margin;
    source.config_error(s.str());
  }
}

/// \param n        number of points.
/// \param point_at point_at(i) -> Eigen::Vector3d, i < n (may be non-finite).
template <typename PointAt>
PointCloudOccupancy voxelize_points(std::size_t n, const PointAt& point_at,
                                    const PointCloudOccupancyOptions& options,
                                    const PointSource& source) {
  check_options(options, source);
  PointCloudOccupancy out;
  out.num_points = n;
  if (n == 0) source.content_error("the cloud has no points");

  // Pass 1: bounding box of the finite points.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (!p.allFinite()) {
      ++out.num_dropped;
      continue;
    }
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (out.num_dropped == n) {
    source.content_error("none of its " + std::to_string(n) +
                         " points has finite coordinates (all are NaN or infinite)");
  }
  out.min_point = lo;
  out.max_point = hi;

  // The grid: origin snapped down to a multiple of the resolution (occupancy_from_points' rule).
  const double res = options.resolution;
  Eigen::Vector3d origin;
  Eigen::Vector3i size;
  double cells = 1.0;
  for (int d = 0; d < 3; ++d) {
    origin[d] = std::floor((lo[d] - options.margin) / res) * res;
    const double cells_d = std::floor((hi[d] + options.margin - origin[d]) / res) + 1.0;
    cells *= cells_d;
    if (!(cells_d >= 1.0 && cells < 2147483648.0)) {
      std::ostringstream s;
      s << "the cloud's extent (" << (hi - lo).transpose() << " m) plus the margin at resolution "
        << res << " m gives 2^31 voxels or more; use a coarser resolution";
      source.config_error(s.str());
    }
    size[d] = static_cast<int>(cells_d);
  }
  out.occupancy = OccupancyGrid<3>(size, GridFrame<3>(res, origin), 0);

  // Pass 2: occupy every voxel that contains a finite point.
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (!p.allFinite()) continue;
    // Every point lies inside the grid; the clamp only absorbs rounding at the outer faces.
    const Eigen::Vector3i i = out.occupancy.cell_of(p)
                                  .cwiseMax(Eigen::Vector3i::Zero())
                                  .cwiseMin(size - Eigen::Vector3i::Ones());
    std::uint8_t& v = out.occupancy(i);
    out.num_occupied += (v == 0);
    v = 1;
  }
  return out;
}

}  // namespace vdtnav::detail
