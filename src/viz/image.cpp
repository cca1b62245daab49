#include "vdtnav/viz/image.hpp"

#include <algorithm>
#include <cmath>

#include <stb/stb_image_write.h>

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

void RgbImage::blend(int x, int y, Rgb c, double alpha) {
  if (!contains(x, y) || !(alpha > 0.0)) return;
  if (alpha >= 1.0) return set(x, y, c);
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
  const auto mix = [alpha](std::uint8_t old, std::uint8_t add) {
    return static_cast<std::uint8_t>(std::lround(old + alpha * (add - old)));
  };
  rgb[i] = mix(rgb[i], c.r);
  rgb[i + 1] = mix(rgb[i + 1], c.g);
  rgb[i + 2] = mix(rgb[i + 2], c.b);
}

namespace {

/// Floor of v clamped to [lo, hi] without overflowing int for huge or infinite v.
int clamped_floor(double v, int lo, int hi) {
  if (std::isnan(v)) return lo;
  return static_cast<int>(std::floor(std::clamp(v, double(lo), double(hi))));
}

double distance_to_segment(Point p, Point a, Point b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

bool finite(Point p) { return std::isfinite(p.x) && std::isfinite(p.y); }

/// Per-pixel coverage over a box of the image, combined with max so that each pixel is blended
/// once however many segments cover it.
class CoverageMask {
 public:
  /// The box covers [xmin, xmax] x [ymin, ymax] (continuous coordinates) clipped to the image.
  CoverageMask(const RgbImage& img, double xmin, double ymin, double xmax, double ymax)
      : x0_(clamped_floor(xmin, 0, img.width)),
        y0_(clamped_floor(ymin, 0, img.height)),
        w_(clamped_floor(xmax, -1, img.width - 1) + 1 - x0_),
        h_(clamped_floor(ymax, -1, img.height - 1) + 1 - y0_),
        cov_(static_cast<std::size_t>(std::max(w_, 0)) * std::max(h_, 0), 0.0f) {}

  void add_segment(Point a, Point b, double half_width) {
    if (!finite(a) || !finite(b)) return;
    const double r = half_width + 1.0;
    const int x0 = clamped_floor(std::min(a.x, b.x) - r, x0_, x0_ + w_);
    const int x1 = clamped_floor(std::max(a.x, b.x) + r, x0_ - 1, x0_ + w_ - 1);
    const int y0 = clamped_floor(std::min(a.y, b.y) - r, y0_, y0_ + h_);
    const int y1 = clamped_floor(std::max(a.y, b.y) + r, y0_ - 1, y0_ + h_ - 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double d = distance_to_segment({x + 0.5, y + 0.5}, a, b);
        float& m = cov_[static_cast<std::size_t>(y - y0_) * w_ + (x - x0_)];
        m = std::max(m, static_cast<float>(std::clamp(half_width + 0.5 - d, 0.0, 1.0)));
      }
    }
  }

  void blend_into(RgbImage& img, Rgb c, double alpha) const {
    for (int y = 0; y < h_; ++y) {
      for (int x = 0; x < w_; ++x) {
        img.blend(x0_ + x, y0_ + y, c, alpha * cov_[static_cast<std::size_t>(y) * w_ + x]);
      }
    }
  }

 private:
  int x0_, y0_, w_, h_;
  std::vector<float> cov_;
};

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

/// Adds weight w times the covered fraction of each pixel of the span [xa, xb) to acc.
void add_span(std::vector<float>& acc, double xa, double xb, float w) {
  const double n = static_cast<double>(acc.size());
  xa = std::clamp(xa, 0.0, n);
  xb = std::clamp(xb, 0.0, n);
  if (xb <= xa) return;
  const auto ia = static_cast<std::size_t>(xa), ib = static_cast<std::size_t>(xb);
  if (ia == ib) {
    acc[ia] += static_cast<float>(xb - xa) * w;
    return;
  }
  acc[ia] += static_cast<float>(ia + 1 - xa) * w;
  for (std::size_t i = ia + 1; i < ib; ++i) acc[i] += w;
  if (ib < acc.size()) acc[ib] += static_cast<float>(xb - ib) * w;
}

}  // namespace

void fill_rect(RgbImage& img, const PixelRect& rect, Rgb c, double alpha) {
  const int x0 = std::max(rect.x, 0), x1 = std::min(rect.x + rect.width, img.width);
  const int y0 = std::max(rect.y, 0), y1 = std::min(rect.y + rect.height, img.height);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) img.blend(x, y, c, alpha);
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
  const double hw = 0.5 * width;
  double xmin = HUGE_VAL, ymin = HUGE_VAL, xmax = -HUGE_VAL, ymax = -HUGE_VAL;
  for (const Point& p : pts) {
    if (!finite(p)) continue;
    xmin = std::min(xmin, p.x - hw - 1);
    ymin = std::min(ymin, p.y - hw - 1);
    xmax = std::max(xmax, p.x + hw + 1);
    ymax = std::max(ymax, p.y + hw + 1);
  }
  if (!(xmax >= xmin)) return;
  CoverageMask mask(img, xmin, ymin, xmax, ymax);
  if (pts.size() == 1) mask.add_segment(pts[0], pts[0], hw);
  if (dashed) {
    // Round caps lengthen each dash by the width: keep the visible gap about width + 3 px.
    for (const auto& dash : dashes(pts, 2.0 * width + 3.0, 2.0 * width + 4.0)) {
      for (std::size_t i = 1; i < dash.size(); ++i) mask.add_segment(dash[i - 1], dash[i], hw);
    }
  } else {
    for (std::size_t i = 1; i < pts.size(); ++i) mask.add_segment(pts[i - 1], pts[i], hw);
  }
  mask.blend_into(img, c, alpha);
}

