#include "vdtnav/viz/image.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
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

double total_ink(const RgbImage& img) {
  double sum = 0.0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) sum += ink(img, x, y);
  }
  return sum;
}

std::string tmp_path(const std::string& name) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  return std::string(VDTNAV_TEST_TMP) + "/" + name;
}

TEST(WritePng, DecodesToTheSamePixelsWhateverTheFileName) {
  RgbImage img(7, 5);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      img.set(x, y, {std::uint8_t(30 * x), std::uint8_t(50 * y), std::uint8_t(x * y + 1)});
    }
  }
  for (const std::string name : {"roundtrip.png", "roundtrip.figure"}) {
    const std::string path = tmp_path(name);
    write_png(path, img);
    std::ifstream in(path, std::ios::binary);
    char sig[8] = {};
    in.read(sig, 8);
    EXPECT_EQ(std::string(sig, 8), "\x89PNG\r\n\x1a\n") << name;
    const cv::Mat png = cv::imread(path, cv::IMREAD_UNCHANGED);  // b g r
    ASSERT_EQ(png.type(), CV_8UC3) << name;
    ASSERT_EQ(png.cols, 7);
    ASSERT_EQ(png.rows, 5);
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        const cv::Vec3b v = png.at<cv::Vec3b>(y, x);
        EXPECT_EQ((Rgb{v[2], v[1], v[0]}), img.at(x, y)) << x << "," << y;
      }
    }
  }
}

TEST(WritePng, IntoAMissingDirectoryThrowsIoErrorNamingThePath) {
  const std::string path = tmp_path("no/such/directory/figure.png");
  try {
    write_png(path, RgbImage(4, 4));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_png(tmp_path("empty.png"), RgbImage()), ConfigError);
}

TEST(FillRect, BlendsWithAlphaAndClipsToTheImage) {
  RgbImage img(6, 4, kWhite);
  fill_rect(img, {-2, -2, 4, 4}, kBlack, 0.5);        // covers (0..1, 0..1)
  fill_rect(img, {4, 2, 10, 10}, {255, 0, 0}, 0.25);  // covers (4..5, 2..3)
  EXPECT_EQ(img.at(0, 0), (Rgb{128, 128, 128}));      // 255 - 127.5, rounded
  EXPECT_EQ(img.at(1, 1), (Rgb{128, 128, 128}));
  EXPECT_EQ(img.at(2, 0), kWhite);
  EXPECT_EQ(img.at(5, 3), (Rgb{255, 191, 191}));  // 255 - 0.25 * 255 = 191.25
  EXPECT_EQ(img.at(3, 3), kWhite);
  draw_rect(img, {1, 1, 4, 3}, kBlack);  // outline inside the rectangle, one pixel
  EXPECT_EQ(img.at(1, 1), kBlack);
  EXPECT_EQ(img.at(4, 3), kBlack);
  EXPECT_EQ(img.at(2, 2), kWhite);
}

TEST(DrawLine, InksThePixelsOnTheSegmentAndLeavesFarOnesUntouched) {
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
        if (d <= 0.25) {
          EXPECT_GT(ink(img, x, y), 0.5) << x << "," << y << " d=" << d << " w=" << c.width;
        }
        if (d >= 0.5 * c.width + 1.0) {
          EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y << " d=" << d << " w=" << c.width;
        }
      }
    }
    // Ink per unit length is the width (round caps add pi w^2 / 4 where the ends are visible).
    const double length = std::hypot(c.b.x - c.a.x, c.b.y - c.a.y);
    const bool clipped = c.a.x < 0;
    const double visible = clipped ? 48.0 * length / (c.b.x - c.a.x) : length;
    const double caps = clipped ? 0.0 : kPi * c.width * c.width / 4;
    // OpenCV fills the fine pixels on the outline too: up to about a quarter pixel wider.
    EXPECT_NEAR((total_ink(img) - caps) / visible, c.width + 0.15, 0.15) << "w=" << c.width;
  }
}

TEST(DrawLine, FarEndpointsAreClippedWithoutBendingTheLine) {
  RgbImage img(100, 40, kWhite);
  draw_line(img, {-1e12, 10.5}, {1e12, 10.5}, kBlack, 1.0);
  draw_line(img, {50.5 - 1e9, 30.5 - 1e9}, {50.5 + 1e9, 30.5 + 1e9}, kBlack, 1.0);
  for (int x = 0; x < 100; ++x) {
    EXPECT_GT(ink(img, x, 10), 0.5) << x;
    if (x < 28 || x > 38) {  // the diagonal y = x - 20 crosses row 13 at x = 33
      EXPECT_EQ(img.at(x, 13), kWhite) << x;
    }
  }
  EXPECT_GT(ink(img, 45, 25), 0.5);  // on the diagonal through (50.5, 30.5)
  EXPECT_EQ(img.at(45, 30), kWhite);
}

