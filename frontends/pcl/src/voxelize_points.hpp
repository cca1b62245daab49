#pragma once
// Internal: the voxelization shared by the file and the in-memory paths. Two passes over the
// points through an accessor (bounding box, then fill), so no cloud is copied into Eigen vectors.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "thin_surfaces.hpp"
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

/// The lattice a cloud is voxelized on (pass 1 over the points): the bounding box of the finite
/// points grown by the margin, origin snapped down to a multiple of the resolution
/// (occupancy_from_points' rule).
struct CloudLattice {
  GridFrame<3> frame;
  Eigen::Vector3i size = Eigen::Vector3i::Zero();
  double cells = 0.0;  ///< voxels of the box
  std::size_t num_dropped = 0;
  Eigen::Vector3d lo, hi;  ///< bounding box of the finite points
};

/// \param n        number of points.
/// \param point_at point_at(i) -> Eigen::Vector3d, i < n (may be non-finite).
/// \param max_cells the largest box accepted (the dense grid's 2^31; a sparse map's more).
template <typename PointAt>
CloudLattice cloud_lattice(std::size_t n, const PointAt& point_at,
                           const PointCloudOccupancyOptions& options, const PointSource& source,
                           double max_cells) {
  check_options(options, source);
  if (n == 0) source.content_error("the cloud has no points");
  CloudLattice l;
  l.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  l.hi = -l.lo;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (!p.allFinite()) {
      ++l.num_dropped;
      continue;
    }
    l.lo = l.lo.cwiseMin(p);
    l.hi = l.hi.cwiseMax(p);
  }
  if (l.num_dropped == n) {
    source.content_error("none of its " + std::to_string(n) +
                         " points has finite coordinates (all are NaN or infinite)");
  }
  const double res = options.resolution;
  Eigen::Vector3d origin;
  l.cells = 1.0;
  for (int d = 0; d < 3; ++d) {
    origin[d] = std::floor((l.lo[d] - options.margin) / res) * res;
    const double cells_d = std::floor((l.hi[d] + options.margin - origin[d]) / res) + 1.0;
    l.cells *= cells_d;
    if (!(cells_d >= 1.0 && cells_d < 2147483648.0 && l.cells < max_cells)) {
      std::ostringstream s;
      s << "the cloud's extent (" << (l.hi - l.lo).transpose()
        << " m) plus the margin at resolution " << res << " m gives " << l.cells
        << " voxels or more (at most " << max_cells << "); use a coarser resolution"
        << (max_cells <= 2147483648.0 ? ", --crop, or a sparse map" : " or --crop");
      source.config_error(s.str());
    }
    l.size[d] = static_cast<int>(cells_d);
  }
  l.frame = GridFrame<3>(res, origin);
  return l;
}

/// The voxel of a point of the cloud (the clamp only absorbs rounding at the outer faces).
inline Eigen::Vector3i voxel_of(const CloudLattice& l, const Eigen::Vector3d& p) {
  return l.frame.cell_of(p)
      .cwiseMax(Eigen::Vector3i::Zero())
      .cwiseMin(l.size - Eigen::Vector3i::Ones());
}

/// \param n        number of points.
/// \param point_at point_at(i) -> Eigen::Vector3d, i < n (may be non-finite).
template <typename PointAt>
PointCloudOccupancy voxelize_points(std::size_t n, const PointAt& point_at,
                                    const PointCloudOccupancyOptions& options,
                                    const PointSource& source) {
  const CloudLattice l = cloud_lattice(n, point_at, options, source, 2147483648.0);
  PointCloudOccupancy out;
  out.num_points = n;
  out.num_dropped = l.num_dropped;
  out.min_point = l.lo;
  out.max_point = l.hi;
  out.occupancy = OccupancyGrid<3>(l.size, l.frame, 0);
  // Pass 2: occupy every voxel that contains a finite point.
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (!p.allFinite()) continue;
    std::uint8_t& v = out.occupancy(voxel_of(l, p));
    out.num_occupied += (v == 0);
    v = 1;
  }
  if (options.thin_surfaces) {
    std::vector<Eigen::Vector3i> occupied;
    occupied.reserve(out.num_occupied);
    for (int z = 0; z < l.size.z(); ++z)
      for (int y = 0; y < l.size.y(); ++y)
        for (int x = 0; x < l.size.x(); ++x)
          if (out.occupancy(Eigen::Vector3i(x, y, z))) occupied.emplace_back(x, y, z);
    const std::vector<bool> keep = surface_voxels(
        occupied, l.frame, n, point_at, [&](const Eigen::Vector3d& p) { return voxel_of(l, p); });
    for (std::size_t i = 0; i < occupied.size(); ++i) {
      if (keep[i]) continue;
      out.occupancy(occupied[i]) = 0;
      --out.num_occupied;
    }
  }
  return out;
}

/// The occupied voxels of a cloud as a list (no dense grid): for sparse maps.
template <typename PointAt>
std::vector<Eigen::Vector3i> occupied_voxels(std::size_t n, const PointAt& point_at,
                                             const CloudLattice& l, bool thin_surfaces) {
  std::vector<Eigen::Vector3i> v;
  v.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (p.allFinite()) v.push_back(voxel_of(l, p));
  }
  const auto less = [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::tie(a.z(), a.y(), a.x()) < std::tie(b.z(), b.y(), b.x());
  };
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
  if (!thin_surfaces) return v;
  const std::vector<bool> keep = surface_voxels(
      v, l.frame, n, point_at, [&](const Eigen::Vector3d& p) { return voxel_of(l, p); });
  std::vector<Eigen::Vector3i> kept;
  kept.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    if (keep[i]) kept.push_back(v[i]);
  return kept;
}

}  // namespace vdtnav::detail
