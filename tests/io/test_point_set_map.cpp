#include "vdtnav/io/point_set_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

std::string tmp_path(const std::string& name) {
  // The running test's own folder: ctest runs this file's tests in parallel.
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string own = std::string(test->test_suite_name()) + "." + test->name();
  for (char& c : own) c = c == '/' ? '_' : c;
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "point_set_map" / own;
  fs::create_directories(dir);
  return (dir / name).string();
}

template <typename T>
class PointSetMap : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(PointSetMap, Dims);

template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.7, 2.9);
  std::vector<Eigen::Matrix<double, Dim, 1>> pts(static_cast<std::size_t>(n));
  for (auto& p : pts)
    for (int d = 0; d < Dim; ++d) p[d] = u(rng) * (d + 1);
  return pts;
}

TYPED_TEST(PointSetMap, OccupiedCellsAreExactlyThoseContainingAPoint) {
  constexpr int Dim = TypeParam::value;
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Index = typename SpaceTraits<Dim>::Index;
  const double res = 0.25, margin = 0.6;
  const auto pts = random_points<Dim>(150, 11);
  std::size_t dropped = 99;
  const OccupancyGrid<Dim> g = occupancy_from_points<Dim>(pts, res, margin, &dropped);
  EXPECT_EQ(dropped, 0U);

  Vector lo = pts[0], hi = pts[0];
  for (const Vector& p : pts) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vector origin = g.frame().origin();
  for (int d = 0; d < Dim; ++d) {
    // Origin on the resolution lattice, the grid covers the box plus margin with < 1 cell spare.
    EXPECT_NEAR(origin[d] / res, std::round(origin[d] / res), 1e-9);
    EXPECT_LE(origin[d], lo[d] - margin + 1e-12);
    EXPECT_GT(origin[d], lo[d] - margin - res);
    const double top = origin[d] + g.size()[d] * res;
    EXPECT_GE(top, hi[d] + margin - 1e-12);
    EXPECT_LT(top, hi[d] + margin + res + 1e-12);
  }
  // Brute force: cell i is occupied iff some point lies in [origin + i res, origin + (i+1) res).
  std::size_t occupied = 0;
  for (std::size_t c = 0; c < g.num_cells(); ++c) {
    const Index i = g.index_of(static_cast<std::ptrdiff_t>(c));
    const Vector cell_lo = origin + i.template cast<double>() * res;
    bool any = false;
    for (const Vector& p : pts) {
      any = any || (((p - cell_lo).array() >= 0.0).all() && ((p - cell_lo).array() < res).all());
    }
    ASSERT_EQ(g[c], any ? 1 : 0) << "cell " << i.transpose();
    occupied += any ? 1 : 0;
  }
  EXPECT_GT(occupied, 100U);  // 150 random points rarely share cells
}

TYPED_TEST(PointSetMap, NonFinitePointsAreDroppedAndCounted) {
  constexpr int Dim = TypeParam::value;
  using Vector = Eigen::Matrix<double, Dim, 1>;
  auto pts = random_points<Dim>(40, 5);
  const OccupancyGrid<Dim> clean = occupancy_from_points<Dim>(pts, 0.1, 0.2);
  Vector nan_point = pts[0], inf_point = pts[1];
  nan_point[0] = std::numeric_limits<double>::quiet_NaN();
  inf_point[Dim - 1] = -std::numeric_limits<double>::infinity();
  pts.insert(pts.begin() + 7, nan_point);
  pts.push_back(inf_point);
  std::size_t dropped = 0;
  const OccupancyGrid<Dim> g = occupancy_from_points<Dim>(pts, 0.1, 0.2, &dropped);
  EXPECT_EQ(dropped, 2U);
  EXPECT_EQ(g.size(), clean.size());
  EXPECT_EQ(g.frame().origin(), clean.frame().origin());
  EXPECT_EQ(g.values(), clean.values());
}

