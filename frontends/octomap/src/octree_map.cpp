#include "vdtnav/octomap/octree_map.hpp"

#include <octomap/AbstractOcTree.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>

#include "vdtnav/core/file_extension.hpp"
#include "voxelize_octree.hpp"

namespace vdtnav {
namespace {

std::unique_ptr<octomap::OcTree> read_binary_tree(std::istream& in, const std::string& path) {
  auto tree = std::make_unique<octomap::OcTree>(0.1);  // readBinary takes the file's resolution
  if (!tree->readBinary(in)) {
    // OctoMap reports a short file as a node count mismatch after reading past its end.
    if (in.eof()) throw FormatError(path, 0, "the octree data ends early (truncated file)");
    throw FormatError(path, 0,
                      "not a binary OctoMap file (expected the header '# Octomap OcTree binary "
                      "file' with id, size and res lines)");
  }
  return tree;
}

std::unique_ptr<octomap::OcTree> read_full_tree(std::istream& in, const std::string& path) {
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read(in));
  if (!tree) {
    throw FormatError(path, 0,
                      "not an OctoMap .ot file of a known tree type (expected the header "
                      "'# Octomap OcTree file' with id, size and res lines)");
  }
  if (dynamic_cast<octomap::OcTree*>(tree.get()) == nullptr) {
    throw FormatError(path, 0,
                      "holds an octree of type '" + tree->getTreeType() +
                          "'; expected an OcTree (occupancy octree)");
  }
  return std::unique_ptr<octomap::OcTree>(static_cast<octomap::OcTree*>(tree.release()));
}

std::unique_ptr<octomap::OcTree> read_tree(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".bt" && ext != ".ot") {
    throw FormatError(path, 0,
                      "unknown octree format '" + ext + "'; expected a .bt or .ot OctoMap file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open octree: " + std::strerror(errno));
  in.peek();
  if (in.bad()) throw IoError(path + ": cannot read octree: " + std::strerror(errno));
  std::unique_ptr<octomap::OcTree> tree;
  try {
    tree = ext == ".bt" ? read_binary_tree(in, path) : read_full_tree(in, path);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // e.g. std::bad_alloc from a corrupt size
    throw FormatError(path, 0, std::string("cannot parse the octree: ") + e.what());
  }
  // OctoMap reads node by node without checking the stream: a short file fails here.
  if (in.bad()) throw IoError(path + ": read error");
  if (in.fail()) throw FormatError(path, 0, "the octree data ends early (truncated file)");
  return tree;
}

}  // namespace

OctreeOccupancy load_octree_occupancy(const std::string& path,
                                      const OctreeOccupancyOptions& options) {
  const detail::OctreeSource source{path, true};
  detail::check_octree_options(options, source);  // before touching the file
  const std::unique_ptr<octomap::OcTree> tree = read_tree(path);
  return detail::voxelize_octree(*tree, options, source);
}

VdtMap3 load_octree_map(const std::string& path, const OctreeOccupancyOptions& options) {
  return VdtMap3::build(load_octree_occupancy(path, options).occupancy);
}

SparseVdtMap3 load_octree_sparse_map(const std::string& path, const OctreeOccupancyOptions& options,
                                     const SparseVdtMapOptions& map_options) {
  const detail::OctreeSource source{path, true};
  detail::check_octree_options(options, source);
  const std::unique_ptr<octomap::OcTree> tree = read_tree(path);
  return detail::sparse_map_of_octree(*tree, options, map_options, source);
}

}  // namespace vdtnav