void fill_circle(RgbImage& img, Point centre, double radius, Rgb c, double alpha) {
  if (!finite(centre)) return;
  const int x0 = clamped_floor(centre.x - radius - 1, 0, img.width);
  const int x1 = clamped_floor(centre.x + radius + 1, 0, img.width - 1);
  const int y0 = clamped_floor(centre.y - radius - 1, 0, img.height);
  const int y1 = clamped_floor(centre.y + radius + 1, 0, img.height - 1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double d = std::hypot(x + 0.5 - centre.x, y + 0.5 - centre.y);
      img.blend(x, y, c, alpha * std::clamp(radius + 0.5 - d, 0.0, 1.0));
    }
  }
}

void fill_polygon(RgbImage& img, const std::vector<Point>& pts, Rgb c, double alpha) {
  if (pts.size() < 3 || img.width == 0) return;
  double ymin = pts[0].y, ymax = pts[0].y;
  for (const Point& p : pts) {
    if (!finite(p)) return;
    ymin = std::min(ymin, p.y);
    ymax = std::max(ymax, p.y);
  }
  constexpr int kSub = 4;  // sub-scanlines per pixel row
  std::vector<float> acc(static_cast<std::size_t>(img.width));
  std::vector<double> xs;
  const int y0 = clamped_floor(ymin, 0, img.height), y1 = clamped_floor(ymax, -1, img.height - 1);
  for (int y = y0; y <= y1; ++y) {
    std::fill(acc.begin(), acc.end(), 0.0f);
    for (int s = 0; s < kSub; ++s) {
      const double sy = y + (s + 0.5) / kSub;
      xs.clear();
      for (std::size_t i = 0, j = pts.size() - 1; i < pts.size(); j = i++) {
        const Point a = pts[j], b = pts[i];
        if ((a.y <= sy) != (b.y <= sy)) xs.push_back(a.x + (sy - a.y) * (b.x - a.x) / (b.y - a.y));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        add_span(acc, xs[k], xs[k + 1], 1.0f / kSub);
      }
    }
    for (int x = 0; x < img.width; ++x) {
      if (acc[x] > 0.0f) img.blend(x, y, c, alpha * std::min(acc[x], 1.0f));
    }
  }
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
      const double hw = std::max(0.75, size / 10.0);
      const double k = marker == Marker::kCross ? r * 0.75 : r;
      CoverageMask mask(img, p.x - r - hw - 1, p.y - r - hw - 1, p.x + r + hw + 1,
                        p.y + r + hw + 1);
      if (marker == Marker::kCross) {
        mask.add_segment({p.x - k, p.y - k}, {p.x + k, p.y + k}, hw);
        mask.add_segment({p.x - k, p.y + k}, {p.x + k, p.y - k}, hw);
      } else {
        mask.add_segment({p.x - k, p.y}, {p.x + k, p.y}, hw);
        mask.add_segment({p.x, p.y - k}, {p.x, p.y + k}, hw);
      }
      return mask.blend_into(img, c, alpha);
    }
  }
}

void blit(RgbImage& dst, const RgbImage& src, int x, int y) {
  for (int j = std::max(0, -y); j < src.height && y + j < dst.height; ++j) {
    for (int i = std::max(0, -x); i < src.width && x + i < dst.width; ++i) {
      dst.set(x + i, y + j, src.at(i, j));
    }
  }
}

void draw_scaled(RgbImage& dst, const RgbImage& src, double x0, double y0, double x1, double y1) {
  if (!(x1 > x0) || !(y1 > y0) || src.width == 0 || src.height == 0) return;
  // Pixels whose centre lies in [x0, x1) x [y0, y1): centre i + 0.5 >= x0  <=>  i >= x0 - 0.5.
  const int i0 = clamped_floor(std::ceil(x0 - 0.5), 0, dst.width);
  const int i1 = clamped_floor(std::ceil(x1 - 0.5), 0, dst.width);
  const int j0 = clamped_floor(std::ceil(y0 - 0.5), 0, dst.height);
  const int j1 = clamped_floor(std::ceil(y1 - 0.5), 0, dst.height);
  for (int j = j0; j < j1; ++j) {
    const int sy =
        std::min(src.height - 1, static_cast<int>((j + 0.5 - y0) / (y1 - y0) * src.height));
    for (int i = i0; i < i1; ++i) {
      const int sx =
          std::min(src.width - 1, static_cast<int>((i + 0.5 - x0) / (x1 - x0) * src.width));
      dst.set(i, j, src.at(sx, sy));
    }
  }
}

void write_png(const std::string& path, const RgbImage& img) {
  VDTNAV_CHECK(img.width > 0 && img.height > 0, "cannot write an empty image to " + path);
  if (stbi_write_png(path.c_str(), img.width, img.height, 3, img.rgb.data(), img.width * 3) == 0) {
    throw IoError("cannot write PNG file " + path);
  }
}

}  // namespace vdtnav::viz
