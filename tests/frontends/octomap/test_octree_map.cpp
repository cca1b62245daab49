// OctoMap front end against independent oracles: the voxel set a synthetic tree was built from,
// a traversal of the real CATEC map with OctoMap's own iterators, and brute-force distances.
#include "vdtnav/octomap/octomap.hpp"

#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "vdtnav/map/sparse_vdt_map.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using Voxel = std::array<int, 3>;
using VoxelSet = std::set<Voxel>;

constexpr int kCentreKey = 32768;  // OcTree key of the tree voxel [0, res) (depth 16)

std::string tmp_path(const std::string& name) {
  // One folder per process: ctest runs each test in its own process, in parallel, and every
  // process writes the synthetic tree in SetUpTestSuite.
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / ("octree_map_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string catec_path() { return std::string(VDTNAV_DATA_DIR) + "/3d/dll-catec/catec.bt"; }

int floor_div(int a, int b) { return static_cast<int>(std::floor(static_cast<double>(a) / b)); }

/// Occupied voxels of a grid as indices of the world lattice of its resolution (voxel v covers
/// [v, v + 1) * resolution), which requires the origin to lie on that lattice.
VoxelSet occupied_set(const OccupancyGrid<3>& grid) {
  const Eigen::Vector3d o = grid.frame().origin() / grid.resolution();
  const Eigen::Vector3d snapped = o.array().round();
  EXPECT_LT((o - snapped).cwiseAbs().maxCoeff(), 1e-6) << "origin off the voxel lattice";
  VoxelSet set;
  for (std::size_t l = 0; l < grid.num_cells(); ++l) {
    if (grid[l] == 0) continue;
    const Eigen::Vector3i i = grid.index_of(static_cast<std::ptrdiff_t>(l));
    set.insert({i.x() + static_cast<int>(snapped.x()), i.y() + static_cast<int>(snapped.y()),
                i.z() + static_cast<int>(snapped.z())});
  }
  return set;
}

octomap::OcTreeKey key_of(const Voxel& v) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(v[0] + kCentreKey),
                            static_cast<octomap::key_type>(v[1] + kCentreKey),
                            static_cast<octomap::key_type>(v[2] + kCentreKey));
}

/// A 0.1 m tree whose occupied voxels are exactly `voxels` (in tree-voxel indices), plus a block
/// of free space far away; blocks aligned to 4 and 2 voxels collapse into coarse leaves on
/// prune().
struct SyntheticTree {
  octomap::OcTree tree{0.1};
  VoxelSet voxels;

  SyntheticTree() {
    auto block = [&](const Voxel& lo, int n) {
      for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) voxels.insert({lo[0] + x, lo[1] + y, lo[2] + z});
    };
    block({8, -4, 0}, 4);   // one leaf at depth 14 (64 voxels)
    block({-6, 2, -2}, 2);  // one leaf at depth 15 (8 voxels)
    voxels.insert({-7, 5, 3});
    voxels.insert({20, -9, 1});
    for (int x = 0; x < 3; ++x) voxels.insert({x, 0, 5});  // an unaligned run: depth-16 leaves
    for (const Voxel& v : voxels) tree.updateNode(key_of(v), true);
    // Free space (observed, not occupied) that must not widen the grid.
    for (int z = -32; z < -24; ++z)
      for (int y = -32; y < -24; ++y)
        for (int x = -32; x < -24; ++x) tree.updateNode(key_of({x, y, z}), false);
    tree.updateNode(key_of({60, 60, 60}), false);
    tree.prune();
  }
};

/// Occupied leaves per depth, by OctoMap's own traversal.
std::vector<std::size_t> occupied_leaves_per_depth(const octomap::OcTree& tree) {
  std::vector<std::size_t> n(17, 0);
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    if (tree.isNodeOccupied(*it)) ++n[it.getDepth()];
  return n;
}

class SyntheticOctree : public ::testing::TestWithParam<const char*> {
 protected:
  static void SetUpTestSuite() {
    static SyntheticTree s;
    synthetic_ = &s;
    ASSERT_TRUE(s.tree.writeBinaryConst(tmp_path("synthetic.bt")));
    ASSERT_TRUE(s.tree.write(tmp_path("synthetic.ot")));
  }
  static std::string path() { return tmp_path(std::string("synthetic") + GetParam()); }
  static const SyntheticTree& synthetic() { return *synthetic_; }

