#include "vdtnav/octomap/octree_conversion.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

#include "voxelize_octree.hpp"

namespace vdtnav {
namespace detail {
namespace {

/// floor(a / b) for b > 0 (C++ division truncates towards zero).
int floor_div(int a, int b) {
  const int q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// An occupied leaf: the cube [lo, lo + size) in tree voxels, counted from the tree's centre key
/// (so tree voxel k covers [k, k + 1) * resolution in OctoMap's world frame).
struct Leaf {
  Eigen::Vector3i lo;
  int size;
};

/// The occupied leaves and the grid they are voxelized into (OctreeOccupancy's rules).
struct Lattice {
  std::vector<Leaf> leaves;
  int ratio = 1;                ///< tree voxels per grid voxel and axis
  Eigen::Vector3i first, size;  ///< grid voxel (0,0,0) on the grid lattice; voxels
  OctreeOccupancy meta;         ///< everything but the occupancy grid
  GridFrame<3> frame;
};

Lattice octree_lattice(const octomap::OcTree& tree, const OctreeOccupancyOptions& options,
                       const OctreeSource& source);

/// Calls f(grid voxel) for every grid voxel overlapping an occupied leaf (repeats possible).
template <typename F>
void for_each_occupied(const Lattice& l, F&& f) {
  for (const Leaf& leaf : l.leaves) {
    Eigen::Vector3i a, b;
    for (int d = 0; d < 3; ++d) {
      a[d] = floor_div(leaf.lo[d], l.ratio) - l.first[d];
      b[d] = floor_div(leaf.lo[d] + leaf.size - 1, l.ratio) - l.first[d];
    }
    for (int z = a.z(); z <= b.z(); ++z)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int x = a.x(); x <= b.x(); ++x) f(Eigen::Vector3i(x, y, z));
  }
}

}  // namespace

void check_octree_options(const OctreeOccupancyOptions& options, const OctreeSource& source) {
  if (!(std::isfinite(options.resolution) && options.resolution >= 0.0)) {
    std::ostringstream s;
    s << source.name
      << ": resolution must be 0 (the tree's) or a finite multiple of the tree's, got "
      << options.resolution;
    throw ConfigError(s.str());
  }
  if (!(std::isfinite(options.margin) && options.margin >= 0.0)) {
    std::ostringstream s;
    s << source.name << ": margin must be finite and >= 0, got " << options.margin;
    throw ConfigError(s.str());
  }
}

namespace {

Lattice octree_lattice(const octomap::OcTree& tree, const OctreeOccupancyOptions& options,
                       const OctreeSource& source) {
  check_octree_options(options, source);
  const double tree_res = tree.getResolution();
  // Grid voxels are `ratio` tree voxels per axis.
  int ratio = 1;
  if (options.resolution > 0.0) {
    const double r = options.resolution / tree_res;
    ratio = static_cast<int>(std::lround(r));
    if (!(r < 65536.0 && ratio >= 1 && std::abs(r - ratio) <= 1e-6 * r)) {
      std::ostringstream s;
      s << source.name << ": resolution " << options.resolution
        << " m is not a whole multiple (>= 1) of the tree's resolution " << tree_res << " m";
      throw ConfigError(s.str());
    }
  }

  // Keys of depth-16 voxels run over [0, 2^16); key 2^15 is the voxel [0, res) of the world.
  const unsigned depth = tree.getTreeDepth();
  const int centre_key = 1 << (depth - 1);
  std::vector<Leaf> leaves;
  Eigen::Vector3i kmin = Eigen::Vector3i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector3i kmax = Eigen::Vector3i::Constant(std::numeric_limits<int>::min());
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    // getIndexKey(): the key of the leaf's lowest voxel; a leaf at depth d spans 2^(16-d) voxels.
    const octomap::OcTreeKey key = it.getIndexKey();
    Leaf leaf{Eigen::Vector3i(static_cast<int>(key[0]) - centre_key,
                              static_cast<int>(key[1]) - centre_key,
                              static_cast<int>(key[2]) - centre_key),
              1 << (depth - it.getDepth())};
    kmin = kmin.cwiseMin(leaf.lo);
    kmax = kmax.cwiseMax(leaf.lo + Eigen::Vector3i::Constant(leaf.size - 1));
    leaves.push_back(leaf);
  }
  if (leaves.empty()) {
    const std::string what = "the octree has no occupied leaf";
    if (source.is_file) throw FormatError(source.name, 0, what);
    throw ConfigError(source.name + ": " + what);
  }