TEST(DrawPolyline, TranslucentJointsAreBlendedOnce) {
  RgbImage img(40, 40, kWhite);
  draw_polyline(img, {{5.5, 5.5}, {30.5, 5.5}, {30.5, 30.5}, {5.5, 5.5}}, kBlack, 4.0, 0.5);
  // The corner (30, 5) is covered by two segments; blended once it is half grey like the middle.
  EXPECT_EQ(img.at(30, 5), (Rgb{128, 128, 128}));
  EXPECT_EQ(img.at(17, 5), (Rgb{128, 128, 128}));
  EXPECT_EQ(img.at(20, 20), (Rgb{128, 128, 128}));  // on the diagonal
  EXPECT_EQ(img.at(25, 12), kWhite);
}

TEST(DrawPolyline, DashedLineAlternatesInkAndGaps) {
  RgbImage img(200, 10, kWhite);
  draw_polyline(img, {{0, 5.5}, {200, 5.5}}, kBlack, 2.0, 1.0, true);
  int transitions = 0;
  for (int x = 1; x < img.width; ++x) {
    transitions += (ink(img, x, 5) > 0.5) != (ink(img, x - 1, 5) > 0.5);
  }
  // dash 7 px + gap 8 px: about 13 periods, two transitions each.
  EXPECT_GE(transitions, 20);
  EXPECT_LE(transitions, 30);
}

TEST(FillCircle, CoversTheDiscAndNothingFarOutside) {
  const Point c{20.3, 18.6};
  const double r = 9.4;
  RgbImage img(45, 40, kWhite);
  fill_circle(img, c, r, kBlack);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double d = std::hypot(x + 0.5 - c.x, y + 0.5 - c.y);
      if (d <= r - 1.0) {
        EXPECT_EQ(img.at(x, y), kBlack) << x << "," << y;
      }
      if (d >= r + 1.0) {
        EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y;
      }
    }
  }
  EXPECT_NEAR(total_ink(img), kPi * r * r, 0.02 * kPi * r * r);
}

TEST(FillPolygon, CoversTheInteriorAndNotTheOutside) {
  const Point a{5.3, 50.2}, b{54.1, 47.9}, c{21.7, 6.4};
  RgbImage img(60, 60, kWhite);
  fill_polygon(img, {a, b, c}, kBlack);
  const Point centroid{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
  EXPECT_EQ(img.at(static_cast<int>(centroid.x), static_cast<int>(centroid.y)), kBlack);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const Point p{x + 0.5, y + 0.5};
      const double d = std::min(
          {sampled_distance(p, a, b), sampled_distance(p, b, c), sampled_distance(p, c, a)});
      // Inside iff on the same side of every edge as the centroid.
      const auto side = [](Point u, Point v, Point q) {
        return (v.x - u.x) * (q.y - u.y) - (v.y - u.y) * (q.x - u.x);
      };
      const bool inside = side(a, b, p) * side(a, b, centroid) > 0 &&
                          side(b, c, p) * side(b, c, centroid) > 0 &&
                          side(c, a, p) * side(c, a, centroid) > 0;
      if (inside && d >= 1.0) {
        EXPECT_EQ(img.at(x, y), kBlack) << x << "," << y;
      }
      if (!inside && d >= 1.0) {
        EXPECT_EQ(img.at(x, y), kWhite) << x << "," << y;
      }
    }
  }
  const double area = 0.5 * std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
  // OpenCV fills the fine pixels on the outline too: at most a fifth of a pixel more all round.
  const double perimeter = std::hypot(b.x - a.x, b.y - a.y) + std::hypot(c.x - b.x, c.y - b.y) +
                           std::hypot(a.x - c.x, a.y - c.y);
  EXPECT_GT(total_ink(img), area - 0.05 * perimeter);
  EXPECT_LT(total_ink(img), area + 0.2 * perimeter);
}

TEST(FillPolygon, FarVerticesAreClippedWithoutChangingTheVisibleEdges) {
  // A band whose upper edge runs from (0, 10) to a vertex 1e9 pixels away on the same line.
  RgbImage img(50, 50, kWhite);
  fill_polygon(img, {{0, 10}, {1e9, 10 + 1e9}, {1e9, 1e9 + 60}, {0, 60}}, kBlack);
  EXPECT_EQ(img.at(30, 42), kBlack);  // below the diagonal y = 10 + x
  EXPECT_EQ(img.at(30, 36), kWhite);  // above it
  EXPECT_EQ(img.at(10, 23), kBlack);
  EXPECT_EQ(img.at(10, 17), kWhite);
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
          EXPECT_LE(std::abs(x + 0.5 - c.x), 0.5 * size + 3.0) << static_cast<int>(m);
          EXPECT_LE(std::abs(y + 0.5 - c.y), 0.5 * size + 3.0) << static_cast<int>(m);
        }
      }
    }
    ASSERT_GT(sum, 20.0) << static_cast<int>(m);
    EXPECT_NEAR(sx / sum, c.x, 0.5) << static_cast<int>(m);
    EXPECT_NEAR(sy / sum, c.y, m == Marker::kTriangle ? 1.0 : 0.5) << static_cast<int>(m);
    EXPECT_EQ(img.at(20, 20), kBlack) << static_cast<int>(m);  // every shape covers its centre
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
  blit(dst, src, 10, 10);  // entirely outside: nothing, no crash
  EXPECT_EQ(dst.at(0, 3), kWhite);
}

}  // namespace
}  // namespace vdtnav::viz