TYPED_TEST(PointSetMap, BadInputIsAConfigError) {
  constexpr int Dim = TypeParam::value;
  using Vector = Eigen::Matrix<double, Dim, 1>;
  const std::vector<Vector> none;
  EXPECT_THROW((void)occupancy_from_points<Dim>(none, 0.1, 0.0), ConfigError);
  const std::vector<Vector> all_nan(3, Vector::Constant(std::nan("")));
  std::size_t dropped = 0;
  EXPECT_THROW((void)occupancy_from_points<Dim>(all_nan, 0.1, 0.0, &dropped), ConfigError);
  EXPECT_EQ(dropped, 3U);
  const std::vector<Vector> one(1, Vector::Zero());
  EXPECT_THROW((void)occupancy_from_points<Dim>(one, 0.0, 0.0), ConfigError);
  EXPECT_THROW((void)occupancy_from_points<Dim>(one, 0.1, -1.0), ConfigError);
  EXPECT_THROW((void)occupancy_from_points<Dim>(one, 1e-9, 10.0), ConfigError);  // too many cells
}

TEST(PointSetMap, KnownPointsGiveKnownCells) {
  // Points at x in {0.05, 0.35}, y = 0.15 with resolution 0.1 and margin 0.1: origin (-0.1, 0.0)
  // after snapping (0.05 - 0.1 = -0.05 -> -0.1; 0.15 - 0.1 = 0.05 -> 0.0).
  const std::vector<Eigen::Vector2d> pts = {{0.05, 0.15}, {0.35, 0.15}};
  const OccupancyGrid<2> g = occupancy_from_points<2>(pts, 0.1, 0.1);
  EXPECT_NEAR(g.frame().origin().x(), -0.1, 1e-12);
  EXPECT_NEAR(g.frame().origin().y(), 0.0, 1e-12);
  EXPECT_EQ(g.size(), Eigen::Vector2i(6, 3));  // x: [-0.1, 0.5), y: [0, 0.3)
  std::vector<std::uint8_t> expected(18, 0);
  expected[1 + 6 * 1] = 1;  // (0.05, 0.15) -> cell (1, 1)
  expected[4 + 6 * 1] = 1;  // (0.35, 0.15) -> cell (4, 1)
  EXPECT_EQ(g.values(), expected);
}

TEST(PointSetCsv, ReadsHeaderCommentsBlankLinesAndCrLf) {
  const std::string path = tmp_path("points.csv");
  std::ofstream(path) << "# surveyed walls\r\n x , y \r\n1.5,-2\r\n\r\n  3e-1 , 4 # a comment\n"
                         "nan,1\n-0.25,7.5\n";
  const auto pts = read_point_set_csv<2>(path);
  ASSERT_EQ(pts.size(), 4U);
  EXPECT_EQ(pts[0], Eigen::Vector2d(1.5, -2.0));
  EXPECT_EQ(pts[1], Eigen::Vector2d(0.3, 4.0));
  EXPECT_TRUE(std::isnan(pts[2].x()));
  EXPECT_EQ(pts[3], Eigen::Vector2d(-0.25, 7.5));
}

TEST(PointSetCsv, MissingFileIsAnIoError) {
  EXPECT_THROW((void)read_point_set_csv<3>(tmp_path("nope.csv")), IoError);
}

TEST(PointSetCsv, MalformedLinesNameFileAndLine) {
  struct Case {
    const char* name;
    const char* text;
    std::size_t line;
  };
  const Case cases[] = {
      {"word", "x,y,z\n1,2,3\n1,two,3\n", 3}, {"too_few", "1,2,3\n1,2\n", 2},
      {"too_many", "# c\n1,2,3,4\n", 2},      {"trailing_comma", "1,2,3,\n", 1},
      {"second_header", "x,y,z\nx,y,z\n", 2},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = tmp_path(std::string(c.name) + ".csv");
    std::ofstream(path) << c.text;
    try {
      (void)read_point_set_csv<3>(path);
      ADD_FAILURE() << "no error";
    } catch (const FormatError& e) {
      EXPECT_EQ(e.line(), c.line);
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path + ":" + std::to_string(c.line) + ": expected 3 comma-separated"),
                std::string::npos)
          << msg;
    }
  }
}

}  // namespace
}  // namespace vdtnav
