// PCL front end against an independent voxelization of the cloud written with pcl::io, in every
// format the loader accepts, and brute-force nearest-voxel distances.
#include "vdtnav/pcl/pcl.hpp"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <string>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using Voxel = std::array<int, 3>;
using VoxelSet = std::set<Voxel>;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

constexpr double kRes = 0.1;
constexpr std::size_t kNonFinite = 10;

std::string tmp_path(const std::string& name) {
  // The running test's own folder: ctest runs this file's tests in parallel.
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string own = std::string(test->test_suite_name()) + "." + test->name();
  for (char& c : own) c = c == '/' ? '_' : c;
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "point_cloud_map" / own;
  fs::create_directories(dir);
  return (dir / name).string();
}

/// Points on two planes — a floor (z ~ 0.05) and a wall (x ~ 1.25) — every coordinate at least a
/// tenth of a voxel from a 0.1 m voxel face, so that no rounding decides a voxel; then 7 points
/// with a NaN coordinate and 3 with an infinite one.
Cloud two_planes() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> frac(0.1, 0.9);
  const auto coord = [&](int lo, int hi) {  // in voxel [k, k+1) * kRes, k in [lo, hi)
    const int k = std::uniform_int_distribution<int>(lo, hi - 1)(rng);
    return static_cast<float>((k + frac(rng)) * kRes);
  };
  Cloud cloud;
  for (int n = 0; n < 1500; ++n)
    cloud.push_back(pcl::PointXYZ(coord(0, 20), coord(-5, 15), coord(0, 1)));
  for (int n = 0; n < 800; ++n)
    cloud.push_back(pcl::PointXYZ(coord(12, 13), coord(-5, 15), coord(0, 10)));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int n = 0; n < 7; ++n) cloud.insert(cloud.begin() + 100 * n, pcl::PointXYZ(nan, 0.5f, 0.5f));
  for (int n = 0; n < 3; ++n) cloud.push_back(pcl::PointXYZ(0.5f, 0.5f, n == 1 ? -inf : inf));
  cloud.is_dense = false;
  return cloud;
}

/// The oracle: lattice voxels floor(p / res) of the finite points.
VoxelSet voxelize(const Cloud& cloud, double res) {
  VoxelSet set;
  for (const auto& p : cloud.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    set.insert({static_cast<int>(std::floor(p.x / res)), static_cast<int>(std::floor(p.y / res)),
                static_cast<int>(std::floor(p.z / res))});
  }
  return set;
}

/// Occupied voxels of a grid as indices of the world lattice of its resolution.
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

/// Bounding box of the finite points.
void finite_bounds(const Cloud& cloud, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const auto& p : cloud.points) {
    const Eigen::Vector3d q(p.x, p.y, p.z);
    if (!q.allFinite()) continue;
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
}

/// The voxels, the counts, the box and the margin of a voxelized two_planes() cloud.
void expect_voxelization(const PointCloudOccupancy& occ, const Cloud& cloud, double margin,
                         double box_tolerance) {
  const VoxelSet expected = voxelize(cloud, kRes);
  EXPECT_EQ(occ.num_points, cloud.size());
  EXPECT_EQ(occ.num_dropped, kNonFinite);
  EXPECT_EQ(occ.num_occupied, expected.size());
  EXPECT_EQ(occupied_set(occ.occupancy), expected);
  Eigen::Vector3d lo, hi;
  finite_bounds(cloud, lo, hi);
  const GridFrame<3>& f = occ.occupancy.frame();
  const Eigen::Vector3d far = f.origin() + occ.occupancy.extent();
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(occ.min_point[d], lo[d], box_tolerance) << d;
    EXPECT_NEAR(occ.max_point[d], hi[d], box_tolerance) << d;
    // At least `margin` of free space on both sides, less than one voxel more.
    EXPECT_LE(f.origin()[d], occ.min_point[d] - margin + 1e-9) << d;
    EXPECT_GT(f.origin()[d], occ.min_point[d] - margin - kRes) << d;
    EXPECT_GE(far[d], occ.max_point[d] + margin - 1e-9) << d;
    EXPECT_LT(far[d], occ.max_point[d] + margin + kRes + 1e-9) << d;
  }
}

struct Format {
  const char* name;
  const char* extension;
  bool (*write)(const std::string&, const Cloud&);
  double box_tolerance;  // ASCII writers round coordinates
};

