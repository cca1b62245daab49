// The continuous VDT map: interpolation at nodes, exact linear fields, analytic gradients and
// Hessians against central finite differences, clamping, and the exact nearest-point query.
#include "vdtnav/map/vdt_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
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
class VdtMapTest : public ::testing::Test {
 protected:
  static constexpr int kDim = Tag::kDim;
  using Vector = typename SpaceTraits<kDim>::Vector;
  using Matrix = typename SpaceTraits<kDim>::Matrix;
  using Index = typename SpaceTraits<kDim>::Index;

  /// A room with walls on the border and one interior wall: straight walls and a cut locus.
  static OccupancyGrid<kDim> room(double yaw = 0.0, int n = kDim == 2 ? 40 : 16) {
    Vector origin = Vector::Constant(-0.8);
    OccupancyGrid<kDim> occ(Index::Constant(n), GridFrame<kDim>(0.1, origin, yaw), 0);
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      const Index i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      const bool border = (i.array() == 0).any() || (i.array() == n - 1).any();
      const bool wall = i[0] == n / 2 && i[1] < n / 2;
      occ[c] = (border || wall) ? 1 : 0;
    }
    return occ;
  }

  static Vector random_point(std::mt19937& rng, const GridFrame<kDim>& f, const Index& size) {
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    Vector u;
    for (int d = 0; d < kDim; ++d) u[d] = 0.5 + (size[d] - 2.0) * uni(rng);
    return f.world_point(u);
  }
};
TYPED_TEST_SUITE(VdtMapTest, Dims);

TYPED_TEST(VdtMapTest, InterpolatesTheExactVdtAtCellCentres) {
  constexpr int kDim = TestFixture::kDim;
  for (double yaw : {0.0, 0.6}) {
    const auto occ = TestFixture::room(yaw);
    const auto map = VdtMap<kDim>::build(occ);
    const auto nearest = nearest_occupied_cells(surface_cells(occ));
    for (std::size_t c = 0; c < occ.num_cells(); c += 7) {
      const auto i = occ.index_of(static_cast<std::ptrdiff_t>(c));
      const auto p = occ.cell_center(i);
      const typename TestFixture::Vector exact =
          p - occ.cell_center(occ.index_of(nearest[c]));  // DT_v = p - c(p)
      const auto s = map.evaluate(p);
      ASSERT_TRUE(s.inside);
      ASSERT_LT((s.value - exact).norm(), 2e-5) << "cell " << i.transpose() << " yaw " << yaw;
    }
  }
}

TYPED_TEST(VdtMapTest, ReproducesLinearFieldsExactly) {
  constexpr int kDim = TestFixture::kDim;
  using Field = CubicBSplineField<kDim, 1>;
  const typename TestFixture::Index size = TestFixture::Index::Constant(kDim == 2 ? 13 : 7);
  typename TestFixture::Vector slope;
  for (int d = 0; d < kDim; ++d) slope[d] = 0.7 - 0.45 * d;
  std::vector<float> samples;
  const Grid<float, kDim> lattice(size, GridFrame<kDim>(1.0, TestFixture::Vector::Zero()));
  for (std::size_t c = 0; c < lattice.num_cells(); ++c) {
    samples.push_back(
        static_cast<float>(2.0 + slope.dot(lattice.index_of(c).template cast<double>())));
  }
  const Field field(size, samples);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    typename TestFixture::Vector u;
    for (int d = 0; d < kDim; ++d) u[d] = (size[d] - 1) * uni(rng);  // whole hull, ends included
    typename Field::Values v;
    typename Field::Jacobian g;
    typename Field::Hessians h;
    field.evaluate(u, &v, &g, &h);
    ASSERT_NEAR(v[0], 2.0 + slope.dot(u), 1e-5);
    ASSERT_LT((g.transpose() - slope).norm(), 1e-5);
    ASSERT_LT(h[0].norm(), 1e-4);
  }
}

TYPED_TEST(VdtMapTest, GradientAndHessianMatchFiniteDifferences) {
  constexpr int kDim = TestFixture::kDim;
  using Vector = typename TestFixture::Vector;
  for (double yaw : {0.0, -0.4}) {
    const auto occ = TestFixture::room(yaw);
    const auto map = VdtMap<kDim>::build(occ);
    std::mt19937 rng(11);
    const double h = 1e-3;  // metres: 1 % of a cell; values are float, so keep h moderate
    for (int k = 0; k < 300; ++k) {
      const Vector p = TestFixture::random_point(rng, occ.frame(), occ.size());
      const auto s = map.evaluate_with_hessian(p);
      for (int d = 0; d < kDim; ++d) {
        const Vector e = Vector::Unit(d) * h;
        const auto sp = map.evaluate(p + e), sm = map.evaluate(p - e);
        const Vector fd = (sp.value - sm.value) / (2 * h);
        ASSERT_LT((s.jacobian.col(d) - fd).norm(), 2e-3 * (1.0 + s.jacobian.norm())) << "d=" << d;
        for (int c = 0; c < kDim; ++c) {
          const Vector fd_h = (sp.jacobian.row(c) - sm.jacobian.row(c)).transpose() / (2 * h);
          ASSERT_LT((s.hessian[c].col(d) - fd_h).norm(), 2e-2 * (1.0 + s.hessian[c].norm()))
              << "component " << c << " d=" << d;
        }
      }
      ASSERT_LT((s.hessian[0] - s.hessian[0].transpose()).norm(), 1e-9);
    }
  }
}

