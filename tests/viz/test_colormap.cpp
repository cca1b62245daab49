#include "vdtnav/viz/colormap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace vdtnav::viz {
namespace {

/// Rec. 709 luma of the sRGB values: a proxy for perceived lightness.
double luma(Rgb c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

int max_channel_step(Rgb a, Rgb b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

TEST(Colormap, EndpointsAndClamping) {
  EXPECT_EQ(colormap(Colormap::kViridis, 0.0), (Rgb{68, 1, 84}));     // #440154
  EXPECT_EQ(colormap(Colormap::kViridis, 1.0), (Rgb{253, 231, 37}));  // #fde725
  EXPECT_EQ(colormap(Colormap::kViridis, 0.5), (Rgb{33, 145, 140}));  // #21918c
  EXPECT_EQ(colormap(Colormap::kViridis, -3.0), colormap(Colormap::kViridis, 0.0));
  EXPECT_EQ(colormap(Colormap::kViridis, 7.0), colormap(Colormap::kViridis, 1.0));
  EXPECT_EQ(colormap(Colormap::kGray, 0.0), kBlack);
  EXPECT_EQ(colormap(Colormap::kGray, 1.0), kWhite);
  EXPECT_EQ(colormap(Colormap::kGray, 0.5), (Rgb{128, 128, 128}));
  EXPECT_EQ(colormap(Colormap::kBlueWhiteRed, 0.5), kWhite);
  const Rgb blue = colormap(Colormap::kBlueWhiteRed, 0.0),
            red = colormap(Colormap::kBlueWhiteRed, 1.0);
  EXPECT_GT(blue.b, 2 * blue.r);
  EXPECT_GT(red.r, 2 * red.b);
  EXPECT_EQ(colormap(Colormap::kViridis, std::nan("")), kNanColor);
}

TEST(Colormap, ContinuousAndLightnessOrdered) {
  for (const Colormap map : {Colormap::kViridis, Colormap::kBlueWhiteRed, Colormap::kGray}) {
    for (int k = 1; k <= 1000; ++k) {
      const Rgb a = colormap(map, (k - 1) / 1000.0), b = colormap(map, k / 1000.0);
      EXPECT_LE(max_channel_step(a, b), 3) << "t = " << k / 1000.0;
      if (map != Colormap::kGray) {
        EXPECT_NE(a, kNanColor);
      }
      if (map == Colormap::kViridis || map == Colormap::kGray) {
        EXPECT_GE(luma(b), luma(a) - 0.5) << "lightness must not decrease, t = " << k / 1000.0;
      }
    }
  }
  // The diverging map is lightest at the centre and about equally dark at +-v.
  for (int k = 0; k < 100; ++k) {
    const double t = k / 200.0;
    const double lo = luma(colormap(Colormap::kBlueWhiteRed, t));
    const double hi = luma(colormap(Colormap::kBlueWhiteRed, 1.0 - t));
    EXPECT_NEAR(lo, hi, 20.0) << "t = " << t;
    EXPECT_LE(lo, luma(colormap(Colormap::kBlueWhiteRed, t + 0.005)) + 0.5);
  }
}

Grid<float, 2> ramp_field() {
  // value = x + 10 y on a 4 x 3 grid: 0 at cell (0, 0), 23 at cell (3, 2).
  Grid<float, 2> g(Eigen::Vector2i(4, 3), GridFrame<2>(0.5, Eigen::Vector2d(1.0, 2.0)));
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) g(Eigen::Vector2i(x, y)) = static_cast<float>(x + 10 * y);
  }
  return g;
}

TEST(Heatmap, LowIsFirstColourHighIsLastAndRowZeroIsAtTheBottom) {
  const Grid<float, 2> g = ramp_field();
  const RgbImage img = heatmap(g, Colormap::kViridis, 0.0, 23.0);
  ASSERT_EQ(img.width, 4);
  ASSERT_EQ(img.height, 3);
  EXPECT_EQ(img.at(0, 2), colormap(Colormap::kViridis, 0.0));  // cell (0, 0): bottom left
  EXPECT_EQ(img.at(3, 0), colormap(Colormap::kViridis, 1.0));  // cell (3, 2): top right
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 4; ++x) {
      EXPECT_EQ(img.at(x, 2 - y), colormap(Colormap::kViridis, (x + 10.0 * y) / 23.0));
    }
  }
  // Values beyond [lo, hi] saturate.
  const RgbImage narrow = heatmap(g, Colormap::kGray, 5.0, 10.0);
  EXPECT_EQ(narrow.at(0, 2), kBlack);
  EXPECT_EQ(narrow.at(3, 0), kWhite);
}