  Lattice l;
  l.ratio = ratio;
  OctreeOccupancy& out = l.meta;
  out.tree_resolution = tree_res;
  out.num_occupied_leaves = leaves.size();
  out.min_point = kmin.cast<double>() * tree_res;
  out.max_point = (kmax + Eigen::Vector3i::Ones()).cast<double>() * tree_res;

  // The grid on the lattice of grid voxels (index c covers tree voxels [c ratio, (c+1) ratio)),
  // the margin rounded up to whole grid voxels (1e-9 absorbs margin = k * resolution exactly).
  const double res = ratio * tree_res;
  const double margin_voxels = std::ceil(options.margin / res - 1e-9);
  Eigen::Vector3i first;  // grid voxel (0,0,0) on that lattice
  Eigen::Vector3i size;
  double cells = 1.0;
  for (int d = 0; d < 3; ++d) {
    const int lo = floor_div(kmin[d], ratio), hi = floor_div(kmax[d], ratio);
    const double n = hi - lo + 1 + 2.0 * margin_voxels;
    cells *= n;
    if (!(cells < 2147483648.0)) {
      std::ostringstream s;
      s << source.name << ": the occupied leaves' extent ("
        << (out.max_point - out.min_point).transpose() << " m) plus the margin at resolution "
        << res << " m gives 2^31 voxels or more; use a coarser resolution";
      throw ConfigError(s.str());
    }
    first[d] = lo - static_cast<int>(margin_voxels);
    size[d] = static_cast<int>(n);
  }
  l.first = first;
  l.size = size;
  l.frame = GridFrame<3>(res, first.cast<double>() * res);
  l.leaves = std::move(leaves);
  return l;
}

}  // namespace

OctreeOccupancy voxelize_octree(const octomap::OcTree& tree, const OctreeOccupancyOptions& options,
                                const OctreeSource& source) {
  Lattice l = octree_lattice(tree, options, source);
  OctreeOccupancy out = std::move(l.meta);
  out.occupancy = OccupancyGrid<3>(l.size, l.frame, 0);
  OccupancyGrid<3>& grid = out.occupancy;
  for_each_occupied(l, [&](const Eigen::Vector3i& v) {
    std::uint8_t& cell = grid(v);
    out.num_occupied += (cell == 0);
    cell = 1;
  });
  return out;
}

SparseVdtMap3 sparse_map_of_octree(const octomap::OcTree& tree,
                                   const OctreeOccupancyOptions& options,
                                   const SparseVdtMapOptions& map_options,
                                   const OctreeSource& source) {
  const Lattice l = octree_lattice(tree, options, source);
  std::vector<Eigen::Vector3i> occupied;  // repeats only where coarse voxels merge leaves
  for_each_occupied(l, [&](const Eigen::Vector3i& v) { occupied.push_back(v); });
  if ((l.size.array() < 4).any()) {
    std::ostringstream s;
    s << source.name << ": the occupied leaves span " << l.size.transpose()
      << " voxels; a sparse map needs >= 4 per axis (add a margin)";
    throw ConfigError(s.str());
  }
  return SparseVdtMap3::build(occupied, l.frame, l.size, map_options);
}

}  // namespace detail

OctreeOccupancy occupancy_from_octree(const octomap::OcTree& tree,
                                      const OctreeOccupancyOptions& options) {
  return detail::voxelize_octree(tree, options, {"occupancy_from_octree", false});
}

VdtMap3 vdt_map_from_octree(const octomap::OcTree& tree, const OctreeOccupancyOptions& options) {
  return VdtMap3::build(occupancy_from_octree(tree, options).occupancy);
}

SparseVdtMap3 sparse_vdt_map_from_octree(const octomap::OcTree& tree,
                                         const OctreeOccupancyOptions& options,
                                         const SparseVdtMapOptions& map_options) {
  return detail::sparse_map_of_octree(tree, options, map_options,
                                      {"sparse_vdt_map_from_octree", false});
}

}  // namespace vdtnav
