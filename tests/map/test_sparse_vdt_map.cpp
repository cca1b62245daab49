// The sparse (brick) VDT map against the dense VdtMap3 of the same occupancy (a generated room):
// values and Jacobians inside the band, the tolerance shown to be tight (no prefilter overlap
// fails it), exact nearest points against brute force, the coarse level's direction beyond the
// band, and the saved, memory-mapped file (bit-identical lookups, bad files refused).
#include "vdtnav/map/sparse_vdt_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../thread_count.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace vdtnav {
namespace {

/// Tolerances of the fine level against the dense map (SparseVdtMapOptions::prefilter_overlap = 8:
/// 0.268^8 ~ 3e-5 of a coefficient's neighbours' differences, plus float rounding).
constexpr double kValueTolerance = 2e-5;     // metres (the room's resolution is 0.1 m)
constexpr double kJacobianTolerance = 5e-4;  // per unit (the Jacobian is ~identity)

struct Room {
  sim::Room3d room;
  VdtMap3 dense;
  std::vector<Eigen::Vector3d> surface;  ///< feature voxel centres, the brute-force oracle
};

const Room& room() {
  static const Room r = [] {
    Room r;
    sim::Room3dOptions o;
    o.resolution = 0.1;
    o.wall_thickness = 0.3;
    r.room = sim::generate_room3d(o);
    r.dense = VdtMap3::build(r.room.occupancy);
    const OccupancyGrid<3> s = surface_cells(r.room.occupancy);
    for (std::size_t c = 0; c < s.num_cells(); ++c) {
      if (s[c] != 0) r.surface.push_back(s.cell_center(s.index_of(static_cast<std::ptrdiff_t>(c))));
    }
    return r;
  }();
  return r;
}

double brute_force_distance(const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& s : room().surface) best = std::min(best, (p - s).squaredNorm());
  return std::sqrt(best);
}

/// Random points of the box whose distance to the surface (the dense map's exact query) is in
/// [lo, hi] metres.
std::vector<Eigen::Vector3d> points_at_distance(double lo, double hi, std::size_t count,
                                                std::uint32_t seed) {
  const VdtMap3& dense = room().dense;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  while (out.size() < count) {
    Eigen::Vector3d u;
    for (int d = 0; d < 3; ++d) u[d] = (dense.size()[d] - 1.0) * uni(rng);
    const Eigen::Vector3d p = dense.frame().world_point(u);
    const double dist = brute_force_distance(p);
    if (dist >= lo && dist <= hi) out.push_back(p);
  }
  return out;
}

struct Agreement {
  double value = 0.0, jacobian = 0.0;  ///< largest differences
  std::size_t coarse = 0;              ///< points answered by the coarse level
};

Agreement agreement(const SparseVdtMap3& sparse, const std::vector<Eigen::Vector3d>& pts) {
  Agreement a;
  std::vector<VdtSample<3>> s(pts.size()), d(pts.size());
  sparse.evaluate(pts.data(), pts.size(), s.data());
  room().dense.evaluate(pts.data(), pts.size(), d.data());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    a.coarse += !sparse.fine_level(pts[k]);
    a.value = std::max(a.value, (s[k].value - d[k].value).cwiseAbs().maxCoeff());
    a.jacobian = std::max(a.jacobian, (s[k].jacobian - d[k].jacobian).cwiseAbs().maxCoeff());
  }
  return a;
}

TEST(SparseVdtMap, AgreesWithTheDenseMapInsideTheBand) {
  const SparseVdtMap3 sparse = SparseVdtMap3::build(room().room.occupancy);
  const double band = sparse.band() * sparse.resolution();
  const auto pts = points_at_distance(0.0, band, 4000, 1);
  const Agreement a = agreement(sparse, pts);
  EXPECT_EQ(a.coarse, 0u) << "every point within the band is answered by the bricks";
  EXPECT_LT(a.value, kValueTolerance);
  EXPECT_LT(a.jacobian, kJacobianTolerance);
  std::printf("band agreement: |dv| %.3g m, |dJ| %.3g, bricks %zu, %zu B (dense %zu B)\n", a.value,
              a.jacobian, sparse.bricks().num_bricks, sparse.memory_bytes(),
              room().dense.memory_bytes());
}

