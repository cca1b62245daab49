// The exact feature transform against a brute-force nearest-occupied-cell oracle, in 2D and 3D.
#include "vdtnav/map/vector_distance_transform.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "../thread_count.hpp"

namespace vdtnav {
namespace {

template <int Dim>
struct DimTag {
  static constexpr int kDim = Dim;
};
using Dims = ::testing::Types<DimTag<2>, DimTag<3>>;

template <typename Tag>
class VectorDistanceTransformTest : public ::testing::Test {
 protected:
  static constexpr int kDim = Tag::kDim;
  using Index = typename SpaceTraits<kDim>::Index;

  static OccupancyGrid<kDim> make(const Index& size) {
    return OccupancyGrid<kDim>(size, GridFrame<kDim>(0.1, SpaceTraits<kDim>::Vector::Zero()), 0);
  }

  /// Brute force: squared distance (cells) from every cell to its nearest occupied cell.
  static std::vector<std::int64_t> brute_force_d2(const OccupancyGrid<kDim>& occ) {
    std::vector<std::int64_t> best(occ.num_cells(), std::numeric_limits<std::int64_t>::max());
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      const Index i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      for (std::size_t o = 0; o < occ.num_cells(); ++o) {
        if (!occ[o]) continue;
        const std::int64_t d2 = (i - occ.index_of(static_cast<std::ptrdiff_t>(o))).squaredNorm();
        best[c] = std::min(best[c], d2);
      }
    }
    return best;
  }

  /// Checks the feature transform against the oracle: squared distances equal, features occupied,
  /// and features equal to the oracle's wherever the nearest occupied cell is unique.
  static void expect_exact(const OccupancyGrid<kDim>& occ) {
    const auto nearest = nearest_occupied_cells(occ);
    const auto d2 = brute_force_d2(occ);
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      const Index i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      ASSERT_NE(nearest[c], kNoFeature) << "cell " << i.transpose();
      ASSERT_TRUE(occ[static_cast<std::size_t>(nearest[c])]) << "feature of a cell is not occupied";
      const std::int64_t got = (i - occ.index_of(nearest[c])).squaredNorm();
      ASSERT_EQ(got, d2[c]) << "cell " << i.transpose();
      int ties = 0;
      std::size_t unique = 0;
      for (std::size_t o = 0; o < occ.num_cells(); ++o) {
        if (occ[o] && (i - occ.index_of(static_cast<std::ptrdiff_t>(o))).squaredNorm() == d2[c]) {
          ++ties;
          unique = o;
        }
      }
      if (ties == 1) {
        ASSERT_EQ(static_cast<std::size_t>(nearest[c]), unique);
      }
    }
  }

  /// Checks squared distances against the oracle over the list of occupied cells, for grids too
  /// large for expect_exact (cells x occupied cells work instead of cells^2).
  static void expect_exact_distances(const OccupancyGrid<kDim>& occ) {
    std::vector<Index> occupied;
    for (std::size_t o = 0; o < occ.num_cells(); ++o)
      if (occ[o]) occupied.push_back(occ.index_of(static_cast<std::ptrdiff_t>(o)));
    const auto nearest = nearest_occupied_cells(occ);
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      const Index i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      std::int64_t best = std::numeric_limits<std::int64_t>::max();
      for (const Index& o : occupied) best = std::min<std::int64_t>(best, (i - o).squaredNorm());
      ASSERT_NE(nearest[c], kNoFeature) << "cell " << i.transpose();
      ASSERT_TRUE(occ[static_cast<std::size_t>(nearest[c])]) << "feature of a cell is not occupied";
      ASSERT_EQ((i - occ.index_of(nearest[c])).squaredNorm(), best) << "cell " << i.transpose();
    }
  }

  /// Thin, odd and degenerate shapes (lines along every axis, sides of 1 and 2).
  static std::vector<Index> odd_shapes() {
    std::vector<std::array<int, 3>> sides = {{1, 1, 1}, {1, 57, 1}, {57, 1, 1}, {1, 1, 57},
                                             {7, 3, 5}, {3, 5, 7},  {2, 31, 3}, {31, 2, 1},
                                             {5, 1, 9}, {1, 9, 5},  {2, 2, 2},  {13, 11, 2}};
    std::vector<Index> shapes;
    for (const auto& s : sides) {
      Index size;
      for (int d = 0; d < kDim; ++d) size[d] = s[static_cast<std::size_t>(d)];
      shapes.push_back(size);
    }
    return shapes;
  }
};
TYPED_TEST_SUITE(VectorDistanceTransformTest, Dims);

TYPED_TEST(VectorDistanceTransformTest, EqualsBruteForceOnRandomGrids) {
  constexpr int kDim = TestFixture::kDim;
  std::mt19937 rng(20261122 + kDim);
  const int max_side = kDim == 2 ? 40 : 12;
  std::uniform_int_distribution<int> side(1, max_side);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  int tested = 0;
  for (int trial = 0; trial < 120; ++trial) {
    typename TestFixture::Index size;
    for (int d = 0; d < kDim; ++d) size[d] = side(rng);
    auto occ = TestFixture::make(size);
    const double p = std::pow(10.0, -2.5 + 2.3 * uni(rng));  // 0.3 % .. 60 % occupied
    bool any = false;
    for (auto& v : occ.values()) any |= (v = uni(rng) < p ? 1 : 0) != 0;
    if (!any) occ[occ.num_cells() / 2] = 1;
    TestFixture::expect_exact(occ);
    ++tested;
  }
  EXPECT_GE(tested, 100);
}

