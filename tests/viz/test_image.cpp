#include "vdtnav/viz/image.hpp"

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::viz {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Coverage of pixel (x, y) after drawing black on white: 0 white .. 1 black.
double ink(const RgbImage& img, int x, int y) { return 1.0 - img.at(x, y).r / 255.0; }

/// Brute-force distance from p to segment ab: minimum over 4001 points along the segment.
double sampled_distance(Point p, Point a, Point b) {
  double best = HUGE_VAL;
  for (int k = 0; k <= 4000; ++k) {
    const double t = k / 4000.0;
    best = std::min(best, std::hypot(p.x - (a.x + t * (b.x - a.x)), p.y - (a.y + t * (b.y - a.y))));
  }
  return best;
}

std::string tmp_path(const std::string& name) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  return std::string(VDTNAV_TEST_TMP) + "/" + name;
}

TEST(RgbImage, PngRoundTripsEveryByte) {
  RgbImage img(7, 5);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      img.set(x, y, {std::uint8_t(30 * x), std::uint8_t(50 * y), std::uint8_t(x * y + 1)});
    }
  }
  const std::string path = tmp_path("roundtrip.png");
  write_png(path, img);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 7);
  EXPECT_EQ(h, 5);
  EXPECT_EQ(channels, 3);
  EXPECT_TRUE(std::equal(img.rgb.begin(), img.rgb.end(), data));
  EXPECT_EQ(data[(3 * 7 + 2) * 3 + 1], 150);  // pixel (2, 3), green = 50 * 3
  stbi_image_free(data);
}

TEST(RgbImage, WritingIntoAMissingDirectoryThrowsIoErrorNamingThePath) {
  const std::string path = tmp_path("no/such/directory/figure.png");
  try {
    write_png(path, RgbImage(4, 4));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(RgbImage, BlendMixesLinearlyAndClipsOutside) {
  RgbImage img(2, 2, kWhite);
  img.blend(0, 0, kBlack, 0.5);
  img.blend(1, 0, {255, 0, 0}, 0.25);
  img.blend(-1, 0, kBlack, 1.0);  // outside: no-op, no crash
  img.set(5, 5, kBlack);
  EXPECT_EQ(img.at(0, 0), (Rgb{128, 128, 128}));  // 255 - 127.5 rounds to 128
  EXPECT_EQ(img.at(1, 0), (Rgb{255, 191, 191}));  // 255 - 0.25 * 255 = 191.25
  EXPECT_EQ(img.at(1, 1), kWhite);
}

TEST(DrawLine, CoversThePixelsWithinHalfTheWidthOfTheSegment) {
  struct Case {
    Point a, b;
    double width;
  };
  for (const Case& c : {Case{{3.2, 4.7}, {41.9, 22.3}, 1.0}, Case{{5.0, 40.0}, {30.5, 2.5}, 3.0},
                        Case{{10.5, 10.5}, {10.5, 35.5}, 2.0}, Case{{-10, 20}, {60, 26}, 5.0}}) {
    RgbImage img(48, 44, kWhite);
    draw_line(img, c.a, c.b, kBlack, c.width);
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        const double d = sampled_distance({x + 0.5, y + 0.5}, c.a, c.b);
        const double h = 0.5 * c.width;
        if (d <= h - 0.52) {
          EXPECT_EQ(img.at(x, y), kBlack) << x << "," << y << " d=" << d;
        }
        if (d >= h + 0.52) {
          EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y << " d=" << d;
        }
        if (d < h - 0.02) {
          EXPECT_GT(ink(img, x, y), 0.5) << x << "," << y << " d=" << d;
        }
        if (d > h + 0.02) {
          EXPECT_LT(ink(img, x, y), 0.5) << x << "," << y << " d=" << d;
        }
      }
    }
  }
}

TEST(DrawLine, ThinShallowLineInksEveryColumnItSpans) {
  RgbImage img(50, 30, kWhite);
  draw_line(img, {2.5, 3.5}, {45.5, 17.5}, kBlack, 1.0);
  for (int x = 3; x <= 45; ++x) {
    double best = 0.0;
    for (int y = 0; y < img.height; ++y) best = std::max(best, ink(img, x, y));
    EXPECT_GE(best, 0.5) << "column " << x;
  }
}

TEST(DrawPolyline, TranslucentJointsAreBlendedOnce) {
  RgbImage img(40, 40, kWhite);
  draw_polyline(img, {{5, 5}, {30, 5}, {30, 30}, {5, 5}}, kBlack, 4.0, 0.5);
  // The corner (30, 5) is covered by two segments; with one blend it is exactly half grey.
  EXPECT_EQ(img.at(30, 5), (Rgb{128, 128, 128}));
  EXPECT_EQ(img.at(17, 5), (Rgb{128, 128, 128}));
}

TEST(DrawPolyline, DashedLineAlternatesInkAndGaps) {
  RgbImage img(200, 10, kWhite);
  draw_polyline(img, {{0, 5}, {200, 5}}, kBlack, 2.0, 1.0, true);
  int transitions = 0;
  for (int x = 1; x < img.width; ++x) {
    transitions += (img.at(x, 5) == kWhite) != (img.at(x - 1, 5) == kWhite);
  }
  // dash 7 px + gap 8 px: about 13 periods, two transitions each.
  EXPECT_GE(transitions, 20);
  EXPECT_LE(transitions, 30);
}