TEST(SparseVdtMap, ToleranceIsTightWithoutPrefilterOverlap) {
  // Prefiltering each tile alone (or with too little overlap) is a different spline near the
  // tiles' borders: the tolerance above must catch it.
  const auto pts = points_at_distance(0.0, 0.4, 4000, 2);
  for (int overlap : {0, 2}) {
    SparseVdtMapOptions o;
    o.prefilter_overlap = overlap;
    const Agreement a = agreement(SparseVdtMap3::build(room().room.occupancy, o), pts);
    EXPECT_GT(a.value, kValueTolerance) << "overlap " << overlap;
  }
}

// The batch lookup's kernels (AVX2 + FMA and the portable one) against the portable point
// lookup, and the fine points against the dense map: supports within one brick, crossing a brick
// face in x (masked loads from two bricks) and in y or z, at the box's ends (natural-end ghosts
// folded into the weights), the coarse level, outside the box and NaN; the test checks that each
// case is reached.
TEST(SparseVdtMap, BatchLookupAgreesAtEveryInstructionSetAndWithTheDenseMap) {
  const SparseVdtMap3 sparse = SparseVdtMap3::build(room().room.occupancy);
  const Eigen::Vector3i n = sparse.size();
  const double band = sparse.band() * sparse.resolution();
  std::vector<Eigen::Vector3d> pts = points_at_distance(0.0, band, 3000, 6);
  for (const Eigen::Vector3d& p : points_at_distance(band + 0.1, 100.0, 300, 7)) pts.push_back(p);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int k = 0; k < 600; ++k) {  // on and near the box's faces, edges and corners
    Eigen::Vector3d u;
    for (int d = 0; d < 3; ++d) {
      const double h = n[d] - 1.0;
      const double ends[] = {0.0, 0.4 * uni(rng), 1.0 + uni(rng), h - 1.0 - uni(rng), h};
      u[d] = uni(rng) < 0.5 ? ends[k % 5] : h * uni(rng);
    }
    pts.push_back(sparse.frame().world_point(u));
  }
  pts.push_back(sparse.frame().world_point(Eigen::Vector3d(-1e-12, 1.0, n.z() - 1 + 1e-12)));
  pts.push_back(sparse.frame().world_point(Eigen::Vector3d(-3.0, n.y() + 5.0, 2.0)));
  pts.push_back(Eigen::Vector3d::Constant(1e6));
  pts.push_back(Eigen::Vector3d::Constant(std::nan("")));

  // Which path each point takes: the support's first node (as the kernels place it).
  std::size_t one_brick = 0, split_x = 0, split_yz = 0, folded = 0, coarse = 0;
  for (const Eigen::Vector3d& p : pts) {
    if (!sparse.fine_level(p)) {
      ++coarse;
      continue;
    }
    Eigen::Vector3d u = sparse.frame().continuous_index(p);
    bool fold = false;
    Eigen::Vector3i l;
    for (int d = 0; d < 3; ++d) {
      u[d] = std::clamp(std::isnan(u[d]) ? 0.0 : u[d], 0.0, n[d] - 1.0);
      const int base = std::min(static_cast<int>(u[d]), n[d] - 2);
      fold |= base == 0 || base == n[d] - 2;
      l[d] = std::clamp(base - 1, 0, n[d] - 4) % SparseVdtMap3::kBrick;
    }
    folded += fold;
    const auto split = (l.array() > SparseVdtMap3::kBrick - 4).eval();
    split_x += split.x();
    split_yz += !split.x() && (split.y() || split.z());
    one_brick += !split.any();
  }
  EXPECT_GT(one_brick, 100u);
  EXPECT_GT(split_x, 100u);
  EXPECT_GT(split_yz, 100u);
  EXPECT_GT(folded, 100u);
  EXPECT_GT(coarse, 100u);

  const SimdLevel best = simd_level();
  set_simd_level(SimdLevel::kBaseline);  // the reference: the portable lookup, point by point
  std::vector<VdtSample<3>> reference;
  for (const Eigen::Vector3d& p : pts) reference.push_back(sparse.evaluate(p));
  std::vector<VdtSample<3>> dense(pts.size());
  room().dense.evaluate(pts.data(), pts.size(), dense.data());
  int levels = 0;
  for (SimdLevel level : {SimdLevel::kBaseline, SimdLevel::kAvx2Fma}) {
    if (set_simd_level(level) != level) continue;  // the CPU lacks it
    ++levels;
    std::vector<VdtSample<3>> batch(pts.size()), values(pts.size());
    sparse.evaluate(pts.data(), pts.size(), batch.data());
    sparse.evaluate(pts.data(), pts.size(), values.data(), /*jacobian=*/false);
    double dense_value = 0.0, dense_jacobian = 0.0;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const VdtSample<3>& ref = reference[k];
      ASSERT_EQ(batch[k].inside, ref.inside) << "point " << k;
      ASSERT_EQ(values[k].inside, ref.inside) << "point " << k;
      // Float coefficients summed in another order, with fused multiply-adds: a few ulps.
      ASSERT_LT((batch[k].value - ref.value).cwiseAbs().maxCoeff(), 1e-5) << "point " << k;
      ASSERT_LT((batch[k].jacobian - ref.jacobian).cwiseAbs().maxCoeff(), 1e-4) << "point " << k;
      ASSERT_LT((values[k].value - ref.value).cwiseAbs().maxCoeff(), 1e-5) << "point " << k;
      if (!sparse.fine_level(pts[k]) || !ref.inside) continue;
      dense_value = std::max(dense_value, (batch[k].value - dense[k].value).cwiseAbs().maxCoeff());
      dense_jacobian =
          std::max(dense_jacobian, (batch[k].jacobian - dense[k].jacobian).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(dense_value, kValueTolerance) << "level " << static_cast<int>(level);
    EXPECT_LT(dense_jacobian, kJacobianTolerance) << "level " << static_cast<int>(level);
  }
  set_simd_level(best);
  EXPECT_GE(levels, 1);
  std::printf(
      "batch lookup: %zu points (%zu in one brick, %zu across x, %zu across y/z only, "
      "%zu at the box's ends, %zu coarse), %d instruction sets\n",
      pts.size(), one_brick, split_x, split_yz, folded, coarse, levels);
}