 private:
  static inline const SyntheticTree* synthetic_ = nullptr;
};

TEST_P(SyntheticOctree, TheTreeHasCoarseOccupiedLeaves) {
  // Guards the premise of the next tests: pruning made leaves of 4^3 and 2^3 voxels.
  const auto n = occupied_leaves_per_depth(synthetic().tree);
  EXPECT_EQ(n[14], 1u);
  EXPECT_EQ(n[15], 1u);
  EXPECT_EQ(n[16], 5u);
}

TEST_P(SyntheticOctree, GridHoldsExactlyTheOccupiedVoxels) {
  OctreeOccupancyOptions o;
  o.margin = 0.25;  // rounded up to 3 voxels of 0.1 m
  const OctreeOccupancy occ = load_octree_occupancy(path(), o);
  const VoxelSet& expected = synthetic().voxels;
  EXPECT_DOUBLE_EQ(occ.tree_resolution, 0.1);
  EXPECT_DOUBLE_EQ(occ.occupancy.resolution(), 0.1);
  EXPECT_EQ(occ.num_occupied_leaves, 7u);
  EXPECT_EQ(occ.num_occupied, expected.size());
  EXPECT_EQ(occupied_set(occ.occupancy), expected);

  // Box of the occupied voxels only (the free block at -3.2 m and the free voxel at 6 m are
  // outside it), then 3 voxels of margin.
  Voxel lo{99, 99, 99}, hi{-99, -99, -99};
  for (const Voxel& v : expected)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], v[d]);
      hi[d] = std::max(hi[d], v[d]);
    }
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(occ.min_point[d], lo[d] * 0.1, 1e-12) << d;
    EXPECT_NEAR(occ.max_point[d], (hi[d] + 1) * 0.1, 1e-12) << d;
    EXPECT_NEAR(occ.occupancy.frame().origin()[d], (lo[d] - 3) * 0.1, 1e-12) << d;
    EXPECT_EQ(occ.occupancy.size()[d], hi[d] - lo[d] + 1 + 6) << d;
  }
}

TEST_P(SyntheticOctree, CoarserGridOccupiesEveryVoxelOverlappingALeaf) {
  for (const int m : {2, 3, 5}) {
    OctreeOccupancyOptions o;
    o.resolution = 0.1 * m;
    o.margin = 0.25;
    const OctreeOccupancy occ = load_octree_occupancy(path(), o);
    VoxelSet expected;
    for (const Voxel& v : synthetic().voxels)
      expected.insert({floor_div(v[0], m), floor_div(v[1], m), floor_div(v[2], m)});
    EXPECT_NEAR(occ.occupancy.resolution(), 0.1 * m, 1e-12);
    EXPECT_EQ(occupied_set(occ.occupancy), expected) << "m = " << m;
    EXPECT_EQ(occ.num_occupied, expected.size());
    // Margin: ceil(0.25 / (0.1 m)) voxels before the first occupied one along x.
    const int margin_voxels = static_cast<int>(std::ceil(0.25 / (0.1 * m) - 1e-9));
    EXPECT_NEAR(occ.occupancy.frame().origin().x(), (floor_div(-7, m) - margin_voxels) * 0.1 * m,
                1e-12);
  }
}

TEST_P(SyntheticOctree, VdtMapDistanceIsTheBruteForceNearestOccupiedVoxel) {
  OctreeOccupancyOptions o;
  o.margin = 0.3;
  const VdtMap3 map = load_octree_map(path(), o);
  const OctreeOccupancy occ = load_octree_occupancy(path(), o);
  std::mt19937 rng(7);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 40; ++trial) {
    Eigen::Vector3i i;
    for (int d = 0; d < 3; ++d)
      i[d] = std::uniform_int_distribution<int>(0, map.size()[d] - 1)(rng);
    if (occ.occupancy(i) != 0) continue;  // free voxels: there DT_v is the plain definition
    const Eigen::Vector3d p = occ.occupancy.cell_center(i);
    double best = std::numeric_limits<double>::infinity();
    for (const Voxel& v : synthetic().voxels) {
      const Eigen::Vector3d c =
          (Eigen::Vector3d(v[0], v[1], v[2]) + Eigen::Vector3d::Constant(0.5)) * 0.1;
      best = std::min(best, (p - c).norm());
    }
    EXPECT_NEAR(map.nearest_point_query(p).value.norm(), best, 1e-9) << p.transpose();
    // The spline interpolates the samples at voxel centres (float coefficients).
    EXPECT_NEAR(map.evaluate(p).value.norm(), best, 1e-4) << p.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, 40);
}

