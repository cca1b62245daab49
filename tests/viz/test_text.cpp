#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <string>

#include "viz/raster.hpp"

namespace vdtnav::viz::detail {
namespace {

/// Bounding box of the pixels that are not white.
cv::Rect ink_box(const RgbImage& img) {
  int x0 = img.width, y0 = img.height, x1 = -1, y1 = -1;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) == kWhite) continue;
      x0 = std::min(x0, x);
      y0 = std::min(y0, y);
      x1 = std::max(x1, x);
      y1 = std::max(y1, y);
    }
  }
  return x1 < 0 ? cv::Rect() : cv::Rect(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
}

TEST(Font, SizeIsOpenCvsForTheChosenScaleAndCapitalsAreEightPixelsPerScale) {
  for (int s = 1; s <= 4; ++s) {
    const Font font(s);
    int descent = 0, cv_descent = 0;
    const cv::Size size = font.size("Tick 0.25", &descent);
    const cv::Size expected = cv::getTextSize("Tick 0.25", cv::FONT_HERSHEY_SIMPLEX, font.scale(),
                                              font.thickness(), &cv_descent);
    EXPECT_EQ(size, expected);
    EXPECT_EQ(descent, cv_descent);
    // The inked capitals: 8 s pixels plus the stroke and its anti-aliased fringe.
    RgbImage img(200, 100);
    font.draw(img, 10, 50, "HEH", kBlack, HAlign::kLeft, VAlign::kBaseline);
    const cv::Rect ink = ink_box(img);
    EXPECT_NEAR(ink.height, 8 * s + font.thickness() + 1, 2) << "s = " << s;
    EXPECT_NEAR(ink.y + ink.height, 50, 1 + font.thickness()) << "s = " << s;
  }
}

TEST(Font, TextFillsTheBoxGetTextSizeGivesAtTheAnchor) {
  const Font font(2);
  const std::string text = "Legend: gyp 12";
  int descent = 0;
  const cv::Size size = font.size(text, &descent);
  const int slack = font.thickness() + 1;  // anti-aliased edge of a stroke
  struct Case {
    HAlign h;
    VAlign v;
    int left, top;  // expected top-left corner of the box for the anchor (200, 60)
  };
  for (const Case& c :
       {Case{HAlign::kLeft, VAlign::kTop, 200, 60},
        Case{HAlign::kRight, VAlign::kTop, 200 - size.width, 60},
        Case{HAlign::kCenter, VAlign::kBaseline, 200 - size.width / 2, 60 - size.height},
        Case{HAlign::kLeft, VAlign::kMiddle, 200,
             60 - font.cap_height() / 2 - (size.height - font.cap_height())}}) {
    RgbImage img(400, 140);
    font.draw(img, 200, 60, text, kBlack, c.h, c.v);
    const cv::Rect ink = ink_box(img);
    ASSERT_FALSE(ink.empty());
    EXPECT_NEAR(ink.x, c.left, slack);
    EXPECT_NEAR(ink.x + ink.width, c.left + size.width, slack);
    EXPECT_NEAR(ink.y, c.top, slack);
    EXPECT_NEAR(ink.y + ink.height, c.top + size.height + descent, slack);
  }
}

TEST(Font, VerticalTextIsTheHorizontalTextTurnedCounterClockwise) {
  const Font font(2);
  const std::string text = "y [m]";
  int descent = 0;
  const cv::Size size = font.size(text, &descent);
  RgbImage flat(300, 300), turned(300, 300);
  font.draw(flat, 150, 150, text, kBlack, HAlign::kLeft, VAlign::kTop);
  font.draw(turned, 150, 150, text, kBlack, HAlign::kLeft, VAlign::kTop, true);
  const cv::Rect a = ink_box(flat), b = ink_box(turned);
  EXPECT_EQ(a.width, b.height);
  EXPECT_EQ(a.height, b.width);
  // Read bottom to top from the anchor: ends at the anchor row, top of the box on the anchor
  // column.
  const int slack = font.thickness() + 1;
  EXPECT_NEAR(b.y + b.height, 150, slack);
  EXPECT_NEAR(b.y, 150 - size.width, slack);
  EXPECT_NEAR(b.x, 150, slack);
  EXPECT_NEAR(b.x + b.width, 150 + size.height + descent, slack);
  // Pixel (i, j) of the flat text is pixel (150 + (j - 150), 150 - (i - 150)) of the turned one.
  int same = 0, inked = 0;
  for (int j = a.y; j < a.y + a.height; ++j) {
    for (int i = a.x; i < a.x + a.width; ++i) {
      if (flat.at(i, j) == kWhite) continue;
      ++inked;
      same += turned.at(j, 300 - i) != kWhite || turned.at(j, 299 - i) != kWhite;
    }
  }
  EXPECT_GT(inked, 100);
  EXPECT_EQ(same, inked);
}

TEST(Font, TextIsColouredAndClippedAtTheImageEdges) {
  const Font font(3, true);
  RgbImage img(60, 30);
  const Rgb red{200, 0, 0};
  font.draw(img, -20, 15, "WWWWWWWW", red, HAlign::kLeft, VAlign::kMiddle);  // wider than img
  int full = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) full += img.at(x, y) == red;
  }
  EXPECT_GT(full, 50);                                 // solid strokes in the text colour
  EXPECT_EQ(ink_box(img).x, 0);                        // runs off the left edge
  EXPECT_EQ(ink_box(img).x + ink_box(img).width, 60);  // and the right one
  font.draw(img, 1000, 1000, "outside", red, HAlign::kLeft, VAlign::kTop);  // no effect, no crash
}

}  // namespace
}  // namespace vdtnav::viz::detail