TEST(FillCircle, CoverageMatchesTheDisc) {
  const Point c{20.3, 18.6};
  const double r = 9.4;
  RgbImage img(45, 40, kWhite);
  fill_circle(img, c, r, kBlack);
  double area = 0.0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double d = std::hypot(x + 0.5 - c.x, y + 0.5 - c.y);
      if (d <= r - 0.51) {
        EXPECT_EQ(img.at(x, y), kBlack);
      }
      if (d >= r + 0.51) {
        EXPECT_EQ(img.at(x, y), kWhite);
      }
      area += ink(img, x, y);
    }
  }
  EXPECT_NEAR(area, kPi * r * r, 0.01 * kPi * r * r);
}

TEST(FillPolygon, RectangleWithFractionalEdgesHasExactCoverage) {
  RgbImage img(16, 12, kWhite);
  fill_polygon(img, {{2.25, 3.0}, {10.75, 3.0}, {10.75, 8.0}, {2.25, 8.0}}, kBlack);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      double expected = 0.0;  // area of pixel [x, x+1) x [y, y+1) inside the rectangle
      const double w = std::max(0.0, std::min(x + 1.0, 10.75) - std::max(double(x), 2.25));
      const double h = std::max(0.0, std::min(y + 1.0, 8.0) - std::max(double(y), 3.0));
      expected = w * h;
      EXPECT_NEAR(ink(img, x, y), expected, 0.6 / 255.0 + 1e-9) << x << "," << y;
    }
  }
}

TEST(FillPolygon, TriangleAndBandAreasMatchGeometry) {
  RgbImage img(60, 60, kWhite);
  fill_polygon(img, {{5.3, 50.2}, {54.1, 47.9}, {21.7, 6.4}}, kBlack);
  double area = 0.0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) area += ink(img, x, y);
  }
  const double exact = 0.5 * std::abs((54.1 - 5.3) * (6.4 - 50.2) - (21.7 - 5.3) * (47.9 - 50.2));
  EXPECT_NEAR(area, exact, 0.01 * exact);
  // Even-odd: a square with a square hole leaves the hole white.
  RgbImage ring(30, 30, kWhite);
  fill_polygon(ring,
               {{2, 2},
                {28, 2},
                {28, 28},
                {2, 28},
                {2, 2},
                {10, 10},
                {10, 20},
                {20, 20},
                {20, 10},
                {10, 10}},
               kBlack);
  EXPECT_EQ(ring.at(15, 15), kWhite);
  EXPECT_EQ(ring.at(5, 15), kBlack);
}

TEST(DrawMarker, EveryShapeIsCentredAndWithinItsSize) {
  for (const Marker m :
       {Marker::kCircle, Marker::kSquare, Marker::kTriangle, Marker::kCross, Marker::kPlus}) {
    RgbImage img(41, 41, kWhite);
    const Point c{20.5, 20.5};
    const double size = 16.0;
    draw_marker(img, c, m, size, kBlack);
    double sum = 0.0, sx = 0.0, sy = 0.0;
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        const double k = ink(img, x, y);
        sum += k;
        sx += k * (x + 0.5);
        sy += k * (y + 0.5);
        if (k > 0.0) {
          EXPECT_LE(std::abs(x + 0.5 - c.x), 0.5 * size + 2.5);
          EXPECT_LE(std::abs(y + 0.5 - c.y), 0.5 * size + 2.5);
        }
      }
    }
    ASSERT_GT(sum, 10.0) << static_cast<int>(m);
    EXPECT_NEAR(sx / sum, c.x, 0.3) << static_cast<int>(m);
    EXPECT_NEAR(sy / sum, c.y, 0.3) << static_cast<int>(m);
  }
  RgbImage img(10, 10, kWhite);
  draw_marker(img, {5, 5}, Marker::kNone, 8.0, kBlack);
  EXPECT_TRUE(std::all_of(img.rgb.begin(), img.rgb.end(), [](auto v) { return v == 255; }));
}

TEST(DrawScaled, NearestNeighbourMapsQuadrants) {
  RgbImage src(2, 2);
  const Rgb tl{255, 0, 0}, tr{0, 255, 0}, bl{0, 0, 255}, br{10, 20, 30};
  src.set(0, 0, tl);
  src.set(1, 0, tr);
  src.set(0, 1, bl);
  src.set(1, 1, br);
  RgbImage dst(40, 40, kWhite);
  draw_scaled(dst, src, 10.0, 10.0, 30.0, 30.0);
  EXPECT_EQ(dst.at(10, 10), tl);
  EXPECT_EQ(dst.at(19, 19), tl);
  EXPECT_EQ(dst.at(20, 19), tr);
  EXPECT_EQ(dst.at(19, 20), bl);
  EXPECT_EQ(dst.at(29, 29), br);
  EXPECT_EQ(dst.at(30, 30), kWhite);
  EXPECT_EQ(dst.at(9, 15), kWhite);
}

TEST(Blit, CopiesWithClipping) {
  RgbImage src(3, 3, kBlack);
  RgbImage dst(4, 4, kWhite);
  blit(dst, src, 2, -1);
  EXPECT_EQ(dst.at(2, 0), kBlack);
  EXPECT_EQ(dst.at(3, 1), kBlack);
  EXPECT_EQ(dst.at(1, 1), kWhite);
  EXPECT_EQ(dst.at(2, 2), kWhite);
}

}  // namespace
}  // namespace vdtnav::viz
