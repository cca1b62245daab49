#pragma once
/// \file
/// \brief Occupancy grids and VDT maps from OctoMap files (.bt, .ot). OctoMap-free interface:
/// OctoMap is used inside the library only (see octree_conversion.hpp for octomap::OcTree).

#include <cstddef>
#include <limits>
#include <string>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// \brief How an octree becomes voxels.
struct OctreeOccupancyOptions {
  /// Voxel edge in metres: 0 for the tree's own resolution, otherwise a whole multiple m >= 1 of
  /// it (within 1e-6 relative), so that every grid voxel is exactly m x m x m tree voxels.
  double resolution = 0.0;
  double margin = 0.0;  ///< free border around the occupied leaves, metres (finite, >= 0)
};

/// \brief A voxelized occupancy octree.
///
/// Occupied leaves are those OcTree::isNodeOccupied() accepts (the tree's occupancy threshold,
/// 0.5 unless the tree says otherwise). A leaf at depth d < 16 (pruned) is a cube of 2^(16-d)
/// tree voxels per axis, all of which are occupied. At the tree's resolution the grid is exactly
/// the occupied tree voxels; at a coarser one a grid voxel is occupied when any of its tree voxels
/// is.
///
/// Bounding box: only occupied leaves count; free and unknown space never extends it, whatever the
/// tree's own metric bounds. The grid covers that box plus `margin` rounded up to whole grid
/// voxels on every side, and it lies on the tree's own voxel lattice: the origin (the
/// lower-left-bottom corner of voxel (0,0,0); centres at origin + (i + 1/2) resolution) is a
/// multiple of the grid resolution in OctoMap's world frame, so grid voxels coincide with tree
/// voxels (or blocks of them). Everything outside occupied leaves, free or unknown, is free (0).
struct OctreeOccupancy {
  OccupancyGrid<3> occupancy;           ///< the voxels
  double tree_resolution = 0.0;         ///< the octree's leaf size at depth 16, metres
  std::size_t num_occupied_leaves = 0;  ///< occupied leaves, at any depth
  std::size_t num_occupied = 0;         ///< occupied grid voxels
  /// Bounding box of the occupied leaves (their outer faces), world frame, metres.
  Eigen::Vector3d min_point = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d max_point = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// \brief Reads an OctoMap file and voxelizes its occupied leaves.
///
/// The format follows the extension (case-insensitive): `.bt` (binary OcTree,
/// OcTree::writeBinary) or `.ot` (full AbstractOcTree::write file; the tree must be an OcTree —
/// a ColorOcTree, OcTreeStamped or other type is refused).
/// \throws ConfigError (message starts with the file name) when an option is out of its domain or
///         the grid would have 2^31 voxels or more.
/// \throws IoError when the file cannot be opened or read.
/// \throws FormatError when the extension is unknown, OctoMap cannot parse the file or it ends
///         early, an .ot file holds another tree type, or the tree has no occupied leaf.
[[nodiscard]] OctreeOccupancy load_octree_occupancy(const std::string& path,
                                                    const OctreeOccupancyOptions& options);

/// \brief load_octree_occupancy() followed by VdtMap3::build().
/// \throws what load_octree_occupancy() throws, and ConfigError when an axis of the grid has fewer
///         than 2 voxels (a single flat layer with margin 0).
[[nodiscard]] VdtMap3 load_octree_map(const std::string& path,
                                      const OctreeOccupancyOptions& options);

/// \brief Reads an OctoMap file and builds the SparseVdtMap3 of its occupied leaves, walking the
/// leaves directly (no dense grid at full resolution); same grid as load_octree_occupancy().
/// \throws what load_octree_occupancy() throws, and ConfigError for bad map options or an axis
///         of fewer than 4 voxels.
[[nodiscard]] SparseVdtMap3 load_octree_sparse_map(const std::string& path,
                                                   const OctreeOccupancyOptions& options,
                                                   const SparseVdtMapOptions& map_options = {});

}  // namespace vdtnav