TEST(SparseVdtMap, MatchesTheDenseMapOnARotatedFrame) {
  OccupancyGrid<3> occ = room().room.occupancy;
  const GridFrame<3> f(occ.resolution(), occ.frame().origin(), 0.4);
  OccupancyGrid<3> rotated(occ.size(), f, 0);
  rotated.values() = occ.values();
  const VdtMap3 dense = VdtMap3::build(rotated);
  const SparseVdtMap3 sparse = SparseVdtMap3::build(rotated);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int checked = 0;
  for (int k = 0; k < 20000 && checked < 1000; ++k) {
    Eigen::Vector3d u;
    for (int d = 0; d < 3; ++d) u[d] = (occ.size()[d] - 1.0) * uni(rng);
    const Eigen::Vector3d p = f.world_point(u);
    if (dense.nearest_point_query(p).value.norm() > 0.3) continue;
    const VdtSample<3> s = sparse.evaluate(p), d = dense.evaluate(p);
    ASSERT_TRUE(sparse.fine_level(p));
    EXPECT_LT((s.value - d.value).cwiseAbs().maxCoeff(), kValueTolerance);
    EXPECT_LT((s.jacobian - d.jacobian).cwiseAbs().maxCoeff(), kJacobianTolerance);
    ++checked;
  }
  EXPECT_EQ(checked, 1000);
}

TEST(SparseVdtMap, NearestPointIsExactInsideTheBand) {
  const SparseVdtMap3 sparse = SparseVdtMap3::build(room().room.occupancy);
  const double band = sparse.band() * sparse.resolution();
  for (const Eigen::Vector3d& p : points_at_distance(0.0, band, 500, 4)) {
    // The query answers for the centre of p's cell (as VdtMap3's): compare there.
    const Eigen::Vector3d c = sparse.frame().cell_center(sparse.frame().cell_of(p));
    const VdtSample<3> s = sparse.nearest_point_query(c);
    EXPECT_NEAR(s.value.norm(), brute_force_distance(c), 1e-9) << p.transpose();
    EXPECT_TRUE(s.jacobian.isIdentity());
  }
}

