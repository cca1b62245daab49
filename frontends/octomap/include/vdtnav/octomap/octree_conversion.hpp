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

}  // namespace vdtnav
