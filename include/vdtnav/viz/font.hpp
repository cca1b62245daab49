#pragma once
/// \file
/// \brief An embedded 5x9 bitmap font for printable ASCII and text drawing on an `RgbImage`.
///
/// Each glyph is 5 pixels wide and 9 tall: rows 0..6 hold capitals and digits (row 6 is the
/// baseline row), rows 7..8 the descenders of g, j, p, q, y. Glyphs advance by 6 pixels; lines are
/// 11 pixels apart. Everything is multiplied by an integer scale.

#include <string_view>

#include "vdtnav/viz/image.hpp"

namespace vdtnav::viz {

inline constexpr int kGlyphWidth = 5;    ///< inked columns of a glyph
inline constexpr int kGlyphHeight = 9;   ///< rows of a glyph, descenders included
inline constexpr int kCapHeight = 7;     ///< rows above and including the baseline row
inline constexpr int kGlyphAdvance = 6;  ///< horizontal distance between glyph origins
inline constexpr int kLineHeight = 11;   ///< vertical distance between lines

/// \brief Horizontal anchor of a text: the anchor x is its left end, centre or right end.
enum class HAlign { kLeft, kCenter, kRight };
/// \brief Vertical anchor: top of the glyph box, middle of the capitals, or bottom of the
/// baseline row.
enum class VAlign { kTop, kMiddle, kBaseline };

/// \brief How to draw a text.
struct TextOptions {
  int scale = 1;  ///< integer magnification (>= 1)
  HAlign halign = HAlign::kLeft;
  VAlign valign = VAlign::kTop;
  bool vertical = false;  ///< rotated 90 degrees counter-clockwise, read bottom to top
  bool bold = false;      ///< struck twice, one pixel apart
};

/// \return true if pixel (col, row) of the glyph of `c` is inked; characters outside 32..126
/// draw as '?', and (col, row) outside the 5x9 box is never inked.
[[nodiscard]] bool glyph_pixel(char c, int col, int row);

/// \return the width in pixels of `text` drawn horizontally: `text.size() * kGlyphAdvance * scale`.
[[nodiscard]] int text_width(std::string_view text, int scale = 1);

/// \brief Draws `text` with its anchor at pixel (x, y). A vertical text is laid out as if
/// horizontal and then rotated about the anchor, so `halign` runs along the text (kLeft = the
/// text starts at y and goes up) and `valign` across it.
void draw_text(RgbImage& img, int x, int y, std::string_view text, Rgb color,
               const TextOptions& options = {});

}  // namespace vdtnav::viz