TYPED_TEST(VdtMapTest, NearAStraightWallTheJacobianProjectsOntoTheNormal) {
  // SPEC: near a straight wall dDT_v/dp is the projector onto the wall normal. The prefilter is
  // global, so a cut locus rings into its neighbourhood (decaying by 0.268 per cell): test ten or
  // more cells away from every cut locus.
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::room(0.0, kDim == 2 ? 80 : 48);
  const auto map = VdtMap<kDim>::build(occ);
  // A point a few cells in from the x=0 border wall, away from every corner and cut locus.
  typename TestFixture::Vector u =
      typename TestFixture::Vector(occ.size().template cast<double>() / 2);
  u[0] = 3.3;
  if (kDim == 2) u[1] = occ.size()[1] * 0.625;
  const auto s = map.evaluate(occ.frame().world_point(u));
  typename TestFixture::Matrix projector = TestFixture::Matrix::Zero();
  projector(0, 0) = 1.0;
  EXPECT_LT((s.jacobian - projector).norm(), 1e-3);
  EXPECT_NEAR(s.value[0], (u[0] - 0.0) * occ.resolution(), 1e-4);  // distance from wall centre
}

TYPED_TEST(VdtMapTest, OutsideQueriesAreClampedAndFlagged) {
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::room();
  const auto map = VdtMap<kDim>::build(occ);
  typename TestFixture::Vector u = TestFixture::Vector::Constant(3.0);
  u[0] = -5.0;
  const auto out = map.evaluate(occ.frame().world_point(u));
  u[0] = 0.0;
  const auto clamped = map.evaluate(occ.frame().world_point(u));
  EXPECT_FALSE(out.inside);
  EXPECT_TRUE(clamped.inside);
  EXPECT_LT((out.value - clamped.value).norm(), 1e-9);
  bool inside = true;
  (void)map.value(TestFixture::Vector::Constant(std::nan("")), &inside);
  EXPECT_FALSE(inside);
}

// The batch lookup (SIMD kernels chosen at run time) against the point lookup, at every
// instruction set this CPU has: random points, points on and just off the hull, far outside, NaN,
// on a map with unequal sides and an offset origin (an axis or stride mix-up shows at once).
TYPED_TEST(VdtMapTest, BatchLookupAgreesWithThePointLookupAtEveryInstructionSet) {
  constexpr int kDim = TestFixture::kDim;
  using Vector = typename TestFixture::Vector;
  using Index = typename TestFixture::Index;
  Index size;
  for (int d = 0; d < kDim; ++d) size[d] = (kDim == 2 ? 37 : 13) - 5 * d;
  OccupancyGrid<kDim> occ(size, GridFrame<kDim>(0.07, Vector::LinSpaced(-1.3, 0.4)), 0);
  std::mt19937 rng(5);
  std::bernoulli_distribution wall(0.04);
  for (auto& v : occ.values()) v = wall(rng) ? 1 : 0;
  occ[0] = 1;
  const auto map = VdtMap<kDim>::build(occ);

  std::vector<Vector> pts;
  std::uniform_real_distribution<double> uni(-0.2, 1.2);  // some outside
  for (int k = 0; k < 2000; ++k) {
    Vector u;
    for (int d = 0; d < kDim; ++d) u[d] = uni(rng) * (size[d] - 1);
    pts.push_back(occ.frame().world_point(u));
  }
  for (double edge : {0.0, -1e-12, 1.0, 1.0 + 1e-12, 1.0 + 1e-6}) {
    Vector u;
    for (int d = 0; d < kDim; ++d) u[d] = (d == 0 ? edge : 0.5) * (size[d] - 1);
    pts.push_back(occ.frame().world_point(u));
  }
  pts.push_back(Vector::Constant(1e6));
  pts.push_back(Vector::Constant(std::nan("")));

  const SimdLevel best = simd_level();
  set_simd_level(SimdLevel::kBaseline);  // the reference: the portable evaluation, point by point
  std::vector<VdtSample<kDim>> reference;
  for (const Vector& p : pts) reference.push_back(map.evaluate(p));
  for (SimdLevel level : {SimdLevel::kBaseline, SimdLevel::kAvx2Fma}) {
    if (set_simd_level(level) != level) continue;  // the CPU lacks it
    std::vector<VdtSample<kDim>> batch(pts.size()), values(pts.size());
    map.evaluate(pts.data(), pts.size(), batch.data());
    map.evaluate(pts.data(), pts.size(), values.data(), /*jacobian=*/false);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const VdtSample<kDim>& ref = reference[k];
      const VdtSample<kDim> one = map.evaluate(pts[k]);
      bool inside = false;
      const Vector value = map.value(pts[k], &inside);
      for (const VdtSample<kDim>* s : {static_cast<const VdtSample<kDim>*>(&batch[k]), &one}) {
        ASSERT_EQ(s->inside, ref.inside) << "point " << k;
        // Float coefficients summed in another order, with fused multiply-adds: a few ulps.
        ASSERT_LT((s->value - ref.value).cwiseAbs().maxCoeff(), 1e-5) << "point " << k;
        ASSERT_LT((s->jacobian - ref.jacobian).cwiseAbs().maxCoeff(), 1e-4) << "point " << k;
      }
      ASSERT_EQ(values[k].inside, ref.inside) << "point " << k;
      ASSERT_EQ(inside, ref.inside) << "point " << k;
      ASSERT_LT((values[k].value - ref.value).cwiseAbs().maxCoeff(), 1e-5) << "point " << k;
      ASSERT_LT((value - ref.value).cwiseAbs().maxCoeff(), 1e-5) << "point " << k;
    }
  }
  set_simd_level(best);
}

