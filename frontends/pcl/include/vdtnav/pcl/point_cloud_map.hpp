#pragma once
/// \file
/// \brief Occupancy grids and VDT maps from point cloud files (PCD, PLY). PCL-free interface:
/// PCL is used inside the library only (see point_cloud_conversion.hpp for pcl::PointCloud).

#include <cstddef>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// \brief How a point cloud becomes voxels.
struct PointCloudOccupancyOptions {
  double resolution = 0.05;  ///< voxel edge, metres (finite, > 0)
  double margin = 0.0;       ///< free border around the cloud's bounding box, metres (finite, >= 0)
  /// Thin the walls to their surfaces: a map drawn from scans holds a wall as a slab a few voxels
  /// thick (range noise, the map builder's pose error), inside which the VDT is zero and a scan
  /// slides freely. Where the points around a voxel lie on a plane thinner than a voxel, only the
  /// voxels that plane crosses stay occupied (src/thin_surfaces.hpp); edges, corners and clutter
  /// stay as voxelized. Off: every voxel with a point is occupied.
  bool thin_surfaces = true;
};

/// \brief A voxelized point cloud and what happened to its points.
///
/// The grid is axis-aligned. It covers the bounding box of the finite points expanded by `margin`
/// on every side; its origin (the lower-left-bottom corner of voxel (0,0,0); voxel centres at
/// origin + (i + 1/2) resolution) is snapped down to a multiple of the resolution, so clouds
/// voxelized at one resolution share voxel boundaries (the rule of occupancy_from_points()). A
/// voxel is occupied (1) when it contains at least one point, free (0) otherwise.
struct PointCloudOccupancy {
  OccupancyGrid<3> occupancy;    ///< the voxels
  std::size_t num_points = 0;    ///< points in the cloud, dropped ones included
  std::size_t num_dropped = 0;   ///< points with a NaN or infinite coordinate (not voxelized)
  std::size_t num_occupied = 0;  ///< occupied voxels
  /// Bounding box of the finite points, world frame, metres.
  Eigen::Vector3d min_point = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d max_point = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// \brief Reads a point cloud file and voxelizes it.
///
/// The formats are read_point_cloud()'s (point_cloud_file.hpp): PCD, PLY, legacy ASCII VTK and
/// text x y z files, by the extension. The cloud needs float32 or float64 fields x, y, z; other
/// fields are ignored. Points with a NaN or infinite coordinate are dropped
/// and counted in `num_dropped`.
/// \throws ConfigError (message starts with the file name) when an option is out of its domain or
///         the grid would have 2^31 voxels or more.
/// \throws IoError when the file cannot be opened or read.
/// \throws FormatError when the extension is unknown, PCL cannot parse the file, it has no x, y, z
///         fields, or it has no point with finite coordinates.
[[nodiscard]] PointCloudOccupancy load_point_cloud_occupancy(
    const std::string& path, const PointCloudOccupancyOptions& options);

/// \brief load_point_cloud_occupancy() followed by VdtMap3::build().
/// \throws what load_point_cloud_occupancy() throws, and ConfigError when an axis of the grid has
///         fewer than 2 voxels (a planar cloud with margin 0).
[[nodiscard]] VdtMap3 load_point_cloud_map(const std::string& path,
                                           const PointCloudOccupancyOptions& options);

/// \brief A sparse VDT map of a point cloud file (sparse_vdt_map.hpp): the occupied voxels of
/// the same lattice as load_point_cloud_occupancy(), collected as a list, never as a dense grid,
/// so the box may exceed 2^31 voxels (up to 10^12).
/// \throws what load_point_cloud_occupancy() throws (but the 2^31 limit), and ConfigError for bad
///         map options or an axis of fewer than 4 voxels.
[[nodiscard]] SparseVdtMap3 load_point_cloud_sparse_map(
    const std::string& path, const PointCloudOccupancyOptions& options,
    const SparseVdtMapOptions& map_options = {});

}  // namespace vdtnav