const Format kFormats[] = {
    {"pcd_ascii", ".pcd",
     [](const std::string& p, const Cloud& c) { return pcl::io::savePCDFileASCII(p, c) == 0; },
     1e-6},
    {"pcd_binary", ".pcd",
     [](const std::string& p, const Cloud& c) { return pcl::io::savePCDFileBinary(p, c) == 0; },
     0.0},
    {"pcd_binary_compressed", ".pcd",
     [](const std::string& p, const Cloud& c) {
       return pcl::io::savePCDFileBinaryCompressed(p, c) == 0;
     },
     0.0},
    {"ply_binary", ".ply",
     [](const std::string& p, const Cloud& c) { return pcl::io::savePLYFileBinary(p, c) == 0; },
     0.0},
};

class PointCloudFile : public ::testing::TestWithParam<Format> {
 protected:
  std::string write(const Cloud& cloud) const {
    const std::string path =
        tmp_path(std::string("two_planes_") + GetParam().name + GetParam().extension);
    EXPECT_TRUE(GetParam().write(path, cloud)) << path;
    return path;
  }
};

TEST_P(PointCloudFile, VoxelsAreThoseOfAnIndependentVoxelization) {
  const Cloud cloud = two_planes();
  const std::string path = write(cloud);
  for (const double margin : {0.0, 0.25, 1.0}) {
    PointCloudOccupancyOptions o;
    o.resolution = kRes;
    o.margin = margin;
    SCOPED_TRACE(margin);
    expect_voxelization(load_point_cloud_occupancy(path, o), cloud, margin,
                        GetParam().box_tolerance);
  }
}

TEST_P(PointCloudFile, MatchesTheInMemoryCloud) {
  const Cloud cloud = two_planes();
  const std::string path = write(cloud);
  PointCloudOccupancyOptions o;
  o.resolution = kRes;
  o.margin = 0.3;
  const PointCloudOccupancy from_file = load_point_cloud_occupancy(path, o);
  const PointCloudOccupancy in_memory = occupancy_from_point_cloud(cloud, o);
  EXPECT_EQ(in_memory.occupancy.size(), from_file.occupancy.size());
  EXPECT_EQ(in_memory.occupancy.values(), from_file.occupancy.values());
  EXPECT_EQ(in_memory.num_dropped, from_file.num_dropped);
}

