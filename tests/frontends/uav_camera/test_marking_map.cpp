// Marking maps: boundaries of a hand-drawn grid against the hand count, a map_server PNG + YAML
// of runway paint loaded into a VDT map, and the edge grid of an orthophoto.
#include "vdtnav/uav_camera/marking_map.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../../io/test_files.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

/// A grid from rows of '#' (occupied) and '.', the first string the top row (max y).
OccupancyGrid<2> grid_of(const std::vector<std::string>& rows) {
  const int ny = static_cast<int>(rows.size());
  const int nx = static_cast<int>(rows[0].size());
  OccupancyGrid<2> g(Eigen::Vector2i(nx, ny), GridFrame<2>(0.5, Eigen::Vector2d(1.0, 2.0)), 0);
  for (int r = 0; r < ny; ++r) {
    for (int x = 0; x < nx; ++x) {
      g(Eigen::Vector2i(x, ny - 1 - r)) = rows[static_cast<std::size_t>(r)][x] == '#' ? 1 : 0;
    }
  }
  return g;
}

TEST(MarkingBoundaries, MatchesTheHandCount) {
  // A 3x3 block (its centre is interior) and a 2-wide stripe running off the map on three
  // sides: only its left column faces free ground; the map border is not a boundary.
  const OccupancyGrid<2> markings = grid_of({
      ".....##",
      ".###.##",
      ".###.##",
      ".###.##",
      ".....##",
  });
  const OccupancyGrid<2> want = grid_of({
      ".....#.",
      ".###.#.",
      ".#.#.#.",
      ".###.#.",
      ".....#.",
  });
  const OccupancyGrid<2> got = marking_boundaries(markings);
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(got.frame().origin(), markings.frame().origin());
  EXPECT_EQ(got.resolution(), 0.5);
  int count = 0;
  for (std::size_t i = 0; i < got.num_cells(); ++i) {
    EXPECT_EQ(got[i], want[i]) << "cell "
                               << got.index_of(static_cast<std::ptrdiff_t>(i)).transpose();
    count += got[i];
  }
  EXPECT_EQ(count, 13);
}

/// Runway paint: a dark image with one white bar at columns 20..29, rows 10..14.
cv::Mat paint_image() {
  cv::Mat img(40, 60, CV_8U, cv::Scalar(30));
  img(cv::Range(10, 15), cv::Range(20, 30)).setTo(240);
  return img;
}

void write_map(const std::string& dir, const cv::Mat& img, int negate) {
  ASSERT_TRUE(cv::imwrite(dir + "/paint.png", img));
  test::write_file(dir + "/paint.yaml",
                   "image: paint.png\nresolution: 0.1\norigin: [-2.0, -1.0, 0.0]\n"
                   "negate: " +
                       std::to_string(negate) + "\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
}

TEST(LoadMarkingMap, WhitePaintWithNegateIsTheMarking) {
  const std::string dir = test::tmp_dir("uav_camera");
  write_map(dir, paint_image(), 1);
  const VdtMap2 map = load_marking_map(dir + "/paint.yaml");
  EXPECT_NEAR(map.frame().resolution(), 0.1, 1e-12);
  EXPECT_LT((map.frame().origin() - Eigen::Vector2d(-2.0, -1.0)).norm(), 1e-12);
  // Bar: cells i = 20..29, j = 39 - 14 .. 39 - 10 = 25..29. Cell (10, 27) is 10 cells left of
  // the bar's left boundary cell (20, 27): DT_v = p - c = (-1.0, 0).
  const Eigen::Vector2d p(-2.0 + 10.5 * 0.1, -1.0 + 27.5 * 0.1);
  const auto s = map.evaluate(p);
  EXPECT_NEAR(s.value.x(), -1.0, 0.02);
  EXPECT_NEAR(s.value.y(), 0.0, 0.02);
  // Above the bar (row 2 -> j = 37), over column 25: nearest is the top boundary cell (25, 29).
  const auto a = map.evaluate({-2.0 + 25.5 * 0.1, -1.0 + 37.5 * 0.1});
  EXPECT_NEAR(a.value.x(), 0.0, 0.02);
  EXPECT_NEAR(a.value.y(), 0.8, 0.02);
}

TEST(LoadMarkingMap, NoMarkingIsAClearError) {
  const std::string dir = test::tmp_dir("uav_camera");
  write_map(dir, cv::Mat(40, 60, CV_8U, cv::Scalar(30)), 1);  // dark tarmac only
  try {
    (void)load_marking_map(dir + "/paint.yaml");
    FAIL() << "no error";
  } catch (const FormatError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir + "/paint.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no ground marking"), std::string::npos) << msg;
  }
  EXPECT_THROW((void)load_marking_map(dir + "/missing.yaml"), IoError);
}

TEST(EdgeGrid, PhotoRowsAreFlippedOntoTheGround) {
  // Rows 5..9 of a 30-row photo: cells j = 29 - 9 .. 29 - 5 = 20..24 (the top half of the
  // ground); its edges must lie within a cell of that band's outline and nowhere else.
  cv::Mat photo(30, 40, CV_8U, cv::Scalar(60));
  photo(cv::Range(5, 10), cv::Range(10, 30)).setTo(200);
  const OccupancyGrid<2> g = edge_grid(photo, 0.05, Eigen::Vector2d(3.0, 4.0));
  EXPECT_EQ(g.size(), Eigen::Vector2i(40, 30));
  EXPECT_EQ(g.resolution(), 0.05);
  EXPECT_EQ(g.frame().origin(), Eigen::Vector2d(3.0, 4.0));
  int n = 0;
  for (std::size_t i = 0; i < g.num_cells(); ++i) {
    if (g[i] == 0) continue;
    ++n;
    const Eigen::Vector2i c = g.index_of(static_cast<std::ptrdiff_t>(i));
    EXPECT_TRUE(c.x() >= 9 && c.x() <= 30 && c.y() >= 19 && c.y() <= 25) << c.transpose();
  }
  EXPECT_GT(n, 40);
}

}  // namespace
}  // namespace vdtnav::uav_camera
