// Ray casting against a brute-force fine ray march and against closed-form wall distances.
#include "vdtnav/sim/ray_casting.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vdtnav::sim {
namespace {

TEST(RayCasting, HitsTheNearFaceOfAWall) {
  // A wall of cells at column 30 (x in [1.5, 1.55) with 0.05 m cells).
  OccupancyGrid<2> g(Eigen::Vector2i(60, 40), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int j = 0; j < 40; ++j) g(Eigen::Vector2i(30, j)) = 1;
  const Eigen::Vector2d o(0.52, 1.0);
  EXPECT_NEAR(cast_ray<2>(g, o, Eigen::Vector2d(1, 0), 10.0), 1.5 - 0.52, 1e-12);
  const double a = 0.4;  // slanted: the face x = 1.5 is reached after (1.5 - 0.52) / cos a
  EXPECT_NEAR(cast_ray<2>(g, o, Eigen::Vector2d(std::cos(a), std::sin(a)), 10.0),
              0.98 / std::cos(a), 1e-12);
  // Thin-wall surface: the centre line of the wall cells, x = 1.525.
  EXPECT_NEAR(cast_ray<2>(g, o, Eigen::Vector2d(1, 0), 10.0, RaySurface::kCellCentre), 1.525 - 0.52,
              1e-12);
  EXPECT_NEAR(
      cast_ray<2>(g, o, Eigen::Vector2d(std::cos(a), std::sin(a)), 10.0, RaySurface::kCellCentre),
      1.005 / std::cos(a), 1e-12);
  EXPECT_TRUE(std::isinf(cast_ray<2>(g, o, Eigen::Vector2d(-1, 0), 10.0)));  // leaves the grid
  EXPECT_TRUE(std::isinf(cast_ray<2>(g, o, Eigen::Vector2d(1, 0), 0.5)));    // beyond max range
}

template <int Dim>
double march(const OccupancyGrid<Dim>& g, const typename SpaceTraits<Dim>::Vector& o,
             const typename SpaceTraits<Dim>::Vector& dir, double max_range) {
  const double h = 1e-4;
  for (double t = 0; t <= max_range; t += h) {
    const auto c = g.cell_of(o + t * dir);
    if (!g.contains(c)) return std::numeric_limits<double>::infinity();
    if (g(c)) return t;
  }
  return std::numeric_limits<double>::infinity();
}

template <int Dim>
void agrees_with_fine_march(double yaw) {
  using Vector = typename SpaceTraits<Dim>::Vector;
  std::mt19937 rng(Dim);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const int n = Dim == 2 ? 30 : 12;
  OccupancyGrid<Dim> g(SpaceTraits<Dim>::Index::Constant(n),
                       GridFrame<Dim>(0.1, Vector::Constant(-0.3), yaw), 0);
  for (auto& v : g.values()) v = uni(rng) < (Dim == 2 ? 0.04 : 0.1) ? 1 : 0;
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    Vector u, dir;
    for (int d = 0; d < Dim; ++d) u[d] = 1.0 + (n - 3.0) * uni(rng);
    for (int d = 0; d < Dim; ++d) dir[d] = uni(rng) - 0.5;
    dir.normalize();
    const Vector o = g.frame().world_point(u);
    if (g(g.cell_of(o))) continue;
    const double r = cast_ray<Dim>(g, o, dir, 2.0), m = march<Dim>(g, o, dir, 2.0);
    ASSERT_EQ(std::isinf(r), std::isinf(m)) << "ray " << k;
    if (!std::isinf(r)) {
      ASSERT_NEAR(r, m, 2e-4) << "ray " << k;
      ++hits;
    }
  }
  EXPECT_GT(hits, 50);
}

TEST(RayCasting, AgreesWithAFineRayMarch2D) {
  agrees_with_fine_march<2>(0.0);
  agrees_with_fine_march<2>(0.3);
}
TEST(RayCasting, AgreesWithAFineRayMarch3D) { agrees_with_fine_march<3>(0.0); }

TEST(RayCasting, A3dCellCentreHitIsOnTheSurfaceOrAMiss) {
  // A floor of 0.1 m voxels (layer k = 5, z in [0.5, 0.6): its surface the plane z = 0.55 through
  // the centres) that ends at x = 20 m, and rays onto it from 5 cm above at grazing elevations.
  // Where the floor goes on, the hit is on the plane (0.05 / sin(elevation) along). Where the ray
  // would reach the plane only past the floor's end it has missed the floor: no hit in the free
  // space beyond (half a voxel / sin(elevation) past the face, metres, before the fix).
  OccupancyGrid<3> g(Eigen::Vector3i(400, 40, 20), GridFrame<3>(0.1, Eigen::Vector3d::Zero()), 0);
  for (int i = 0; i < 200; ++i)
    for (int j = 0; j < 40; ++j) g(Eigen::Vector3i(i, j, 5)) = 1;
  int on_plane = 0, missed = 0;
  for (const double x0 : {0.55, 19.75, 19.95}) {
    const Eigen::Vector3d o(x0, 2.05, 0.65);
    for (const double elevation : {1.5, 1.0, 0.5, 0.2, 0.05, 0.01, 0.002}) {
      const Eigen::Vector3d d(std::cos(elevation), 0.0, -std::sin(elevation));
      const double t = cast_ray<3>(g, o, d, 100.0, RaySurface::kCellCentre);
      const double along = 0.1 / std::tan(elevation);  // x travelled down to z = 0.55
      if (x0 + along < 20.0) {
        ASSERT_TRUE(std::isfinite(t)) << x0 << " " << elevation;
        EXPECT_NEAR((o + t * d).z(), 0.55, 1e-9) << x0 << " " << elevation;
        ++on_plane;
      } else {
        EXPECT_TRUE(std::isinf(t)) << x0 << " " << elevation << ": hit at " << (o + t * d).x();
        ++missed;
      }
    }
  }
  EXPECT_GE(on_plane, 10);
  EXPECT_GE(missed, 5);
}

}  // namespace
}  // namespace vdtnav::sim
