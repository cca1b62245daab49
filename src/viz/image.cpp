#include "vdtnav/viz/image.hpp"

#include <stb/stb_image_write.h>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "raster.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::viz {

RgbImage::RgbImage(int width, int height, Rgb fill) : width(width), height(height) {
  VDTNAV_CHECK(width >= 0 && height >= 0, "image size must be >= 0");
  rgb.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = fill.r;
    rgb[i + 1] = fill.g;
    rgb[i + 2] = fill.b;
  }
}

Rgb RgbImage::at(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void RgbImage::set(int x, int y, Rgb c) {
  if (!contains(x, y)) return;
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  rgb[i] = c.r;
  rgb[i + 1] = c.g;
  rgb[i + 2] = c.b;
}

namespace detail {
namespace {

/// Floor of v clamped to [lo, hi] without overflowing int for huge or infinite v.
int clamped_floor(double v, int lo, int hi) {
  if (std::isnan(v)) return lo;
  return static_cast<int>(std::floor(std::clamp(v, double(lo), double(hi))));
}

bool finite(Point p) { return std::isfinite(p.x) && std::isfinite(p.y); }

/// Clips segment ab to the box [lo, hi] (Liang & Barsky); false if it misses the box.
bool clip_segment(Point& a, Point& b, Point lo, Point hi) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y};
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else if (p[i] < 0.0) {
      t0 = std::max(t0, q[i] / p[i]);
    } else {
      t1 = std::min(t1, q[i] / p[i]);
    }
  }
  if (t0 > t1) return false;
  const Point a0 = a;
  a = {a0.x + t0 * dx, a0.y + t0 * dy};
  b = {a0.x + t1 * dx, a0.y + t1 * dy};
  return true;
}

/// Clips a polygon to the box [lo, hi], one box edge at a time (Sutherland & Hodgman).
std::vector<Point> clip_polygon(std::vector<Point> poly, Point lo, Point hi) {
  const auto coord = [](Point p, int axis) { return axis == 0 ? p.x : p.y; };
  for (int edge = 0; edge < 4 && !poly.empty(); ++edge) {
    const int axis = edge / 2;
    const double bound = edge % 2 == 0 ? coord(lo, axis) : coord(hi, axis);
    const double side = edge % 2 == 0 ? 1.0 : -1.0;
    const auto inside = [&](Point p) { return side * (coord(p, axis) - bound) >= 0.0; };
    const auto cross = [&](Point a, Point b) {
      const double t = (bound - coord(a, axis)) / (coord(b, axis) - coord(a, axis));
      return Point{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    };
    std::vector<Point> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Point a = poly[(i + poly.size() - 1) % poly.size()], b = poly[i];
      if (inside(a) != inside(b)) out.push_back(cross(a, b));
      if (inside(b)) out.push_back(b);
    }
    poly = std::move(out);
  }
  return poly;
}

cv::Mat as_const_mat(const RgbImage& img) {
  return {img.height, img.width, CV_8UC3, const_cast<std::uint8_t*>(img.rgb.data())};
}

}  // namespace

cv::Mat as_mat(RgbImage& img) { return {img.height, img.width, CV_8UC3, img.rgb.data()}; }

void blend(RgbImage& img, const cv::Mat& coverage, cv::Point at, Rgb c, double alpha) {
  if (!(alpha > 0.0)) return;
  alpha = std::min(alpha, 1.0);
  const cv::Rect r = cv::Rect(at, coverage.size()) & cv::Rect(0, 0, img.width, img.height);
  const std::uint8_t col[3] = {c.r, c.g, c.b};
  for (int y = r.y; y < r.y + r.height; ++y) {
    const std::uint8_t* m = coverage.ptr<std::uint8_t>(y - at.y) - at.x;
    for (int x = r.x; x < r.x + r.width; ++x) {
      if (m[x] == 0) continue;
      const double a = alpha * m[x] / 255.0;
      std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
      for (int k = 0; k < 3; ++k) {
        p[k] = static_cast<std::uint8_t>(std::lround(p[k] + a * (col[k] - p[k])));
      }
    }
  }
}

Coverage::Coverage(const RgbImage& img, double xmin, double ymin, double xmax, double ymax)
    : x0_(clamped_floor(xmin, 0, img.width)), y0_(clamped_floor(ymin, 0, img.height)) {
  const int w = clamped_floor(xmax, -1, img.width - 1) + 1 - x0_;
  const int h = clamped_floor(ymax, -1, img.height - 1) + 1 - y0_;
  if (w > 0 && h > 0) mask_ = cv::Mat::zeros(h * kSuper, w * kSuper, CV_8UC1);
}

cv::Point Coverage::fixed(Point p) const {
  const auto f = [](double v, int origin) {
    const double limit = 1 << 20;  // clipping keeps shapes far inside this
    const double fine = std::clamp((v - origin) * kSuper - 0.5, -limit, limit);
    return static_cast<int>(std::lround(fine * (1 << kShift)));
  };
  return {f(p.x, x0_), f(p.y, y0_)};
}