TEST_P(SyntheticOctree, SparseMapFromTheLeavesMatchesTheDenseMapNearSurfaces) {
  // load_octree_sparse_map walks the occupied leaves (no dense grid): within its band it must
  // answer as the dense map of the same file, on the same lattice; beyond, finitely.
  OctreeOccupancyOptions o;
  o.margin = 0.5;
  const VdtMap3 dense = load_octree_map(path(), o);
  const SparseVdtMap3 sparse = load_octree_sparse_map(path(), o);
  const OctreeOccupancy occ = load_octree_occupancy(path(), o);
  EXPECT_EQ(sparse.size(), dense.size());
  EXPECT_EQ(sparse.frame().origin(), dense.frame().origin());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double band = sparse.band() * sparse.resolution();
  int near = 0, far = 0;
  for (int trial = 0; trial < 20000 && (near < 300 || far < 100); ++trial) {
    Eigen::Vector3d p;
    for (int d = 0; d < 3; ++d) {
      const double lo = dense.frame().origin()[d] + dense.resolution();
      const double hi = dense.frame().origin()[d] + (dense.size()[d] - 1) * dense.resolution();
      p[d] = lo + (hi - lo) * u(rng);
    }
    // Free space only: inside thick obstacles DT_v points to the nearest surface voxel.
    if (occ.occupancy(occ.occupancy.cell_of(p)) != 0) continue;
    const VdtSample<3> a = dense.evaluate(p);
    const VdtSample<3> b = sparse.evaluate(p);
    ASSERT_TRUE(b.value.allFinite() && b.jacobian.allFinite());
    const double distance = dense.nearest_point_query(p).value.norm();
    if (distance < band - 0.5 * dense.resolution()) {
      EXPECT_LT((a.value - b.value).norm(), 2e-5) << p.transpose();
      EXPECT_LT((a.jacobian - b.jacobian).norm(), 5e-4) << p.transpose();
      ++near;
    } else if (distance > band + dense.resolution()) {
      ++far;  // the coarse level's answers are tested in tests/map/test_sparse_vdt_map.cpp
    }
  }
  EXPECT_GE(near, 300);
  EXPECT_GE(far, 100);
}

TEST_P(SyntheticOctree, InMemoryTreeGivesTheSameGrid) {
  OctreeOccupancyOptions o;
  o.margin = 0.1;
  const OctreeOccupancy from_file = load_octree_occupancy(path(), o);
  const OctreeOccupancy in_memory = occupancy_from_octree(synthetic().tree, o);
  EXPECT_EQ(in_memory.occupancy.size(), from_file.occupancy.size());
  EXPECT_EQ(in_memory.occupancy.frame().origin(), from_file.occupancy.frame().origin());
  EXPECT_EQ(in_memory.occupancy.values(), from_file.occupancy.values());
}

TEST_P(SyntheticOctree, OptionsOutOfTheirDomainNameTheFile) {
  for (const double res : {-0.1, 0.05, 0.15, std::numeric_limits<double>::quiet_NaN()}) {
    OctreeOccupancyOptions o;
    o.resolution = res;
    try {
      (void)load_octree_occupancy(path(), o);
      ADD_FAILURE() << "resolution " << res << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path()), std::string::npos) << e.what();
    }
  }
  OctreeOccupancyOptions o;
  o.margin = -1.0;
  EXPECT_THROW((void)load_octree_occupancy(path(), o), ConfigError);
}

INSTANTIATE_TEST_SUITE_P(Formats, SyntheticOctree, ::testing::Values(".bt", ".ot"),
                         [](const auto& info) { return std::string(info.param + 1); });

