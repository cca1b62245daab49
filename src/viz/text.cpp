// Text of vdtnav figures: OpenCV's Hershey simplex font drawn anti-aliased into a coverage mask,
// which is then blended into the image (turned for vertical labels).

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "raster.hpp"

namespace vdtnav::viz::detail {
namespace {

constexpr int kFace = cv::FONT_HERSHEY_SIMPLEX;
constexpr int kCapPerScale = 8;  // capital height in pixels per unit of Figure's font scale

}  // namespace

Font::Font(int s, bool bold) {
  s = std::max(s, 1);
  // OpenCV's anti-aliased strokes ink about 1.4 px at thickness 1 and t + 1.7 px above: thickness
  // 1 up to s = 3 (capitals 24 px), then s / 2; bold one more, from s = 2 on (at s = 1 the 8 px
  // capitals would fill in).
  thickness_ = std::max(1, s / 2) + (bold && s >= 2 ? 1 : 0);
  // getTextSize's height is the capital height times the scale plus half the stroke.
  const int unit = cv::getTextSize("H", kFace, 1.0, 1, nullptr).height;
  scale_ = static_cast<double>(kCapPerScale * s) / unit;
  int descent = 0;
  cap_ = cv::getTextSize("H", kFace, scale_, thickness_, &descent).height;
  descent_ = descent;
  gap_ = 3 * s;
}

cv::Size Font::size(std::string_view text, int* descent) const {
  int d = 0;
  const cv::Size sz = cv::getTextSize(std::string(text), kFace, scale_, thickness_, &d);
  if (descent != nullptr) *descent = d;
  return sz;
}

void Font::draw(RgbImage& img, int x, int y, std::string_view text, Rgb c, HAlign h, VAlign v,
                bool vertical) const {
  if (text.empty()) return;
  // The text in a mask of its box plus a margin for the anti-aliased stroke; (ax, ay) is the
  // anchor in the mask.
  const int margin = thickness_ + 1;
  const cv::Size sz = size(text);
  cv::Mat mask = cv::Mat::zeros(sz.height + descent_ + 2 * margin, sz.width + 2 * margin, CV_8UC1);
  const cv::Point origin(margin, margin + sz.height);  // left end of the baseline
  cv::putText(mask, std::string(text), origin, kFace, scale_, 255, thickness_, cv::LINE_AA);
  const int ax = origin.x + (h == HAlign::kLeft     ? 0
                             : h == HAlign::kCenter ? sz.width / 2
                                                    : sz.width);
  const int ay = v == VAlign::kBaseline ? origin.y
                 : v == VAlign::kMiddle ? origin.y - cap_ / 2
                                        : margin;
  // Top-left corner of the mask in the image. Turned counter-clockwise, mask pixel (i, j) lands
  // at (x + j - ay, y - i + ax), so the turned mask's corner is (x - ay, y + ax - (width - 1)).
  int x0 = x - ax, y0 = y - ay;
  if (vertical) {
    cv::rotate(mask, mask, cv::ROTATE_90_COUNTERCLOCKWISE);
    x0 = x - ay;
    y0 = y + ax - (mask.rows - 1);
  }
  blend(img, mask, {x0, y0}, c, 1.0);
}

}  // namespace vdtnav::viz::detail