void Coverage::segment(Point a, Point b, double width) {
  if (empty() || !finite(a) || !finite(b)) return;
  const double m = width + 2.0;  // anything farther outside the mask leaves it untouched
  const double w = static_cast<double>(mask_.cols) / kSuper,
               h = static_cast<double>(mask_.rows) / kSuper;
  if (!clip_segment(a, b, {x0_ - m, y0_ - m}, {x0_ + w + m, y0_ + h + m})) return;
  // A rectangle and two discs: cv::line's thick strokes come only in odd fine-pixel widths.
  const double len = std::hypot(b.x - a.x, b.y - a.y), r = 0.5 * width;
  if (len > 0.0) {
    const Point n{-(b.y - a.y) / len * r, (b.x - a.x) / len * r};
    polygon({{a.x + n.x, a.y + n.y},
             {b.x + n.x, b.y + n.y},
             {b.x - n.x, b.y - n.y},
             {a.x - n.x, a.y - n.y}});
  }
  disc(a, r);
  disc(b, r);
}

void Coverage::polygon(std::vector<Point> pts) {
  if (empty()) return;
  for (const Point& p : pts) {
    if (!finite(p)) return;
  }
  const double w = static_cast<double>(mask_.cols) / kSuper,
               h = static_cast<double>(mask_.rows) / kSuper;
  pts = clip_polygon(std::move(pts), {x0_ - 2.0, y0_ - 2.0}, {x0_ + w + 2.0, y0_ + h + 2.0});
  if (pts.size() < 3) return;
  std::vector<cv::Point> poly;
  poly.reserve(pts.size());
  for (const Point& p : pts) poly.push_back(fixed(p));
  cv::fillPoly(mask_, std::vector<std::vector<cv::Point>>{poly}, 255, cv::LINE_8, kShift);
}

void Coverage::disc(Point centre, double radius) {
  if (empty() || !finite(centre) || !(radius > 0.0)) return;
  // As for lines: the outline's fine pixels are included, half a fine pixel off the radius.
  const double fine_radius = std::max(radius * kSuper - 0.5, 0.0);
  cv::circle(mask_, fixed(centre), static_cast<int>(std::lround(fine_radius * (1 << kShift))), 255,
             cv::FILLED, cv::LINE_8, kShift);
}

void Coverage::blend_into(RgbImage& img, Rgb c, double alpha) const {
  if (empty()) return;
  cv::Mat coverage;
  cv::resize(mask_, coverage, cv::Size(mask_.cols / kSuper, mask_.rows / kSuper), 0.0, 0.0,
             cv::INTER_AREA);
  blend(img, coverage, {x0_, y0_}, c, alpha);
}

}  // namespace detail

namespace {

using detail::Coverage;

/// Splits a polyline into dashes of length `on` separated by gaps of length `off`.
std::vector<std::vector<Point>> dashes(const std::vector<Point>& pts, double on, double off) {
  std::vector<std::vector<Point>> out;
  std::vector<Point> current{pts.front()};
  bool drawing = true;
  double left = on;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const Point a = pts[i - 1], b = pts[i];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    double t = 0.0;
    while (len - t > left) {
      t += left;
      const Point p{a.x + (b.x - a.x) * t / len, a.y + (b.y - a.y) * t / len};
      if (drawing) {
        current.push_back(p);
        out.push_back(current);
        current.clear();
      } else {
        current = {p};
      }
      drawing = !drawing;
      left = drawing ? on : off;
    }
    left -= len - t;
    if (drawing) current.push_back(b);
  }
  if (drawing && current.size() >= 2) out.push_back(current);
  return out;
}

/// The coverage mask of the bounding box of `pts` grown by `margin` pixels.
Coverage box_of(const RgbImage& img, const std::vector<Point>& pts, double margin) {
  double xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
  for (const Point& p : pts) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    xmin = std::min(xmin, p.x - margin);
    ymin = std::min(ymin, p.y - margin);
    xmax = std::max(xmax, p.x + margin);
    ymax = std::max(ymax, p.y + margin);
  }
  return {img, xmin, ymin, xmax, ymax};
}

}  // namespace

void fill_rect(RgbImage& img, const PixelRect& rect, Rgb c, double alpha) {
  const cv::Rect r =
      cv::Rect(rect.x, rect.y, rect.width, rect.height) & cv::Rect(0, 0, img.width, img.height);
  if (r.empty() || !(alpha > 0.0)) return;
  cv::Mat roi = detail::as_mat(img)(r);
  const cv::Scalar color(c.r, c.g, c.b);
  if (alpha >= 1.0) {
    roi.setTo(color);
  } else {
    cv::addWeighted(roi, 1.0 - alpha, cv::Mat(roi.size(), roi.type(), color), alpha, 0.0, roi);
  }
}

void draw_rect(RgbImage& img, const PixelRect& r, Rgb c, int t) {
  fill_rect(img, {r.x, r.y, r.width, t}, c);
  fill_rect(img, {r.x, r.y + r.height - t, r.width, t}, c);
  fill_rect(img, {r.x, r.y + t, t, r.height - 2 * t}, c);
  fill_rect(img, {r.x + r.width - t, r.y + t, t, r.height - 2 * t}, c);
}

