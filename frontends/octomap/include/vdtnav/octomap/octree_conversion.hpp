#pragma once
/// \file
/// \brief Occupancy grids and VDT maps from an in-memory octomap::OcTree.

#include <octomap/OcTree.h>

#include "vdtnav/octomap/octree_map.hpp"

namespace vdtnav {

/// \brief Voxelizes the occupied leaves of a tree, by the rules of OctreeOccupancy.
/// \throws ConfigError when an option is out of its domain, the tree has no occupied leaf, or the
///         grid would have 2^31 voxels or more.
[[nodiscard]] OctreeOccupancy occupancy_from_octree(const octomap::OcTree& tree,
                                                    const OctreeOccupancyOptions& options);

/// \brief occupancy_from_octree() followed by VdtMap3::build().
/// \throws ConfigError as occupancy_from_octree(), and when an axis of the grid has fewer than 2
///         voxels.
[[nodiscard]] VdtMap3 vdt_map_from_octree(const octomap::OcTree& tree,
                                          const OctreeOccupancyOptions& options);

/// \brief The SparseVdtMap3 of a tree's occupied leaves on the grid of occupancy_from_octree(),
/// built from the leaves directly (no dense grid at full resolution).
/// \throws ConfigError as occupancy_from_octree(), for bad map options, and when an axis of the
///         grid has fewer than 4 voxels.
[[nodiscard]] SparseVdtMap3 sparse_vdt_map_from_octree(const octomap::OcTree& tree,
                                                       const OctreeOccupancyOptions& options,
                                                       const SparseVdtMapOptions& map_options = {});

}  // namespace vdtnav