/// Expects `f` to throw E whose message names `file`.
template <typename E, typename F>
void expect_error_naming(F f, const std::string& file, const char* what) {
  try {
    f();
    ADD_FAILURE() << what << ": no exception";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << what << ": " << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": wrong exception type: " << e.what();
  }
}

TEST(OctreeMapErrors, MissingCorruptAndForeignFilesNameTheFile) {
  const OctreeOccupancyOptions o;
  const std::string missing = tmp_path("does_not_exist.bt");
  expect_error_naming<IoError>([&] { (void)load_octree_occupancy(missing, o); }, missing,
                               "missing");

  const std::string garbage = tmp_path("garbage.bt");
  std::ofstream(garbage) << "this is not an octree\n";
  expect_error_naming<FormatError>([&] { (void)load_octree_occupancy(garbage, o); }, garbage,
                                   "garbage .bt");
  const std::string garbage_ot = tmp_path("garbage.ot");
  std::ofstream(garbage_ot) << "# Octomap OcTree file\nid NoSuchTree\nsize 1\nres 0.1\ndata\n";
  expect_error_naming<FormatError>([&] { (void)load_octree_occupancy(garbage_ot, o); }, garbage_ot,
                                   "unknown tree type");

  // Valid trees cut short, in both formats.
  const SyntheticTree s;
  for (const std::string ext : {".bt", ".ot"}) {
    const std::string full = tmp_path("full" + ext), cut = tmp_path("truncated" + ext);
    ASSERT_TRUE(ext == ".bt" ? s.tree.writeBinaryConst(full) : s.tree.write(full));
    {
      std::ifstream in(full, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() - 40);
    }
    try {
      (void)load_octree_occupancy(cut, o);
      ADD_FAILURE() << cut << " accepted";
    } catch (const FormatError& e) {
      EXPECT_EQ(e.file(), cut);
      EXPECT_NE(std::string(e.what()).find("ends early"), std::string::npos) << e.what();
    }
  }

  const std::string wrong_ext = tmp_path("map.pcd");
  std::ofstream(wrong_ext) << "x";
  expect_error_naming<FormatError>([&] { (void)load_octree_occupancy(wrong_ext, o); }, wrong_ext,
                                   "unknown extension");
}

TEST(OctreeMapErrors, OtFileMustHoldAnOcTree) {
  octomap::ColorOcTree color(0.1);
  color.updateNode(key_of({1, 2, 3}), true);
  const std::string path = tmp_path("color.ot");
  ASSERT_TRUE(color.write(path));
  try {
    (void)load_octree_occupancy(path, {});
    ADD_FAILURE() << "a ColorOcTree was accepted";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find("ColorOcTree"), std::string::npos) << e.what();
  }
}

TEST(OctreeMapErrors, TreeWithoutOccupiedLeaf) {
  octomap::OcTree tree(0.1);
  tree.updateNode(key_of({0, 0, 0}), false);
  const std::string path = tmp_path("free_only.bt");
  ASSERT_TRUE(tree.writeBinaryConst(path));
  EXPECT_THROW((void)load_octree_occupancy(path, {}), FormatError);
  EXPECT_THROW((void)occupancy_from_octree(tree, {}), ConfigError);
}

// ------------------------------------------------------------------ the real CATEC OctoMap