TYPED_TEST(VectorDistanceTransformTest, EqualsBruteForceOnOddShapes) {
  std::mt19937 rng(97);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (const auto& size : TestFixture::odd_shapes()) {
    SCOPED_TRACE(::testing::Message() << "size " << size.transpose());
    auto occ = TestFixture::make(size);
    std::uniform_int_distribution<std::size_t> cell(0, occ.num_cells() - 1);
    for (int trial = 0; trial < 4; ++trial) {  // a single occupied cell, corners included
      for (auto& v : occ.values()) v = 0;
      occ[trial == 0 ? 0 : trial == 1 ? occ.num_cells() - 1 : cell(rng)] = 1;
      TestFixture::expect_exact(occ);
    }
    for (auto& v : occ.values()) v = 1;  // all occupied
    TestFixture::expect_exact(occ);
    for (double p : {0.05, 0.3, 0.8}) {
      bool any = false;
      for (auto& v : occ.values()) any |= (v = uni(rng) < p ? 1 : 0) != 0;
      if (!any) occ[cell(rng)] = 1;
      TestFixture::expect_exact(occ);
    }
  }
}

TYPED_TEST(VectorDistanceTransformTest, LongLinesUseWideArithmetic) {
  // Squared distances along a 30000-cell side exceed the int32 fast path: the int64 one runs.
  constexpr int kDim = TestFixture::kDim;
  std::mt19937 rng(5);
  for (int axis = 0; axis < kDim; ++axis) {
    typename TestFixture::Index size = TestFixture::Index::Constant(1);
    size[axis] = 30000;
    size[(axis + 1) % kDim] = 2;
    auto occ = TestFixture::make(size);
    std::uniform_int_distribution<std::size_t> cell(0, occ.num_cells() - 1);
    for (int k = 0; k < 12; ++k) occ[cell(rng)] = 1;
    TestFixture::expect_exact_distances(occ);
  }
}

TYPED_TEST(VectorDistanceTransformTest, EmptyMapHasNoFeatures) {
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::make(TestFixture::Index::Constant(7));
  const auto nearest = nearest_occupied_cells(occ);
  for (auto f : nearest.values()) ASSERT_EQ(f, kNoFeature);
  const auto udt = unsigned_distance_transform(nearest);
  for (auto v : udt.values()) ASSERT_TRUE(std::isinf(v) && v > 0);
  const auto vdt = vector_distance_transform<kDim>(nearest);
  for (const auto& v : vdt.values()) ASSERT_TRUE(v.hasNaN());
}

TYPED_TEST(VectorDistanceTransformTest, AllOccupiedPointsToItself) {
  auto occ = TestFixture::make(TestFixture::Index::Constant(5));
  for (auto& v : occ.values()) v = 1;
  const auto nearest = nearest_occupied_cells(occ);
  for (std::size_t c = 0; c < occ.num_cells(); ++c)
    ASSERT_EQ(nearest[c], static_cast<std::int32_t>(c));
  const auto sdt = signed_distance_transform(occ);
  for (auto v : sdt.values()) ASSERT_TRUE(std::isinf(v) && v < 0);
}

TYPED_TEST(VectorDistanceTransformTest, SingleCellAndOneCellGrid) {
  auto occ = TestFixture::make(TestFixture::Index::Constant(9));
  const typename TestFixture::Index corner = TestFixture::Index::Constant(8);  // a border corner
  occ(corner) = 1;
  const auto nearest = nearest_occupied_cells(occ);
  const auto target = static_cast<std::int32_t>(occ.linear_index(corner));
  for (auto f : nearest.values()) ASSERT_EQ(f, target);
  auto one = TestFixture::make(TestFixture::Index::Ones());
  one[0] = 1;
  EXPECT_EQ(nearest_occupied_cells(one)[0], 0);
}

TYPED_TEST(VectorDistanceTransformTest, TiesKeepTheExactDistance) {
  // Two occupied cells mirror-symmetric about the centre: the centre column is a cut locus.
  auto occ = TestFixture::make(TestFixture::Index::Constant(9));
  typename TestFixture::Index a = TestFixture::Index::Constant(4), b = a;
  a[0] = 1;
  b[0] = 7;
  occ(a) = 1;
  occ(b) = 1;
  TestFixture::expect_exact(occ);
}