INSTANTIATE_TEST_SUITE_P(Formats, PointCloudFile, ::testing::ValuesIn(kFormats),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(PointCloudMap, InMemoryCloudVoxelsMarginsAndDroppedPoints) {
  const Cloud cloud = two_planes();
  for (const double res : {0.1, 0.25}) {
    PointCloudOccupancyOptions o;
    o.resolution = res;
    o.margin = 0.5;
    o.thin_surfaces = false;  // the voxelization rule itself (the thinning: test_thin_surfaces)
    const PointCloudOccupancy occ = occupancy_from_point_cloud(cloud, o);
    EXPECT_EQ(occ.num_dropped, kNonFinite);
    EXPECT_EQ(occupied_set(occ.occupancy), voxelize(cloud, res)) << res;
  }
}

TEST(PointCloudMap, DoubleCoordinatesAndExtraFields) {
  // A hand-written ASCII PCD with float64 x, y, z and an intensity field.
  const std::string path = tmp_path("double_fields.pcd");
  std::ofstream(path) << "# .PCD v0.7\nVERSION 0.7\nFIELDS intensity x y z\nSIZE 4 8 8 8\n"
                         "TYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                         "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
                         "7 0.123456789012 -2.35 4.05\n8 nan 1 1\n9 1.15 0.05 -0.95\n";
  PointCloudOccupancyOptions o;
  o.resolution = kRes;
  const PointCloudOccupancy occ = load_point_cloud_occupancy(path, o);
  EXPECT_EQ(occ.num_points, 3u);
  EXPECT_EQ(occ.num_dropped, 1u);
  EXPECT_EQ(occupied_set(occ.occupancy), (VoxelSet{{1, -24, 40}, {11, 0, -10}}));
  EXPECT_DOUBLE_EQ(occ.min_point.x(), 0.123456789012);  // kept in double precision
}

TEST(PointCloudMap, VdtMapDistanceIsTheBruteForceNearestOccupiedVoxel) {
  const Cloud cloud = two_planes();
  PointCloudOccupancyOptions o;
  o.resolution = kRes;
  o.margin = 0.4;
  const std::string path = tmp_path("two_planes_for_map.pcd");
  ASSERT_EQ(pcl::io::savePCDFileBinary(path, cloud), 0);
  const VdtMap3 from_file = load_point_cloud_map(path, o);
  const VdtMap3 in_memory = vdt_map_from_point_cloud(cloud, o);
  const PointCloudOccupancy occ = occupancy_from_point_cloud(cloud, o);
  const VoxelSet voxels = voxelize(cloud, kRes);
  std::mt19937 rng(5);
  int checked = 0;
  for (int trial = 0; trial < 500 && checked < 30; ++trial) {
    Eigen::Vector3i i;
    for (int d = 0; d < 3; ++d)
      i[d] = std::uniform_int_distribution<int>(0, occ.occupancy.size()[d] - 1)(rng);
    if (occ.occupancy(i) != 0) continue;
    const Eigen::Vector3d p = occ.occupancy.cell_center(i);
    double best = std::numeric_limits<double>::infinity();
    for (const Voxel& v : voxels) {
      const Eigen::Vector3d c =
          (Eigen::Vector3d(v[0], v[1], v[2]) + Eigen::Vector3d::Constant(0.5)) * kRes;
      best = std::min(best, (p - c).norm());
    }
    EXPECT_NEAR(from_file.nearest_point_query(p).value.norm(), best, 1e-9) << p.transpose();
    EXPECT_NEAR(in_memory.evaluate(p).value.norm(), best, 1e-4) << p.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, 30);
}

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

TEST(PointCloudMap, SparseMapFromTheCloudMatchesTheDenseMapNearItsSurfaces) {
  // The occupied voxels as a list, no dense grid: within the band the sparse map answers as the
  // dense map of the same cloud on the same lattice (file and memory alike).
  const Cloud cloud = two_planes();
  PointCloudOccupancyOptions o;
  o.resolution = kRes;
  o.margin = 0.5;
  const VdtMap3 dense = vdt_map_from_point_cloud(cloud, o);
  const SparseVdtMap3 sparse = sparse_vdt_map_from_point_cloud(cloud, o);
  const std::string path = tmp_path("sparse.pcd");
  ASSERT_EQ(pcl::io::savePCDFileBinary(path, cloud), 0);
  const SparseVdtMap3 from_file = load_point_cloud_sparse_map(path, o);
  ASSERT_EQ(sparse.size(), dense.size());
  ASSERT_EQ(sparse.frame().origin(), dense.frame().origin());
  std::mt19937 rng(5);
  int near = 0;
  for (int trial = 0; trial < 5000 && near < 300; ++trial) {
    Eigen::Vector3d p;
    for (int d = 0; d < 3; ++d)
      p[d] = dense.frame().origin()[d] +
             std::uniform_real_distribution<double>(1.0, dense.size()[d] - 1.0)(rng) * kRes;
    if (dense.nearest_point_query(p).value.norm() > (sparse.band() - 0.5) * kRes) continue;
    const VdtSample<3> a = dense.evaluate(p), b = sparse.evaluate(p), c = from_file.evaluate(p);
    EXPECT_LT((a.value - b.value).norm(), 2e-5) << p.transpose();
    EXPECT_LT((a.jacobian - b.jacobian).norm(), 5e-4) << p.transpose();
    EXPECT_EQ(b.value, c.value);
    ++near;
  }
  EXPECT_EQ(near, 300);
}

TEST(PointCloudMap, ASparseMapTakesABoxTheDenseGridRefuses) {
  // 150 m apart on every axis at 0.1 m: 3.4e9 voxels, past the dense grid's 2^31.
  Cloud cloud;
  cloud.push_back(pcl::PointXYZ(0.05f, 0.05f, 0.05f));
  cloud.push_back(pcl::PointXYZ(150.05f, 150.05f, 150.05f));
  PointCloudOccupancyOptions o;
  o.resolution = 0.1;
  EXPECT_THROW((void)occupancy_from_point_cloud(cloud, o), ConfigError);
  const SparseVdtMap3 sparse = sparse_vdt_map_from_point_cloud(cloud, o);
  EXPECT_GT(sparse.size().cast<double>().prod(), 2147483648.0);
  // Next to each point, DT_v points back to it.
  const VdtSample<3> s = sparse.evaluate(Eigen::Vector3d(0.25, 0.05, 0.05));
  EXPECT_NEAR(s.value.x(), 0.2, 1e-4);
  EXPECT_NEAR(s.value.tail<2>().norm(), 0.0, 1e-4);
}

TEST(PointCloudMapErrors, BadFilesNameTheFile) {
  const PointCloudOccupancyOptions o;
  const auto load = [&](const std::string& p) {
    return [&, p] { (void)load_point_cloud_occupancy(p, o); };
  };

  const std::string missing = tmp_path("does_not_exist.pcd");
  expect_error_naming<IoError>(load(missing), missing, "missing");
  const std::string directory = tmp_path("a_directory.ply");
  fs::create_directories(directory);
  expect_error_naming<IoError>(load(directory), directory, "directory");

  const std::string garbage_pcd = tmp_path("garbage.pcd");
  std::ofstream(garbage_pcd) << "this is not a point cloud\n1 2 3\n";
  expect_error_naming<FormatError>(load(garbage_pcd), garbage_pcd, "garbage .pcd");
  // A zero-byte PCD file (PCL 1.13's PCDReader::read alone segfaults on it: PCL issue #5854).
  const std::string zero_bytes = tmp_path("zero_bytes.pcd");
  std::ofstream{zero_bytes};
  expect_error_naming<FormatError>(load(zero_bytes), zero_bytes, "zero-byte .pcd");
  const std::string garbage_ply = tmp_path("garbage.ply");
  std::ofstream(garbage_ply) << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                "end_header\nnot numbers\n";
  expect_error_naming<FormatError>(load(garbage_ply), garbage_ply, "garbage .ply");

  const std::string empty = tmp_path("empty.pcd");
  std::ofstream(empty) << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                          "COUNT 1 1 1\nWIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\n"
                          "DATA ascii\n";
  expect_error_naming<FormatError>(load(empty), empty, "empty cloud");

  const std::string all_nan = tmp_path("all_nan.pcd");
  Cloud nan_cloud;
  nan_cloud.push_back(pcl::PointXYZ(std::numeric_limits<float>::quiet_NaN(), 0, 0));
  nan_cloud.is_dense = false;
  ASSERT_EQ(pcl::io::savePCDFileBinary(all_nan, nan_cloud), 0);
  expect_error_naming<FormatError>(load(all_nan), all_nan, "no finite point");

  const std::string no_z = tmp_path("no_z.pcd");
  std::ofstream(no_z) << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\n"
                         "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n1 2\n";
  expect_error_naming<FormatError>(load(no_z), no_z, "no z field");

  const std::string wrong_ext = tmp_path("cloud.las");
  std::ofstream(wrong_ext) << "1 2 3\n";
  expect_error_naming<FormatError>(load(wrong_ext), wrong_ext, "unknown extension");
}

TEST(PointCloudMapErrors, OptionsOutOfTheirDomain) {
  const std::string path = tmp_path("options.pcd");
  ASSERT_EQ(pcl::io::savePCDFileBinary(path, two_planes()), 0);
  for (const double res : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN()}) {
    PointCloudOccupancyOptions o;
    o.resolution = res;
    expect_error_naming<ConfigError>([&] { (void)load_point_cloud_occupancy(path, o); }, path,
                                     "resolution");
    EXPECT_THROW((void)occupancy_from_point_cloud(two_planes(), o), ConfigError);
  }
  PointCloudOccupancyOptions o;
  o.margin = -0.1;
  expect_error_naming<ConfigError>([&] { (void)load_point_cloud_occupancy(path, o); }, path,
                                   "margin");
  o.margin = 0.0;
  o.resolution = 1e-6;  // 2^31 voxels or more
  expect_error_naming<ConfigError>([&] { (void)load_point_cloud_occupancy(path, o); }, path,
                                   "too many voxels");
}

TEST(PointCloudMapErrors, InMemoryEmptyOrNonFiniteCloud) {
  const PointCloudOccupancyOptions o;
  EXPECT_THROW((void)occupancy_from_point_cloud(Cloud(), o), ConfigError);
  Cloud nan_cloud;
  nan_cloud.push_back(pcl::PointXYZ(0, std::numeric_limits<float>::infinity(), 0));
  EXPECT_THROW((void)occupancy_from_point_cloud(nan_cloud, o), ConfigError);
  // A planar cloud with no margin is one voxel thick: a VdtMap3 needs 2 voxels per axis.
  Cloud flat;
  flat.push_back(pcl::PointXYZ(0.01f, 0.01f, 0.01f));
  flat.push_back(pcl::PointXYZ(0.51f, 0.31f, 0.01f));
  EXPECT_EQ(occupancy_from_point_cloud(flat, o).occupancy.size().z(), 1);
  EXPECT_THROW((void)vdt_map_from_point_cloud(flat, o), ConfigError);
}

}  // namespace
}  // namespace vdtnav
