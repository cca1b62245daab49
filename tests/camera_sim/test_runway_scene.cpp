// Tests of the simulated runway: the figure-of-eight geometry, the texture against the marking
// map built from the same geometry, and the map_server files the localizer reads.

#include "vdtnav/camera_sim/runway_scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/ros_map.hpp"

namespace vdtnav::uav_camera {
namespace {

RunwaySceneOptions small_margin_options() {
  RunwaySceneOptions o;
  o.grass_margin = 4.0;  // keeps the texture small; the geometry is the default one
  return o;
}

const RunwayScene& scene() {
  static const RunwayScene s = make_runway_scene(small_margin_options());
  return s;
}

TEST(RunwayScene, CentrelineIsAClosedFigureEightOnTheRunway) {
  const RunwaySceneOptions o = small_margin_options();
  const auto& c = scene().centreline;
  ASSERT_GT(c.size(), 1000u);
  // Every road point, with the painted lines either side, lies on the asphalt.
  const double reach = 0.5 * o.lane_width + 0.5 * o.line_width;
  for (const auto& p : c) {
    EXPECT_LE(std::abs(p.x()) + reach, 0.5 * o.runway_length);
    EXPECT_LE(std::abs(p.y()) + reach, 0.5 * o.runway_width);
  }
  // Closed, evenly spaced.
  double length = 0.0, turning = 0.0, abs_turning = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Eigen::Vector2d a = c[(k + 1) % c.size()] - c[k];
    const Eigen::Vector2d b = c[(k + 2) % c.size()] - c[(k + 1) % c.size()];
    EXPECT_NEAR(a.norm(), o.centreline_spacing, 0.01 * o.centreline_spacing);
    length += a.norm();
    const double d = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    turning += d;
    abs_turning += std::abs(d);
  }
  // A figure of eight: one loop clockwise, one counter-clockwise, so the total turning is zero
  // (a simple loop turns 2 pi), while each loop turns pi + 2 alpha.
  const double alpha = std::asin(o.loop_radius / (0.5 * o.loop_separation));
  EXPECT_NEAR(turning, 0.0, 1e-6);
  EXPECT_NEAR(abs_turning, 2.0 * (kPi + 2.0 * alpha), 1e-3);
  const double legs = 4.0 * 0.5 * o.loop_separation * std::cos(alpha);
  EXPECT_NEAR(length, legs + 2.0 * o.loop_radius * (kPi + 2.0 * alpha), 1e-3);
  // Loop diameters (outer edge) within 25-30 m.
  EXPECT_GE(2.0 * (o.loop_radius + reach), 25.0);
  EXPECT_LE(2.0 * (o.loop_radius + reach), 30.0);
}

TEST(RunwayScene, TextureFollowsTheMapServerConvention) {
  const GroundTexture& t = scene().texture;
  ASSERT_EQ(t.image.type(), CV_8UC1);
  // Pixel (0, rows - 1) is the lower-left one; row 0 is the top.
  const Eigen::Vector2d ll = t.pixel_center(0, t.image.rows - 1);
  EXPECT_NEAR(ll.x(), t.origin.x() + 0.5 * t.resolution, 1e-9);
  EXPECT_NEAR(ll.y(), t.origin.y() + 0.5 * t.resolution, 1e-9);
  const Eigen::Vector2d ul = t.pixel_center(0, 0);
  EXPECT_NEAR(ul.y(), t.origin.y() + (t.image.rows - 0.5) * t.resolution, 1e-9);
  // sample() at a pixel centre is that pixel; outside the image it is the background.
  for (const auto& [c, r] : {std::pair{17, 31}, std::pair{t.image.cols - 3, 5}}) {
    EXPECT_NEAR(t.sample(t.pixel_center(c, r)), t.image.at<std::uint8_t>(r, c), 1e-6);
  }
  EXPECT_EQ(t.sample(t.origin - Eigen::Vector2d(1.0, 1.0)), t.background);
  // The right loop's outer edge line at (c + R + lane/2, 0) is white; inside the lane, asphalt.
  const RunwaySceneOptions o = small_margin_options();
  const double x_line = 0.5 * o.loop_separation + o.loop_radius + 0.5 * o.lane_width;
  EXPECT_GT(t.sample({x_line, 0.0}), 180.0);
  EXPECT_LT(t.sample({x_line - 0.5, 0.0}), 120.0);
  // Grass (outside) is brighter than asphalt on average: the border is a strong edge.
  const double grass = t.sample({0.0, 0.5 * o.runway_width + 2.0});
  const double asphalt = t.sample({0.0, 0.5 * o.runway_width - 0.5});
  EXPECT_GT(grass - asphalt, 15.0);
}

TEST(RunwayScene, GrassAndAsphaltHaveOnlyWeakEdgesComparedWithPaint) {
  const GroundTexture& t = scene().texture;
  cv::Mat blurred, gx, gy, mag;
  cv::GaussianBlur(t.image, blurred, cv::Size(5, 5), 1.0);
  cv::Sobel(blurred, gx, CV_32F, 1, 0);
  cv::Sobel(blurred, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, mag);
  const auto patch_p99 = [&](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    const int c0 = static_cast<int>((lo.x() - t.origin.x()) / t.resolution);
    const int c1 = static_cast<int>((hi.x() - t.origin.x()) / t.resolution);
    const int r1 = t.image.rows - static_cast<int>((lo.y() - t.origin.y()) / t.resolution);
    const int r0 = t.image.rows - static_cast<int>((hi.y() - t.origin.y()) / t.resolution);
    std::vector<float> v;
    for (int r = r0; r < r1; ++r) {
      for (int c = c0; c < c1; ++c) v.push_back(mag.at<float>(r, c));
    }
    std::nth_element(v.begin(), v.begin() + v.size() * 99 / 100, v.end());
    return v[v.size() * 99 / 100];
  };
  const float grass = patch_p99({-10.0, 15.5}, {10.0, 18.5});
  const float asphalt = patch_p99({-3.0, -14.0}, {3.0, -11.0});  // between road and border
  const float paint = patch_p99({33.0, -1.0}, {34.0, 1.0});      // across an edge line
  EXPECT_LT(grass, 0.25f * paint);
  EXPECT_LT(asphalt, 0.25f * paint);
}

TEST(RunwayScene, MarkingMapAgreesWithTheTexture) {
  const RunwayScene& s = scene();
  const OccupancyGrid<2>& m = s.markings;
  EXPECT_DOUBLE_EQ(m.resolution(), small_margin_options().map_resolution);
  std::size_t tp = 0, fp = 0, fn = 0, marked = 0;
  for (int j = 0; j < m.size().y(); ++j) {
    for (int i = 0; i < m.size().x(); ++i) {
      const Eigen::Vector2d p = m.cell_center({i, j});
      marked += m({i, j}) != 0;
      // Away from the border (which is a map line but grass/asphalt in the texture).
      if (std::abs(p.x()) > 49.7 || std::abs(p.y()) > 14.7) continue;
      const bool white = s.texture.sample(p) > 145.0;  // halfway between asphalt and paint
      const bool mark = m({i, j}) != 0;
      tp += white && mark;
      fp += !white && mark;
      fn += white && !mark;
    }
  }
  ASSERT_GT(tp, 10000u);  // ~170 m of road, 2.5 painted lines 0.15 m wide, 0.05 m cells
  EXPECT_GT(static_cast<double>(tp) / (tp + fp), 0.95);
  EXPECT_GT(static_cast<double>(tp) / (tp + fn), 0.95);
  EXPECT_LT(marked, m.num_cells() / 5);  // markings are lines, not areas
}

TEST(RunwayScene, RunwayBorderIsATwoCellLineInTheMap) {
  const OccupancyGrid<2>& m = scene().markings;
  // Along a column through (7.3, y): exactly the cells within 0.05 m of y = +-15 are marked
  // outside the road.
  for (const double y_border : {15.0, -15.0}) {
    int count = 0;
    for (int k = -10; k < 10; ++k) {
      const double y = y_border + 0.025 + 0.05 * k;  // cell centres (the map origin is -17)
      const Eigen::Vector2i c = m.cell_of({7.3, y});
      ASSERT_TRUE(m.contains(c));
      if (m(c) != 0) {
        EXPECT_NEAR(m.cell_center(c).y(), y_border, 0.05 + 1e-9);
        ++count;
      }
    }
    EXPECT_EQ(count, 2);
  }
  const Eigen::Vector2i end = m.cell_of({50.0 - 0.01, 3.3});
  EXPECT_EQ(m(end), 1);
  EXPECT_EQ(m(m.cell_of({50.0 + 0.6, 3.3})), 0);
  EXPECT_EQ(m(m.cell_of({0.0, 15.6})), 0);
}

TEST(RunwayScene, SameSeedSameSceneOtherSeedOtherTextureSameMap) {
  RunwaySceneOptions o = small_margin_options();
  o.resolution = 0.05;  // faster
  o.grass_margin = 1.0;
  const RunwayScene a = make_runway_scene(o);
  const RunwayScene b = make_runway_scene(o);
  o.seed = 2;
  const RunwayScene c = make_runway_scene(o);
  EXPECT_EQ(cv::norm(a.texture.image, b.texture.image, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.texture.image, c.texture.image, cv::NORM_L1), 1e5);
  EXPECT_EQ(a.markings.values(), c.markings.values());
}

TEST(RunwayScene, RejectsBadOptions) {
  RunwaySceneOptions o;
  o.loop_radius = 16.0;  // the loops would not fit across a 30 m runway
  EXPECT_THROW((void)make_runway_scene(o), ConfigError);
  o = RunwaySceneOptions{};
  o.loop_separation = 20.0;  // < 2 R: the legs cannot be tangent to both loops
  EXPECT_THROW((void)make_runway_scene(o), ConfigError);
  o = RunwaySceneOptions{};
  o.resolution = 0.0;
  EXPECT_THROW((void)make_runway_scene(o), ConfigError);
}

TEST(RunwayScene, SavedMarkingMapReadsBackThroughMapServer) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  const std::string prefix = std::string(VDTNAV_TEST_TMP) + "/runway_markings";
  const RunwayScene& s = scene();
  save_marking_map(prefix, s);
  const RosMap map = load_ros_map(prefix + ".yaml");
  const OccupancyGrid<2> back = occupancy(map);
  ASSERT_EQ(back.size(), s.markings.size());
  EXPECT_DOUBLE_EQ(back.resolution(), s.markings.resolution());
  EXPECT_NEAR((back.frame().origin() - s.markings.frame().origin()).norm(), 0.0, 1e-12);
  EXPECT_EQ(back.values(), s.markings.values());
  // The image itself: row 0 is the top (largest y), markings black.
  const cv::Mat png = cv::imread(prefix + ".png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(png.type(), CV_8UC1);
  const Eigen::Vector2i top_border = s.markings.cell_of({7.3, 15.01});
  EXPECT_EQ(png.at<std::uint8_t>(png.rows - 1 - top_border.y(), top_border.x()), 0);
  EXPECT_EQ(png.at<std::uint8_t>(png.rows - 1 - top_border.y() - 8, top_border.x()), 255);
}

TEST(RunwayScene, PhotographTextureLaysTheAerialPhotoOnTheGround) {
  const std::string path = std::string(VDTNAV_DATA_DIR) + "/vision/aerial/aero1.jpg";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "real data absent: " << path;
  const cv::Mat photo = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_EQ(photo.cols, 640);
  const GroundTexture t = photograph_texture(photo, 0.1, {-32.0, -24.0});
  cv::Mat grey;
  cv::cvtColor(photo, grey, cv::COLOR_BGR2GRAY);
  for (const auto& [c, r] : {std::pair{0, 479}, std::pair{320, 0}, std::pair{611, 123}}) {
    EXPECT_NEAR(t.sample(t.pixel_center(c, r)), grey.at<std::uint8_t>(r, c), 0.6);
  }
  // Lower-left corner at the origin, 64 m x 48 m.
  EXPECT_TRUE(t.contains({-31.99, -23.99}));
  EXPECT_FALSE(t.contains({32.01, 0.0}));
  EXPECT_NEAR(t.sample({100.0, 0.0}), t.background, 1e-12);
  EXPECT_THROW((void)photograph_texture(cv::Mat(), 0.1, {0.0, 0.0}), ConfigError);
}

}  // namespace
}  // namespace vdtnav::uav_camera
