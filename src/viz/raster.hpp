#pragma once
// Private to vdtnav::viz: the OpenCV side of RgbImage drawing and text (no public header includes
// OpenCV, so users of vdtnav::viz need none of its headers).

#include <opencv2/core.hpp>
#include <string_view>
#include <vector>

#include "vdtnav/viz/image.hpp"

namespace vdtnav::viz::detail {

/// \return `img` as a cv::Mat of CV_8UC3 sharing its pixels (channel order r g b).
cv::Mat as_mat(RgbImage& img);

/// \brief Mixes `c` into `img` with opacity alpha * coverage / 255, `coverage` (CV_8UC1) having its
/// top-left pixel at `at`; clipped to the image.
void blend(RgbImage& img, const cv::Mat& coverage, cv::Point at, Rgb c, double alpha);

/// \brief Coverage of a shape over the pixels it can touch, blended into the image once (so a
/// translucent shape whose parts overlap does not darken where they do). Shapes are drawn by
/// OpenCV at kSuper times the resolution and averaged down (cv::resize, INTER_AREA): exact stroke
/// widths and areas to 1/kSuper pixel, where OpenCV's LINE_AA strokes come only 1.4, 3.7, 5.7 px
/// wide and its anti-aliased fillPoly grows a shape by about 0.7 px on every side.
class Coverage {
 public:
  static constexpr int kSuper = 4;  ///< sub-pixels per pixel and axis
  static constexpr int kShift = 4;  ///< fractional bits of OpenCV's fixed-point coordinates

  /// The mask covers [xmin, xmax] x [ymin, ymax] (continuous coordinates) clipped to the image.
  Coverage(const RgbImage& img, double xmin, double ymin, double xmax, double ymax);

  [[nodiscard]] bool empty() const { return mask_.empty(); }
  /// \brief Segment `width` pixels wide with round caps (cv::fillPoly and two cv::circle).
  void segment(Point a, Point b, double width);
  /// \brief Filled polygon (cv::fillPoly).
  void polygon(std::vector<Point> pts);
  /// \brief Filled disc (cv::circle).
  void disc(Point centre, double radius);
  /// \brief Mixes `c` with opacity alpha * coverage into the pixels of `img`.
  void blend_into(RgbImage& img, Rgb c, double alpha) const;

 private:
  /// p in the fine mask's fixed-point coordinates (OpenCV puts pixel centres at integers).
  [[nodiscard]] cv::Point fixed(Point p) const;

  int x0_ = 0, y0_ = 0;
  cv::Mat mask_;  // kSuper times the size of the covered box
};

/// \brief Anchors of a text: the anchor x is its left end, centre or right end; the anchor y the
/// top of its box, the middle of its capitals or its baseline.
enum class HAlign { kLeft, kCenter, kRight };
enum class VAlign { kTop, kMiddle, kBaseline };

/// \brief Text in OpenCV's FONT_HERSHEY_SIMPLEX at the size of one integer font scale `s` of
/// Figure: capitals 8 s pixels tall (the former bitmap font had 7 s).
class Font {
 public:
  explicit Font(int s, bool bold = false);
  /// \return the size of `text`: width, capital height and descent below the baseline.
  [[nodiscard]] cv::Size size(std::string_view text, int* descent = nullptr) const;
  [[nodiscard]] int width(std::string_view text) const { return size(text).width; }
  [[nodiscard]] int cap_height() const { return cap_; }
  /// \return capital height plus descent: the height of any text's box.
  [[nodiscard]] int box_height() const { return cap_ + descent_; }
  /// \return the distance between the tops of two lines of text.
  [[nodiscard]] int line_height() const { return box_height() + gap_; }
  /// \return the width of one digit.
  [[nodiscard]] int advance() const { return width("0"); }
  /// \return the fontScale and thickness handed to cv::putText.
  [[nodiscard]] double scale() const { return scale_; }
  [[nodiscard]] int thickness() const { return thickness_; }

  /// \brief Draws `text` with its anchor at pixel (x, y). A vertical text is laid out as if
  /// horizontal and then turned 90 degrees counter-clockwise about the anchor (read bottom to top).
  void draw(RgbImage& img, int x, int y, std::string_view text, Rgb c, HAlign h, VAlign v,
            bool vertical = false) const;

 private:
  double scale_;
  int thickness_, cap_, descent_, gap_;
};

}  // namespace vdtnav::viz::detail
