#include "vdtnav/viz/font.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

namespace vdtnav::viz {
namespace {

std::vector<bool> bitmap(char c) {
  std::vector<bool> bits;
  for (int row = 0; row < kGlyphHeight; ++row) {
    for (int col = 0; col < kGlyphWidth; ++col) bits.push_back(glyph_pixel(c, col, row));
  }
  return bits;
}

bool inked(const RgbImage& img, int x, int y) { return img.at(x, y) != kWhite; }

TEST(Font, EveryPrintableGlyphIsInkedAndUnique) {
  std::set<std::vector<bool>> seen;
  for (char c = 33; c <= 126; ++c) {
    const std::vector<bool> bits = bitmap(c);
    EXPECT_NE(std::count(bits.begin(), bits.end(), true), 0) << c;
    EXPECT_TRUE(seen.insert(bits).second) << "glyph '" << c << "' duplicates another";
  }
  const std::vector<bool> space = bitmap(' ');
  EXPECT_EQ(std::count(space.begin(), space.end(), true), 0);
  EXPECT_EQ(bitmap('\t'), bitmap('?'));  // non-printable characters draw as '?'
  EXPECT_FALSE(glyph_pixel('H', -1, 0));
  EXPECT_FALSE(glyph_pixel('H', 0, kGlyphHeight));
}

TEST(Font, OnlyDescendersInkBelowTheBaselineRow) {
  std::string below;
  for (char c = 32; c <= 126; ++c) {
    for (int col = 0; col < kGlyphWidth; ++col) {
      if (glyph_pixel(c, col, kCapHeight) || glyph_pixel(c, col, kCapHeight + 1)) {
        below += c;
        break;
      }
    }
  }
  EXPECT_EQ(below, ",_gjpqy|");
  // Capitals and digits fill the cap height: ink on the top row and on the baseline row.
  for (const char c : std::string("0123456789ABCDEFHIJKLMNOPRSTUVWXYZ")) {
    bool top = false, base = false;
    for (int col = 0; col < kGlyphWidth; ++col) {
      top = top || glyph_pixel(c, col, 0);
      base = base || glyph_pixel(c, col, kCapHeight - 1);
    }
    EXPECT_TRUE(top && base) << c;
  }
}

TEST(Font, TextWidthIsCharactersTimesAdvance) {
  EXPECT_EQ(text_width("", 1), 0);
  EXPECT_EQ(text_width("x", 1), kGlyphAdvance);
  EXPECT_EQ(text_width("-0.005", 2), 6 * kGlyphAdvance * 2);
  EXPECT_EQ(text_width("position error [m]", 3), 18 * kGlyphAdvance * 3);
}

TEST(Font, DrawnPixelsAreTheScaledGlyphs) {
  const std::string text = "Hg,0!";
  const int s = 2, x0 = 7, y0 = 5;
  RgbImage img(80, 40, kWhite);
  draw_text(img, x0, y0, text, kBlack, {s});
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const int u = x - x0, v = y - y0;
      const int k = u / (kGlyphAdvance * s), col = (u % (kGlyphAdvance * s)) / s, row = v / s;
      const bool expected =
          u >= 0 && v >= 0 && k < static_cast<int>(text.size()) && glyph_pixel(text[k], col, row);
      EXPECT_EQ(inked(img, x, y), expected) << x << "," << y;
    }
  }
}

/// Ink bounding box {xmin, ymin, xmax, ymax}, inclusive.
std::vector<int> ink_box(const RgbImage& img) {
  std::vector<int> box{img.width, img.height, -1, -1};
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (!inked(img, x, y)) continue;
      box = {std::min(box[0], x), std::min(box[1], y), std::max(box[2], x), std::max(box[3], y)};
    }
  }
  return box;
}

TEST(Font, AlignmentShiftsByTheTextExtent) {
  const std::string text = "HUH";  // ink in the first and last glyph columns
  RgbImage left(100, 40, kWhite), centre(100, 40, kWhite), right(100, 40, kWhite);
  draw_text(left, 50, 20, text, kBlack, {1, HAlign::kLeft, VAlign::kTop});
  draw_text(centre, 50, 20, text, kBlack, {1, HAlign::kCenter, VAlign::kMiddle});
  draw_text(right, 50, 20, text, kBlack, {1, HAlign::kRight, VAlign::kBaseline});
  const int w = text_width(text);
  EXPECT_EQ(ink_box(left), (std::vector<int>{50, 20, 50 + w - 2, 20 + kCapHeight - 1}));
  EXPECT_EQ(ink_box(centre)[0], 50 - w / 2);
  EXPECT_EQ(ink_box(centre)[1], 20 - kCapHeight / 2);
  EXPECT_EQ(ink_box(right)[2], 50 - 2);  // the advance's blank column ends at the anchor
  EXPECT_EQ(ink_box(right)[3], 20 - 1);  // baseline row ends just above the anchor
}

TEST(Font, VerticalTextIsHorizontalTextRotatedCounterClockwise) {
  const std::string text = "y [m]";
  const int s = 2;
  RgbImage h(80, 30, kWhite), v(30, 80, kWhite);
  draw_text(h, 0, 0, text, kBlack, {s});
  draw_text(v, 0, 80, text, kBlack, {s, HAlign::kLeft, VAlign::kTop, true});
  int count_h = 0, count_v = 0;
  for (int y = 0; y < h.height; ++y) {
    for (int x = 0; x < h.width; ++x) {
      if (!inked(h, x, y)) continue;
      ++count_h;
      // (u, v) horizontal -> (v, H - 1 - u) vertical: the text reads bottom to top.
      EXPECT_TRUE(inked(v, y, 80 - 1 - x)) << x << "," << y;
    }
  }
  for (const auto b : v.rgb) count_v += b == 0;
  EXPECT_EQ(count_v, 3 * count_h);
  EXPECT_GT(ink_box(v)[3], 80 - kGlyphAdvance * s);  // first glyph 'y' at the bottom
}

TEST(Font, BoldAddsInkAndKeepsTheGlyph) {
  RgbImage plain(40, 20, kWhite), bold(40, 20, kWhite);
  draw_text(plain, 2, 2, "Ab", kBlack, {2});
  draw_text(bold, 2, 2, "Ab", kBlack, {2, HAlign::kLeft, VAlign::kTop, false, true});
  int extra = 0;
  for (int y = 0; y < plain.height; ++y) {
    for (int x = 0; x < plain.width; ++x) {
      if (inked(plain, x, y)) {
        EXPECT_TRUE(inked(bold, x, y));
      }
      extra += inked(bold, x, y) && !inked(plain, x, y);
    }
  }
  EXPECT_GT(extra, 5);
}

}  // namespace
}  // namespace vdtnav::viz
