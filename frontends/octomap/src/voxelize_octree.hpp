#pragma once
// Internal: the voxelization shared by the file and the in-memory paths.

#include <string>

#include <octomap/OcTree.h>

#include "vdtnav/octomap/octree_map.hpp"

namespace vdtnav::detail {

/// Where the tree comes from, for the messages: a file (content errors are FormatError with the
/// file name) or memory (ConfigError prefixed with the function name).
struct OctreeSource {
  std::string name;
  bool is_file = false;
};

/// Checks the options against nothing but their own domain (the tree is not known yet).
void check_octree_options(const OctreeOccupancyOptions& options, const OctreeSource& source);

/// The sparse map of the occupied leaves, walked leaf by leaf (no dense grid).
SparseVdtMap3 sparse_map_of_octree(const octomap::OcTree& tree,
                                   const OctreeOccupancyOptions& options,
                                   const SparseVdtMapOptions& map_options,
                                   const OctreeSource& source);

OctreeOccupancy voxelize_octree(const octomap::OcTree& tree, const OctreeOccupancyOptions& options,
                                const OctreeSource& source);

}  // namespace vdtnav::detail
