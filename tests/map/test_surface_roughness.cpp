// The map's wall roughness (map/surface_roughness.hpp) against what the raster is known to hold:
// straight walls at the axes (no spread), both faces of thin and thick walls (never one rough
// face), a tilted straight wall and a jagged wall against the brute-force RMS offset of their
// surface cells from the true line, and a 3D slab and rough plane.
#include "vdtnav/map/surface_roughness.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

constexpr double kH = 0.05;

OccupancyGrid<2> empty(int n) {
  return OccupancyGrid<2>(Eigen::Vector2i(n, n), GridFrame<2>(kH, Eigen::Vector2d::Zero()), 0);
}

/// Column x is occupied below row top[x] (a wall whose free side faces +y).
OccupancyGrid<2> wall_below(const std::vector<int>& top) {
  const int n = static_cast<int>(top.size());
  OccupancyGrid<2> g = empty(n);
  for (int x = 0; x < n; ++x) {
    for (int y = 0; y < top[static_cast<std::size_t>(x)]; ++y) g(Eigen::Vector2i(x, y)) = 1;
  }
  return g;
}

/// RMS over columns (away from the ends) of the top cell's offset from the line y = a + b x,
/// in metres: the spread a range model sees on this wall.
double rms_offset(const std::vector<int>& top, double a, double b) {
  double s = 0.0;
  int count = 0;
  for (std::size_t x = 6; x + 6 < top.size(); ++x) {
    const double y_cell = top[x] - 1;  // the top occupied cell's row
    const double d = (y_cell - (a + b * static_cast<double>(x))) / std::sqrt(1.0 + b * b);
    s += d * d;
    ++count;
  }
  return std::sqrt(s / count) * kH;
}

TEST(SurfaceRoughness, StraightWallsAlongTheAxesHaveNoSpreadOnEitherFace) {
  for (const int thickness : {1, 2, 3, 6}) {  // a thick wall's two faces are two smooth surfaces
    OccupancyGrid<2> g = empty(60);
    for (int x = 5; x < 55; ++x) {
      for (int y = 20; y < 20 + thickness; ++y) g(Eigen::Vector2i(x, y)) = 1;
    }
    for (int y = 35; y < 55; ++y) g(Eigen::Vector2i(30, y)) = 1;  // and a thin vertical one
    const SurfaceRoughness r = measure_surface_roughness(g);
    EXPECT_GT(r.windows, 100U);
    EXPECT_LT(r.sigma, 0.1 * kH) << "thickness " << thickness;
    EXPECT_NEAR(r.floor, kH / std::sqrt(12.0), 1e-12);  // the quantisation floor remains
  }
}

TEST(SurfaceRoughness, TiltedStraightWallMatchesItsRasterOffsets) {
  // y = 20.3 + 0.37 x: a raster of a straight line spreads its cells by ~h/sqrt(12) about it.
  const double a = 20.3, b = 0.37;
  std::vector<int> top(80);
  for (int x = 0; x < 80; ++x)
    top[static_cast<std::size_t>(x)] = static_cast<int>(std::floor(a + b * x + 0.5)) + 1;
  const double oracle = rms_offset(top, a - 0.5 + 0.5, b);  // cells centred on integer rows
  // Fit's own line absorbs the mean offset: compare with the oracle about its mean.
  const SurfaceRoughness r = measure_surface_roughness(wall_below(top));
  EXPECT_GT(oracle, 0.2 * kH);
  EXPECT_NEAR(r.sigma, oracle, 0.25 * oracle);
  EXPECT_NEAR(r.sigma, kH / std::sqrt(12.0), 0.3 * kH / std::sqrt(12.0));
}

TEST(SurfaceRoughness, JaggedWallReadsItsJags) {
  // A horizontal wall whose top cell is off by -1, 0 or +1 cells at random: spread sqrt(2/3) h.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> jag(-1, 1);
  std::vector<int> top(200);
  for (int& t : top) t = 40 + jag(rng);
  const double oracle = rms_offset(top, 39.0, 0.0);
  const SurfaceRoughness r = measure_surface_roughness(wall_below(top));
  EXPECT_NEAR(oracle, std::sqrt(2.0 / 3.0) * kH, 0.1 * kH);
  // A window's fitted line takes up its own mean and tilt: about (1 - 2/9) of the variance.
  EXPECT_NEAR(r.sigma, oracle * std::sqrt(7.0 / 9.0), 0.2 * oracle);
  EXPECT_GT(r.floor, 2.0 * kH / std::sqrt(12.0));
}

TEST(SurfaceRoughness, ThreeDimensionalSlabAndRoughPlane) {
  const int n = 24;
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> jag(-1, 1);
  for (const bool rough : {false, true}) {
    OccupancyGrid<3> g(Eigen::Vector3i(n, n, n), GridFrame<3>(kH, Eigen::Vector3d::Zero()), 0);
    for (int x = 0; x < n; ++x) {
      for (int y = 0; y < n; ++y) {
        const int top = 12 + (rough ? jag(rng) : 0);
        for (int z = 0; z < top; ++z) g(Eigen::Vector3i(x, y, z)) = 1;
      }
    }
    const SurfaceRoughness r = measure_surface_roughness(g);
    EXPECT_GT(r.windows, 300U);
    if (rough) {
      EXPECT_NEAR(r.sigma, std::sqrt(2.0 / 3.0) * kH, 0.35 * std::sqrt(2.0 / 3.0) * kH);
    } else {
      EXPECT_LT(r.sigma, 0.1 * kH);
    }
  }
}

TEST(SurfaceRoughness, RejectsABadRadiusAndReadsNothingOnAnEmptyMap) {
  SurfaceRoughnessOptions o;
  o.radius = 0;
  EXPECT_THROW((void)measure_surface_roughness(empty(10), o), Error);
  const SurfaceRoughness r = measure_surface_roughness(empty(10));
  EXPECT_EQ(r.windows, 0U);
  EXPECT_NEAR(r.floor, kH / std::sqrt(12.0), 1e-12);
}

}  // namespace
}  // namespace vdtnav