TEST(Heatmap, NonFiniteCellsGetTheNanColour) {
  Grid<float, 2> g = ramp_field();
  g(Eigen::Vector2i(1, 0)) = std::numeric_limits<float>::quiet_NaN();
  g(Eigen::Vector2i(2, 1)) = std::numeric_limits<float>::infinity();
  g(Eigen::Vector2i(3, 1)) = -std::numeric_limits<float>::infinity();
  const RgbImage img = heatmap(g, Colormap::kBlueWhiteRed, -23.0, 23.0);
  EXPECT_EQ(img.at(1, 2), kNanColor);
  EXPECT_EQ(img.at(2, 1), kNanColor);
  EXPECT_EQ(img.at(3, 1), kNanColor);
  EXPECT_EQ(img.at(0, 2), kWhite);  // 0 is the centre of a symmetric diverging range
  EXPECT_EQ(heatmap(g, Colormap::kGray, 0, 23, {255, 0, 0}).at(1, 2), (Rgb{255, 0, 0}));
  const auto [lo, hi] = finite_range(g);
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 23.0);
}

TEST(OccupancyImage, OccupiedBlackFreeWhiteWorldYUp) {
  Grid<std::uint8_t, 2> occ(Eigen::Vector2i(3, 2), GridFrame<2>(0.1, Eigen::Vector2d::Zero()));
  occ(Eigen::Vector2i(0, 0)) = 1;
  occ(Eigen::Vector2i(2, 1)) = 255;
  const RgbImage img = occupancy_image(occ);
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.at(0, 1), kBlack);
  EXPECT_EQ(img.at(2, 0), kBlack);
  EXPECT_EQ(img.at(0, 0), kWhite);
  EXPECT_EQ(img.at(1, 1), kWhite);
}

TEST(OccupancyImage, RosCellsAsMapServerDrawsThem) {
  // -1 unknown grey 205; 0..100 from white to black, 255 - 2.55 v; above 100 black; world y up.
  Grid<std::int8_t, 2> cells(Eigen::Vector2i(4, 2), GridFrame<2>(0.05, Eigen::Vector2d::Zero()));
  cells(Eigen::Vector2i(0, 0)) = -1;
  cells(Eigen::Vector2i(1, 0)) = 0;
  cells(Eigen::Vector2i(2, 0)) = 100;
  cells(Eigen::Vector2i(3, 0)) = 50;
  cells(Eigen::Vector2i(0, 1)) = 127;
  const RgbImage img = occupancy_image(cells);
  ASSERT_EQ(img.width, 4);
  ASSERT_EQ(img.height, 2);
  EXPECT_EQ(img.at(0, 1), (Rgb{205, 205, 205}));  // row y = 0 at the bottom
  EXPECT_EQ(img.at(1, 1), kWhite);
  EXPECT_EQ(img.at(2, 1), kBlack);
  EXPECT_EQ(img.at(3, 1), (Rgb{127, 127, 127}));  // 255 - 127.5, truncated
  EXPECT_EQ(img.at(0, 0), kBlack);
}

}  // namespace
}  // namespace vdtnav::viz