TEST(OctreeMapCatec, VoxelCountAndBoxMatchAnIndependentTraversal) {
  const std::string path = catec_path();
  if (!fs::exists(path)) GTEST_SKIP() << "CATEC OctoMap not found at " << path;
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path));

  // Oracle: OctoMap's own leaf traversal; a leaf at depth d holds 8^(16 - d) voxels.
  std::size_t voxels = 0, leaves = 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    ++leaves;
    voxels += std::size_t{1} << (3 * (tree.getTreeDepth() - it.getDepth()));
    const octomap::point3d c = it.getCoordinate();
    const double half = it.getSize() / 2;
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], static_cast<double>(c(d)) - half);
      hi[d] = std::max(hi[d], static_cast<double>(c(d)) + half);
    }
  }

  const OctreeOccupancy occ = load_octree_occupancy(path, {});
  EXPECT_DOUBLE_EQ(occ.tree_resolution, 0.05);
  EXPECT_DOUBLE_EQ(occ.occupancy.resolution(), 0.05);
  EXPECT_EQ(occ.num_occupied_leaves, leaves);
  const auto counted = static_cast<std::size_t>(
      std::count_if(occ.occupancy.values().begin(), occ.occupancy.values().end(),
                    [](std::uint8_t v) { return v != 0; }));
  EXPECT_EQ(counted, voxels);
  EXPECT_EQ(occ.num_occupied, voxels);
  // Leaf centres are floats in OctoMap: 1e-5 m.
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(occ.min_point[d], lo[d], 1e-5) << d;
    EXPECT_NEAR(occ.max_point[d], hi[d], 1e-5) << d;
    // Margin 0: the grid is exactly the box.
    EXPECT_NEAR(occ.occupancy.frame().origin()[d], lo[d], 1e-5) << d;
    EXPECT_NEAR(occ.occupancy.frame().origin()[d] + occ.occupancy.extent()[d], hi[d], 1e-5) << d;
  }

  // Every voxel of every occupied leaf is occupied in the grid; with the equal counts above the
  // two voxel sets are equal.
  std::size_t missing = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int n = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::point3d c = it.getCoordinate();
    const Eigen::Vector3d corner(c.x() - it.getSize() / 2, c.y() - it.getSize() / 2,
                                 c.z() - it.getSize() / 2);
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const Eigen::Vector3d p =
              corner + (Eigen::Vector3d(x, y, z).array() + 0.5).matrix() * 0.05;
          const Eigen::Vector3i i = occ.occupancy.cell_of(p);
          if (!occ.occupancy.contains(i) || occ.occupancy(i) == 0) ++missing;
        }
  }
  EXPECT_EQ(missing, 0u);
}

TEST(OctreeMapCatec, CoarseVdtMapDistanceIsTheBruteForceNearestOccupiedVoxel) {
  const std::string path = catec_path();
  if (!fs::exists(path)) GTEST_SKIP() << "CATEC OctoMap not found at " << path;
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(path));
  // Oracle at 0.2 m: the 0.2 m lattice voxel of the centre of every occupied 0.05 m voxel.
  VoxelSet expected;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int n = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::point3d c = it.getCoordinate();
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const Eigen::Vector3d p = Eigen::Vector3d(c.x(), c.y(), c.z()) -
                                    Eigen::Vector3d::Constant(it.getSize() / 2) +
                                    (Eigen::Vector3d(x, y, z).array() + 0.5).matrix() * 0.05;
          expected.insert({static_cast<int>(std::floor(p.x() / 0.2)),
                           static_cast<int>(std::floor(p.y() / 0.2)),
                           static_cast<int>(std::floor(p.z() / 0.2))});
        }
  }
  OctreeOccupancyOptions o;
  o.resolution = 0.2;
  o.margin = 0.4;
  const OctreeOccupancy occ = load_octree_occupancy(path, o);
  ASSERT_EQ(occupied_set(occ.occupancy), expected);

  const VdtMap3 map = VdtMap3::build(occ.occupancy);
  std::vector<Eigen::Vector3d> centres;
  for (const Voxel& v : expected)
    centres.push_back((Eigen::Vector3d(v[0], v[1], v[2]) + Eigen::Vector3d::Constant(0.5)) * 0.2);
  std::mt19937 rng(3);
  int checked = 0;
  for (int trial = 0; trial < 1000 && checked < 12; ++trial) {
    Eigen::Vector3i i;
    for (int d = 0; d < 3; ++d)
      i[d] = std::uniform_int_distribution<int>(0, map.size()[d] - 1)(rng);
    if (occ.occupancy(i) != 0) continue;
    const Eigen::Vector3d p = occ.occupancy.cell_center(i);
    double best = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& c : centres) best = std::min(best, (p - c).norm());
    EXPECT_NEAR(map.nearest_point_query(p).value.norm(), best, 1e-9) << p.transpose();
    EXPECT_NEAR(map.evaluate(p).value.norm(), best, 1e-4) << p.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, 12);
}

}  // namespace
}  // namespace vdtnav