TEST(SparseVdtMap, BeyondTheBandTheCoarseLevelPointsAway) {
  const SparseVdtMap3 sparse = SparseVdtMap3::build(room().room.occupancy);
  const double band = sparse.band() * sparse.resolution();
  const auto pts = points_at_distance(band + 0.1, 100.0, 2000, 5);
  std::size_t coarse = 0, away = 0, growing = 0, dense_away = 0, dense_growing = 0;
  for (const Eigen::Vector3d& p : pts) {
    const VdtSample<3> s = sparse.evaluate(p);
    ASSERT_TRUE(s.value.allFinite() && s.jacobian.allFinite());
    if (sparse.fine_level(p)) continue;  // the dense map's spline, tested above
    ++coarse;
    const Eigen::Vector3d exact = room().dense.nearest_point_query(p).value;
    away += s.value.dot(exact) > 0.0;  // points away from the nearest surface
    // p - c with c a real surface voxel: never nearer than the nearest one.
    EXPECT_GE(s.value.norm(), brute_force_distance(p) - 1e-9);
    // d|DT_v|^2/dp = 2 J^T DT_v: the distance grows along DT_v.
    growing += s.value.dot(s.jacobian.transpose() * s.value) > 0.0;
    const VdtSample<3> d = room().dense.evaluate(p);
    dense_away += d.value.dot(exact) > 0.0;
    dense_growing += d.value.dot(d.jacobian.transpose() * d.value) > 0.0;
  }
  std::printf("dense at the same points: %zu away, %zu growing\n", dense_away, dense_growing);
  EXPECT_GT(coarse, pts.size() / 4) << "the test reaches the coarse level";
  EXPECT_GE(away, coarse * 95 / 100);  // 96 %: the rest lie near cut loci
  EXPECT_EQ(growing, coarse);          // J = I
  std::printf("beyond the band: %zu/%zu coarse, of which %zu away, %zu growing\n", coarse,
              pts.size(), away, growing);
}

TEST(SparseVdtMap, BuildsFromAVoxelListAndRefusesBadInput) {
  const GridFrame<3> f(0.1, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3i> wall;
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 30; ++y) wall.emplace_back(10, y, z);
  const SparseVdtMap3 m = SparseVdtMap3::build(wall, f, Eigen::Vector3i(40, 30, 20));
  const VdtSample<3> s = m.evaluate(Eigen::Vector3d(1.33, 1.5, 1.0));
  EXPECT_NEAR(s.value.x(), 1.33 - 1.05, 1e-5);  // the wall's centre plane is x = 1.05
  EXPECT_NEAR(s.jacobian(0, 0), 1.0, 1e-4);
  EXPECT_THROW((void)SparseVdtMap3::build({}, f, Eigen::Vector3i(40, 30, 20)), ConfigError);
  EXPECT_THROW(
      (void)SparseVdtMap3::build({Eigen::Vector3i(40, 0, 0)}, f, Eigen::Vector3i(40, 30, 20)),
      ConfigError);
  EXPECT_THROW((void)SparseVdtMap3::build(wall, f, Eigen::Vector3i(40, 30, 3)), ConfigError);
  SparseVdtMapOptions o;
  o.band = -1.0;
  EXPECT_THROW((void)SparseVdtMap3::build(wall, f, Eigen::Vector3i(40, 30, 20), o), ConfigError);
}

TEST(SparseVdtMap, TheSameBricksForAnyThreadCount) {
  // A box of 3 x 3 x 1 build tiles (64 voxels a side) with walls, pillars and scattered voxels:
  // tiles built at once on the pool's threads, appended in tile order, must give the bricks, their
  // order, their coefficients and the coarse level of one thread, bit for bit.
  const Eigen::Vector3i size(150, 140, 40);
  const GridFrame<3> f(0.1, Eigen::Vector3d::Zero());
  std::vector<Eigen::Vector3i> occupied;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> ux(0, size.x() - 1), uy(0, size.y() - 1), uz(0, size.z() - 1);
  for (int z = 0; z < size.z(); ++z) {
    for (int y = 0; y < size.y(); ++y) occupied.emplace_back(70, y, z);  // a wall across tiles
    for (int x = 0; x < 60; ++x) occupied.emplace_back(x, 100, z);
    for (int k = 0; k < 3; ++k) occupied.emplace_back(120 + k, 20, z);  // a pillar
  }
  for (int k = 0; k < 200; ++k) occupied.emplace_back(ux(rng), uy(rng), uz(rng));
  const auto build = [&](int t) {
    const test::ThreadCount count(t);
    return SparseVdtMap3::build(occupied, f, size);
  };
  const SparseVdtMap3 one = build(1);
  const std::size_t boxes = static_cast<std::size_t>(((size.array() + 7) / 8).prod());
  ASSERT_GT(one.bricks().num_bricks, 100u);
  for (const int t : {2, 3}) {
    const SparseVdtMap3 m = build(t);
    const auto& a = one.bricks();
    const auto& b = m.bricks();
    ASSERT_EQ(a.num_bricks, b.num_bricks) << t << " threads";
    EXPECT_EQ(std::memcmp(a.index, b.index, boxes * sizeof(std::int32_t)), 0) << t;
    EXPECT_EQ(std::memcmp(a.coarse, b.coarse, 3 * boxes * sizeof(std::int32_t)), 0) << t;
    EXPECT_EQ(std::memcmp(a.coefficients, b.coefficients,
                          a.num_bricks * SparseVdtMap3::kBrickFloats * sizeof(float)),
              0)
        << t << " threads";
  }
}