TYPED_TEST(VdtMapTest, NearestPointQueryIsExact) {
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::room(0.3);
  const auto map = VdtMap<kDim>::build(occ);
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const auto p = TestFixture::random_point(rng, occ.frame(), occ.size());
    const auto s = map.nearest_point_query(p);
    // Brute force: nearest occupied cell centre to the centre of p's cell.
    const auto cell = occ.cell_of(p);
    double best = 1e9;
    for (std::size_t c = 0; c < occ.num_cells(); ++c) {
      if (occ[c])
        best = std::min(best, (occ.cell_center(cell) - occ.cell_center(occ.index_of(c))).norm());
    }
    ASSERT_NEAR((occ.cell_center(cell) - (p - s.value)).norm(), best, 1e-9);
    ASSERT_TRUE(s.jacobian.isIdentity());
  }
}

TYPED_TEST(VdtMapTest, TheSameMapForAnyThreadCount) {
  // Large enough that the samples, the surface cells and every axis's prefilter are cut into
  // pieces for the pool's threads: each piece's arithmetic is the same, so the coefficients are
  // bit for bit those of one thread.
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::room(0.0, kDim == 2 ? 1200 : 48);
  std::vector<float> one;
  {
    const test::ThreadCount count(1);
    const auto map = VdtMap<kDim>::build(occ);
    one = map.field().coefficients();
  }
  for (const int t : {2, 3}) {
    const test::ThreadCount count(t);
    const auto map = VdtMap<kDim>::build(occ);
    ASSERT_EQ(map.field().coefficients().size(), one.size());
    EXPECT_EQ(
        std::memcmp(map.field().coefficients().data(), one.data(), one.size() * sizeof(float)), 0)
        << t << " threads";
  }
}

TYPED_TEST(VdtMapTest, RejectsEmptyMapsAndDegenerateAxes) {
  constexpr int kDim = TestFixture::kDim;
  OccupancyGrid<kDim> empty(TestFixture::Index::Constant(4),
                            GridFrame<kDim>(0.1, TestFixture::Vector::Zero()), 0);
  EXPECT_THROW((void)VdtMap<kDim>::build(empty), ConfigError);
  typename TestFixture::Index thin = TestFixture::Index::Constant(4);
  thin[0] = 1;
  OccupancyGrid<kDim> line(thin, GridFrame<kDim>(0.1, TestFixture::Vector::Zero()), 1);
  EXPECT_THROW((void)VdtMap<kDim>::build(line), ConfigError);
}

TYPED_TEST(VdtMapTest, MemoryIsWithinTheBudget) {
  constexpr int kDim = TestFixture::kDim;
  const auto occ = TestFixture::room();
  const auto map = VdtMap<kDim>::build(occ);
  const double per_cell =
      static_cast<double>(map.memory_bytes()) / static_cast<double>(occ.num_cells());
  // 4 B features + 4 Dim B coefficients, plus the ghost layer on these small test maps.
  EXPECT_LE(per_cell, (4.0 + 4.0 * kDim) * (kDim == 2 ? 1.11 : 1.43));
}

TEST(DistanceFieldMap, InterpolatesUdtAndItsGradient) {
  OccupancyGrid<2> occ(Eigen::Vector2i(30, 20), GridFrame<2>(0.05, Eigen::Vector2d(1.0, 2.0)), 0);
  for (int i = 0; i < 30; ++i) occ(Eigen::Vector2i(i, 0)) = 1;  // a wall along y = 0 row
  const DistanceFieldMap<2> udt(unsigned_distance_transform(nearest_occupied_cells(occ)));
  const Eigen::Vector2d p = occ.cell_center(Eigen::Vector2i(15, 8)) + Eigen::Vector2d(0.01, 0.013);
  const auto s = udt.evaluate(p, true);
  EXPECT_NEAR(s.value, p.y() - occ.cell_center(Eigen::Vector2i(15, 0)).y(), 1e-4);
  EXPECT_LT((s.gradient - Eigen::Vector2d(0, 1)).norm(), 1e-3);
  EXPECT_LT(s.hessian.norm(), 1e-2);
}

}  // namespace
}  // namespace vdtnav