TYPED_TEST(VectorDistanceTransformTest, UdtAndSdtFollowTheDocumentedRule) {
  constexpr int kDim = TestFixture::kDim;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto occ = TestFixture::make(TestFixture::Index::Constant(kDim == 2 ? 25 : 9));
  for (auto& v : occ.values()) v = uni(rng) < 0.15 ? 1 : 0;
  OccupancyGrid<kDim> free_space = occ;
  for (auto& v : free_space.values()) v = v ? 0 : 1;
  const auto d_occ = TestFixture::brute_force_d2(occ);
  const auto d_free = TestFixture::brute_force_d2(free_space);
  const auto udt = unsigned_distance_transform(nearest_occupied_cells(occ));
  const auto sdt = signed_distance_transform(occ);
  const double r = occ.resolution();
  for (std::size_t c = 0; c < occ.num_cells(); ++c) {
    ASSERT_NEAR(udt[c], std::sqrt(static_cast<double>(d_occ[c])) * r, 1e-5);
    const double expected = occ[c] ? -(std::sqrt(static_cast<double>(d_free[c])) * r - r / 2)
                                   : std::sqrt(static_cast<double>(d_occ[c])) * r - r / 2;
    ASSERT_NEAR(sdt[c], expected, 1e-5);
    ASSERT_EQ(sdt[c] < 0, occ[c] != 0);
  }
}

TYPED_TEST(VectorDistanceTransformTest, VdtIsCellMinusFeatureInMetres) {
  constexpr int kDim = TestFixture::kDim;
  auto occ = TestFixture::make(TestFixture::Index::Constant(6));
  typename TestFixture::Index w = TestFixture::Index::Zero();
  occ(w) = 1;
  const auto vdt = vector_distance_transform<kDim>(nearest_occupied_cells(occ));
  for (std::size_t c = 0; c < occ.num_cells(); ++c) {
    const auto i = occ.index_of(static_cast<std::ptrdiff_t>(c));
    ASSERT_TRUE(vdt[c].isApprox((i.template cast<float>() * 0.1F), 1e-6F) ||
                i == TestFixture::Index::Zero());
  }
}

}  // namespace
}  // namespace vdtnav

namespace vdtnav {
namespace {

TYPED_TEST(VectorDistanceTransformTest, SurfaceCellsGiveTheSameTransformOutsideObstacles) {
  constexpr int kDim = TestFixture::kDim;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    auto occ = TestFixture::make(TestFixture::Index::Constant(kDim == 2 ? 30 : 10));
    // Blobby obstacles: thick regions with interiors.
    for (auto& v : occ.values()) v = uni(rng) < 0.3 ? 1 : 0;
    const auto surface = surface_cells(occ);
    const auto d_all = TestFixture::brute_force_d2(occ);
    const auto nearest = nearest_occupied_cells(surface);
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      ASSERT_TRUE(!surface[c] || occ[c]);
      if (occ[c]) continue;
      const auto i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      ASSERT_EQ((i - occ.index_of(nearest[c])).squaredNorm(), d_all[c]);
    }
  }
  // A solid block: only its outer layer is surface.
  auto block = TestFixture::make(TestFixture::Index::Constant(7));
  for (std::size_t c = 0; c < block.num_cells(); ++c) {
    const auto i = block.index_of(static_cast<std::ptrdiff_t>(c));
    block[c] = ((i.array() >= 1).all() && (i.array() <= 5).all()) ? 1 : 0;
  }
  const auto s = surface_cells(block);
  EXPECT_FALSE(s(TestFixture::Index::Constant(3)));
  EXPECT_TRUE(s(TestFixture::Index::Constant(1)));
}

TYPED_TEST(VectorDistanceTransformTest, ExactAndTheSameForAnyThreadCount) {
  // Grids long and large enough to be cut into blocks of planes (16 planes and 2^16 cells), with
  // lines whose nearest occupied cell lies blocks away: the seeds a block takes from the others.
  constexpr int kDim = TestFixture::kDim;
  using Index = typename TestFixture::Index;
  Index size;
  if constexpr (kDim == 2) {
    size = Index(320, 211);
  } else {
    size = Index(24, 22, 131);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<OccupancyGrid<kDim>> grids;
  for (const double p : {0.02, 0.002}) {
    auto occ = TestFixture::make(size);
    for (auto& v : occ.values()) v = uni(rng) < p ? 1 : 0;
    occ[occ.num_cells() / 3] = 1;
    grids.push_back(occ);
  }
  auto one_plane = TestFixture::make(size);  // every line's site is in one block
  for (std::size_t c = 0; c < one_plane.num_cells(); ++c) {
    one_plane[c] = one_plane.index_of(static_cast<std::ptrdiff_t>(c))[kDim - 1] == 5 ? 1 : 0;
  }
  grids.push_back(one_plane);
  for (const auto& occ : grids) {
    std::vector<std::int32_t> one;
    {
      const test::ThreadCount count(1);
      const auto nearest = nearest_occupied_cells(occ);
      one.assign(nearest.data(), nearest.data() + nearest.num_cells());
    }
    for (const int t : {2, 3, 5}) {
      const test::ThreadCount count(t);
      const auto nearest = nearest_occupied_cells(occ);
      ASSERT_TRUE(std::equal(one.begin(), one.end(), nearest.data())) << t << " threads";
    }
    const test::ThreadCount count(3);
    TestFixture::expect_exact_distances(occ);
  }
}

}  // namespace
}  // namespace vdtnav