std::string tmp_path(const std::string& name) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  return std::string(VDTNAV_TEST_TMP) + "/" + name;
}

TEST(SparseVdtMapFile, MemoryMappedRoundTripIsBitIdentical) {
  const SparseVdtMap3 built = SparseVdtMap3::build(room().room.occupancy);
  const std::string path = tmp_path("room.vdtsp");
  save_sparse_vdt_map(path, built);
  const SparseVdtMap3 loaded = load_sparse_vdt_map(path);
  EXPECT_EQ(loaded.bricks().num_bricks, built.bricks().num_bricks);
  EXPECT_EQ(loaded.memory_bytes(), built.memory_bytes());
  auto pts = points_at_distance(0.0, 0.4, 1000, 6);
  const auto far = points_at_distance(0.6, 100.0, 1000, 7);
  pts.insert(pts.end(), far.begin(), far.end());
  pts.emplace_back(-5.0, 100.0, 2.0);  // outside the box
  std::vector<VdtSample<3>> a(pts.size()), b(pts.size());
  built.evaluate(pts.data(), pts.size(), a.data());
  loaded.evaluate(pts.data(), pts.size(), b.data());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    ASSERT_EQ(std::memcmp(a[k].value.data(), b[k].value.data(), sizeof(double) * 3), 0);
    ASSERT_EQ(std::memcmp(a[k].jacobian.data(), b[k].jacobian.data(), sizeof(double) * 9), 0);
    ASSERT_EQ(a[k].inside, b[k].inside);
    ASSERT_EQ(built.nearest_point_query(pts[k]).value, loaded.nearest_point_query(pts[k]).value);
  }
  EXPECT_FALSE(a.back().inside);
}

/// Writes bytes to a file and expects load_sparse_vdt_map to refuse it with the file's name and
/// `what` in the message.
void expect_refused(const std::string& name, const std::vector<char>& bytes,
                    const std::string& what) {
  const std::string path = tmp_path(name);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  try {
    (void)load_sparse_vdt_map(path);
    ADD_FAILURE() << name << " was accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(SparseVdtMapFile, RefusesBadFilesNamingThem) {
  const std::string path = tmp_path("good.vdtsp");
  save_sparse_vdt_map(path, SparseVdtMap3::build(room().room.occupancy));
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> good((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
  expect_refused("empty.vdtsp", {}, "not a sparse vdtnav map file");
  std::vector<char> bad = good;
  bad[0] = 'X';
  expect_refused("magic.vdtsp", bad, "not a sparse vdtnav map file");
  expect_refused("short_header.vdtsp", std::vector<char>(good.begin(), good.begin() + 50),
                 "truncated file");
  expect_refused("truncated.vdtsp", std::vector<char>(good.begin(), good.end() - 100),
                 "truncated file");
  bad = good;
  bad.push_back(0);
  expect_refused("long.vdtsp", bad, "unexpected data after the map");
  bad = good;
  bad[8] = 9;
  expect_refused("version.vdtsp", bad, "unsupported format version 9");
  bad = good;
  bad[20] ^= 1;
  expect_refused("header.vdtsp", bad, "header checksum mismatch");
  bad = good;
  bad[bad.size() - 1000] ^= 0x10;
  expect_refused("payload.vdtsp", bad, "checksum mismatch");
  EXPECT_THROW((void)load_sparse_vdt_map(tmp_path("missing.vdtsp")), IoError);
}

}  // namespace
}  // namespace vdtnav