void draw_line(RgbImage& img, Point a, Point b, Rgb c, double width, double alpha) {
  draw_polyline(img, {a, b}, c, width, alpha);
}

void draw_polyline(RgbImage& img, const std::vector<Point>& pts, Rgb c, double width, double alpha,
                   bool dashed) {
  if (pts.empty()) return;
  Coverage mask = box_of(img, pts, 0.5 * width + 2.0);
  if (pts.size() == 1) mask.segment(pts[0], pts[0], width);
  if (dashed) {
    // Round caps lengthen each dash by the width: keep the visible gap about width + 3 px.
    for (const auto& dash : dashes(pts, 2.0 * width + 3.0, 2.0 * width + 4.0)) {
      for (std::size_t i = 1; i < dash.size(); ++i) mask.segment(dash[i - 1], dash[i], width);
    }
  } else {
    for (std::size_t i = 1; i < pts.size(); ++i) mask.segment(pts[i - 1], pts[i], width);
  }
  mask.blend_into(img, c, alpha);
}

void fill_circle(RgbImage& img, Point centre, double radius, Rgb c, double alpha) {
  Coverage mask = box_of(img, {centre}, radius + 2.0);
  mask.disc(centre, radius);
  mask.blend_into(img, c, alpha);
}

void fill_polygon(RgbImage& img, const std::vector<Point>& pts, Rgb c, double alpha) {
  if (pts.size() < 3) return;
  Coverage mask = box_of(img, pts, 2.0);
  mask.polygon(pts);
  mask.blend_into(img, c, alpha);
}

void draw_marker(RgbImage& img, Point p, Marker marker, double size, Rgb c, double alpha) {
  const double r = 0.5 * size;
  switch (marker) {
    case Marker::kNone:
      return;
    case Marker::kCircle:
      return fill_circle(img, p, r, c, alpha);
    case Marker::kSquare: {
      const double h = 0.85 * r;  // same visual weight as the circle
      return fill_polygon(
          img, {{p.x - h, p.y - h}, {p.x + h, p.y - h}, {p.x + h, p.y + h}, {p.x - h, p.y + h}}, c,
          alpha);
    }
    case Marker::kTriangle: {
      const double R = 1.15 * r, s = R * std::sqrt(3.0) / 2.0;
      return fill_polygon(img, {{p.x, p.y - R}, {p.x + s, p.y + R / 2}, {p.x - s, p.y + R / 2}}, c,
                          alpha);
    }
    case Marker::kCross:
    case Marker::kPlus: {
      const double w = std::max(1.5, size / 5.0);
      const double k = marker == Marker::kCross ? r * 0.75 : r;
      Coverage mask = box_of(img, {p}, r + w + 2.0);
      if (marker == Marker::kCross) {
        mask.segment({p.x - k, p.y - k}, {p.x + k, p.y + k}, w);
        mask.segment({p.x - k, p.y + k}, {p.x + k, p.y - k}, w);
      } else {
        mask.segment({p.x - k, p.y}, {p.x + k, p.y}, w);
        mask.segment({p.x, p.y - k}, {p.x, p.y + k}, w);
      }
      return mask.blend_into(img, c, alpha);
    }
  }
}

void blit(RgbImage& dst, const RgbImage& src, int x, int y) {
  const cv::Rect r = cv::Rect(x, y, src.width, src.height) & cv::Rect(0, 0, dst.width, dst.height);
  if (r.empty()) return;
  detail::as_const_mat(src)(r - cv::Point(x, y)).copyTo(detail::as_mat(dst)(r));
}

void draw_scaled(RgbImage& dst, const RgbImage& src, double x0, double y0, double x1, double y1) {
  if (!(x1 > x0) || !(y1 > y0) || src.width == 0 || src.height == 0 || dst.width == 0 ||
      dst.height == 0) {
    return;
  }
  // Inverse map of pixel centres, dst (i + 0.5) -> src (i + 0.5 - x0) / (x1 - x0) * width; OpenCV
  // puts centres at integers, hence the -0.5 on both sides. Pixels mapping outside src stay.
  const double sx = src.width / (x1 - x0), sy = src.height / (y1 - y0);
  const cv::Matx23d inverse(sx, 0.0, (0.5 - x0) * sx - 0.5, 0.0, sy, (0.5 - y0) * sy - 0.5);
  cv::Mat out = detail::as_mat(dst);
  cv::warpAffine(detail::as_const_mat(src), out, inverse, out.size(),
                 cv::INTER_NEAREST | cv::WARP_INVERSE_MAP, cv::BORDER_TRANSPARENT);
}

void write_png(const std::string& path, const RgbImage& img) {
  VDTNAV_CHECK(img.width > 0 && img.height > 0, "cannot write an empty image to " + path);
  if (stbi_write_png(path.c_str(), img.width, img.height, 3, img.rgb.data(), img.width * 3) == 0) {
    throw IoError("cannot write PNG file " + path);
  }
}

}  // namespace vdtnav::viz
