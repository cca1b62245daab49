#include "vdtnav/viz/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "raster.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::viz {
namespace {

using detail::Font;
using detail::HAlign;
using detail::VAlign;

constexpr Rgb kGridColor{224, 224, 224};
constexpr Rgb kReferenceColor{80, 80, 80};
constexpr Rgb kLegendEdge{170, 170, 170};
constexpr double kAutoMargin = 0.05;  // fraction of the data range added on each side

/// A growing interval of finite values.
struct Span {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();

  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  [[nodiscard]] bool empty() const { return !(lo <= hi); }
};

/// The data span plus the auto margin; a single value gets +-10 % (or +-1 around 0).
std::pair<double, double> padded(const Span& s) {
  if (s.hi == s.lo) {
    const double d = s.lo == 0.0 ? 1.0 : 0.1 * std::abs(s.lo);
    return {s.lo - d, s.hi + d};
  }
  const double m = kAutoMargin * (s.hi - s.lo);
  return {s.lo - m, s.hi + m};
}

/// Calls f(begin, end) for each maximal run of indices i where ok(i).
template <typename Ok, typename F>
void for_each_run(std::size_t n, Ok&& ok, F&& f) {
  for (std::size_t i = 0; i < n;) {
    if (!ok(i)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < n && ok(j)) ++j;
    f(i, j);
    i = j;
  }
}

int max_label_width(const std::vector<double>& ticks, const Font& font) {
  int w = 0;
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
  for (const double t : ticks) w = std::max(w, font.width(format_tick(t, step)));
  return w;
}

/// Pixel row/column of a tick at continuous coordinate v, kept on the frame [lo - 1, hi].
int tick_pixel(double v, int lo, int hi) {
  return static_cast<int>(std::floor(std::clamp(v, double(lo - 1), double(hi))));
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int max_ticks) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return {};
  if (hi == lo) return {lo};
  max_ticks = std::max(max_ticks, 2);
  constexpr double kEps = 1e-9;  // tolerance, in steps, for ticks exactly on the range ends
  // step = m 10^e; ticks are computed as (i m) 10^e or (i m) / 10^-e, exact for e.g. 0.6.
  for (int e = static_cast<int>(std::floor(std::log10((hi - lo) / max_ticks)));; ++e) {
    const double p = std::pow(10.0, std::abs(e));
    for (const double m : {1.0, 2.0, 5.0}) {
      const double step = e >= 0 ? m * p : m / p;
      const double first = std::ceil(lo / step - kEps), last = std::floor(hi / step + kEps);
      if (last - first + 1 > max_ticks) continue;
      std::vector<double> ticks;
      for (double i = first; i <= last; ++i) ticks.push_back(e >= 0 ? i * m * p : i * m / p);
      return ticks;
    }
  }
}

std::string format_tick(double value, double step) {
  step = std::abs(step);
  if (!std::isfinite(value)) return "nan";
  if (value == 0.0 || !(step > 0.0) || std::abs(value) < 1e-9 * step) return "0";
  const int e_step = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  char buf[48];
  if (e_step >= -3 && e_step <= 4) {
    std::snprintf(buf, sizeof buf, "%.*f", std::max(0, -e_step), value);
    return buf;
  }
  // Scientific: mantissa digits down to the step's decade, trailing zeros dropped.
  const int e = static_cast<int>(std::floor(std::log10(std::abs(value)) + 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", std::clamp(e - e_step, 0, 6), value / std::pow(10.0, e));
  std::string mantissa = buf;
  if (mantissa.find('.') != std::string::npos) {
    mantissa.erase(mantissa.find_last_not_of('0') + 1);
    if (mantissa.back() == '.') mantissa.pop_back();
  }
  return mantissa + "e" + std::to_string(e);
}

// ---------------------------------------------------------------- Axes: content

Axes& Axes::title(std::string text) {
  title_ = std::move(text);
  return *this;
}
Axes& Axes::xlabel(std::string text) {
  xlabel_ = std::move(text);
  return *this;
}
Axes& Axes::ylabel(std::string text) {
  ylabel_ = std::move(text);
  return *this;
}

Axes& Axes::add(Kind kind, std::vector<double> x, std::vector<double> y, std::vector<double> y2,
                const Style& style) {
  Rgb color = kReferenceColor;
  if (style.color) {
    color = *style.color;
  } else if (kind == Kind::kBand) {
    color = kColorCycle[next_color_ % kColorCycle.size()];  // the next line's colour
  } else if (kind == Kind::kLine || kind == Kind::kScatter) {
    color = kColorCycle[next_color_++ % kColorCycle.size()];
  }
  const double alpha = std::clamp(style.alpha.value_or(kind == Kind::kBand ? 0.25 : 1.0), 0.0, 1.0);
  series_.push_back({kind, std::move(x), std::move(y), std::move(y2), style, color, alpha});
  return *this;
}

Axes& Axes::line(const std::vector<double>& xs, const std::vector<double>& ys, const Style& style) {
  VDTNAV_CHECK(xs.size() == ys.size(), "Axes::line: xs and ys differ in size");
  return add(Kind::kLine, xs, ys, {}, style);
}

Axes& Axes::scatter(const std::vector<double>& xs, const std::vector<double>& ys,
                    const Style& style) {
  VDTNAV_CHECK(xs.size() == ys.size(), "Axes::scatter: xs and ys differ in size");
  return add(Kind::kScatter, xs, ys, {}, style);
}

Axes& Axes::band(const std::vector<double>& xs, const std::vector<double>& lo,
                 const std::vector<double>& hi, const Style& style) {
  VDTNAV_CHECK(xs.size() == lo.size() && xs.size() == hi.size(),
               "Axes::band: xs, lo and hi differ in size");
  return add(Kind::kBand, xs, lo, hi, style);
}

Axes& Axes::hline(double y, const Style& style) { return add(Kind::kHLine, {}, {y}, {}, style); }
Axes& Axes::vline(double x, const Style& style) { return add(Kind::kVLine, {x}, {}, {}, style); }

Axes& Axes::image(const RgbImage& img, double x_min, double x_max, double y_min, double y_max) {
  VDTNAV_CHECK(x_min < x_max && y_min < y_max, "Axes::image: the extent must have min < max");
  images_.push_back({img, x_min, x_max, y_min, y_max});
  return *this;
}

Axes& Axes::colorbar(Colormap map, double lo, double hi, std::string label) {
  VDTNAV_CHECK(std::isfinite(lo) && std::isfinite(hi) && lo < hi, "Axes::colorbar: need lo < hi");
  colorbar_ = Colorbar{map, lo, hi, std::move(label)};
  return *this;
}

Axes& Axes::equal_aspect(bool on) {
  equal_aspect_ = on;
  return *this;
}
Axes& Axes::xlim(double lo, double hi) {
  VDTNAV_CHECK(std::isfinite(lo) && std::isfinite(hi) && lo < hi, "Axes::xlim: need lo < hi");
  xlim_ = {lo, hi};
  return *this;
}
Axes& Axes::ylim(double lo, double hi) {
  VDTNAV_CHECK(std::isfinite(lo) && std::isfinite(hi) && lo < hi, "Axes::ylim: need lo < hi");
  ylim_ = {lo, hi};
  return *this;
}
Axes& Axes::grid(bool on) {
  grid_ = on;
  return *this;
}
Axes& Axes::legend(LegendLocation where) {
  legend_ = where;
  return *this;
}

// ---------------------------------------------------------------- Axes: layout and drawing

Point Axes::to_pixel(double x, double y) const {
  return {area_.x + (x - x0_) / (x1_ - x0_) * area_.width,
          area_.y + (y1_ - y) / (y1_ - y0_) * area_.height};
}

Point Axes::to_data(Point p) const {
  return {x0_ + (p.x - area_.x) / area_.width * (x1_ - x0_),
          y1_ - (p.y - area_.y) / area_.height * (y1_ - y0_)};
}

void Axes::auto_limits() {
  Span xs, ys, xi, yi;
  for (const Series& s : series_) {
    if (s.kind == Kind::kHLine) ys.add(s.y[0]);
    if (s.kind == Kind::kVLine) xs.add(s.x[0]);
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      xs.add(s.x[i]);
      ys.add(s.y[i]);
      if (s.kind == Kind::kBand) ys.add(s.y2[i]);
    }
  }
  for (const Background& b : images_) {
    xi.add(b.x_min);
    xi.add(b.x_max);
    yi.add(b.y_min);
    yi.add(b.y_max);
  }
  // Data get a margin, images none (like imshow): the margin shows only where data leave the image.
  const auto limits = [](const Span& data, const Span& img) {
    if (data.empty()) {
      return img.empty() ? std::make_pair(0.0, 1.0) : std::make_pair(img.lo, img.hi);
    }
    const auto [lo, hi] = padded(data);
    if (img.empty()) return std::make_pair(lo, hi);
    return std::make_pair(data.lo < img.lo ? lo : img.lo, data.hi > img.hi ? hi : img.hi);
  };
  std::tie(x0_, x1_) = xlim_.value_or(limits(xs, xi));
  std::tie(y0_, y1_) = ylim_.value_or(limits(ys, yi));
}

void Axes::draw(RgbImage& canvas, const PixelRect& cell, int s) {
  auto_limits();
  const Font font(s);
  const int pad = 6 * s, tick = 4 * s, gap = 3 * s, line = font.line_height();
  const auto y_ticks_for = [&](int h, double lo, double hi) {
    return nice_ticks(lo, hi, std::clamp(h / (2 * line), 3, 8));
  };
  // Vertical layout first: the height fixes the y ticks, whose labels fix the left margin.
  const int top = pad + (title_.empty() ? 0 : line + pad);
  const int bottom = tick + gap + font.box_height() + (xlabel_.empty() ? 0 : pad + line) + pad;
  const int h = std::max(cell.height - top - bottom, 1);
  const int left = pad + (ylabel_.empty() ? 0 : line + pad) +
                   max_label_width(y_ticks_for(h, y0_, y1_), font) + gap + tick;
  int right = pad + 3 * font.advance();  // room for the last x label's overhang
  if (colorbar_) {
    const int cbw = max_label_width(y_ticks_for(h, colorbar_->lo, colorbar_->hi), font);
    right += 8 * s + 10 * s + tick + gap + cbw + (colorbar_->label.empty() ? 0 : pad + line);
  }
  area_ = {cell.x + left, cell.y + top, std::max(cell.width - left - right, 1), h};
  if (equal_aspect_) {
    // Shrink the box so that both axes have the same units per pixel, then widen the limits by
    // the rounding (< half a pixel) so that the ratio is exact.
    const double ux = (x1_ - x0_) / area_.width, uy = (y1_ - y0_) / area_.height;
    const double u = std::max(ux, uy);
    if (ux > uy) {
      const int nh = std::max(1, static_cast<int>(std::lround((y1_ - y0_) / u)));
      area_.y += (area_.height - nh) / 2;
      area_.height = nh;
    } else {
      const int nw = std::max(1, static_cast<int>(std::lround((x1_ - x0_) / u)));
      area_.x += (area_.width - nw) / 2;
      area_.width = nw;
    }
    const double cx = 0.5 * (x0_ + x1_), cy = 0.5 * (y0_ + y1_);
    x0_ = cx - 0.5 * u * area_.width;
    x1_ = cx + 0.5 * u * area_.width;
    y0_ = cy - 0.5 * u * area_.height;
    y1_ = cy + 0.5 * u * area_.height;
  }
  const PixelRect& a = area_;
  // Ticks within half a pixel outside the limits still sit on the frame (equal-aspect rounding).
  const double hx = 0.5 * (x1_ - x0_) / a.width, hy = 0.5 * (y1_ - y0_) / a.height;
  const std::vector<double> yt = y_ticks_for(a.height, y0_ - hy, y1_ + hy);
  std::vector<double> xt;
  for (int m = 8; m >= 2; --m) {  // as many x ticks as fit with their labels apart
    xt = nice_ticks(x0_ - hx, x1_ + hx, m);
    const int need = static_cast<int>(xt.size()) * (max_label_width(xt, font) + 2 * font.advance());
    if (need <= a.width) break;
  }

  // Plot area: drawn on its own image, which clips everything to it.
  RgbImage plot(a.width, a.height, kWhite);
  for (const Background& b : images_) {
    const Point p = to_pixel(b.x_min, b.y_max), q = to_pixel(b.x_max, b.y_min);
    draw_scaled(plot, b.img, p.x - a.x, p.y - a.y, q.x - a.x, q.y - a.y);
  }
  if (grid_.value_or(images_.empty())) {
    for (const double t : xt) {
      const int px = tick_pixel(to_pixel(t, 0).x, a.x, a.x + a.width) - a.x;
      fill_rect(plot, {px, 0, 1, a.height}, kGridColor);
    }
    for (const double t : yt) {
      const int py = tick_pixel(to_pixel(0, t).y, a.y, a.y + a.height) - a.y;
      fill_rect(plot, {0, py, a.width, 1}, kGridColor);
    }
  }
  for (const Series& series : series_) draw_series(plot, series);
  blit(canvas, plot, a.x, a.y);
  draw_rect(canvas, {a.x - 1, a.y - 1, a.width + 2, a.height + 2}, kBlack);

  // Ticks and their labels, outside the frame.
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  const int tw = std::max(1, s / 2);
  for (const double t : xt) {
    const int px = tick_pixel(to_pixel(t, 0).x, a.x, a.x + a.width);
    fill_rect(canvas, {px, a.y + a.height + 1, tw, tick}, kBlack);
    font.draw(canvas, px, a.y + a.height + 1 + tick + gap, format_tick(t, xstep), kBlack,
              HAlign::kCenter, VAlign::kTop);
  }
  int ylw = 0;
  for (const double t : yt) {
    const int py = tick_pixel(to_pixel(0, t).y, a.y, a.y + a.height);
    const std::string label = format_tick(t, ystep);
    ylw = std::max(ylw, font.width(label));
    fill_rect(canvas, {a.x - 1 - tick, py, tick, tw}, kBlack);
    font.draw(canvas, a.x - 1 - tick - gap, py, label, kBlack, HAlign::kRight, VAlign::kMiddle);
  }
  const int cx = a.x + a.width / 2, cy = a.y + a.height / 2;
  if (!title_.empty()) {
    Font(s, true).draw(canvas, cx, a.y - 1 - pad, title_, kBlack, HAlign::kCenter,
                       VAlign::kBaseline);
  }
  if (!xlabel_.empty()) {
    font.draw(canvas, cx, a.y + a.height + 1 + tick + gap + font.box_height() + pad, xlabel_,
              kBlack, HAlign::kCenter, VAlign::kTop);
  }
  if (!ylabel_.empty()) {
    font.draw(canvas, a.x - 1 - tick - gap - ylw - pad - font.box_height(), cy, ylabel_, kBlack,
              HAlign::kCenter, VAlign::kTop, true);
  }
  draw_legend(canvas, s);
  draw_colorbar(canvas, s);
}

void Axes::draw_series(RgbImage& plot, const Series& s) const {
  const auto local = [this](double x, double y) {
    const Point p = to_pixel(x, y);
    return Point{p.x - area_.x, p.y - area_.y};
  };
  const auto finite_xy = [&s](std::size_t i) {
    return std::isfinite(s.x[i]) && std::isfinite(s.y[i]);
  };
  const Style& st = s.style;
  switch (s.kind) {
    case Kind::kLine:
      for_each_run(s.x.size(), finite_xy, [&](std::size_t b, std::size_t e) {
        std::vector<Point> pts;
        for (std::size_t i = b; i < e; ++i) pts.push_back(local(s.x[i], s.y[i]));
        if (st.line_width > 0) draw_polyline(plot, pts, s.color, st.line_width, s.alpha, st.dashed);
        for (const Point& p : pts) {
          draw_marker(plot, p, st.marker, st.marker_size, s.color, s.alpha);
        }
      });
      return;
    case Kind::kScatter:
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!finite_xy(i)) continue;
        draw_marker(plot, local(s.x[i], s.y[i]),
                    st.marker == Marker::kNone ? Marker::kCircle : st.marker, st.marker_size,
                    s.color, s.alpha);
      }
      return;
    case Kind::kBand: {
      const auto finite3 = [&](std::size_t i) { return finite_xy(i) && std::isfinite(s.y2[i]); };
      for_each_run(s.x.size(), finite3, [&](std::size_t b, std::size_t e) {
        std::vector<Point> poly;
        for (std::size_t i = b; i < e; ++i) poly.push_back(local(s.x[i], s.y2[i]));
        for (std::size_t i = e; i-- > b;) poly.push_back(local(s.x[i], s.y[i]));
        fill_polygon(plot, poly, s.color, s.alpha);
      });
      return;
    }
    case Kind::kHLine: {
      const double y = local(0.0, s.y[0]).y;
      draw_polyline(plot, {{0.0, y}, {double(plot.width), y}}, s.color, st.line_width, s.alpha,
                    st.dashed);
      return;
    }
    case Kind::kVLine: {
      const double x = local(s.x[0], 0.0).x;
      draw_polyline(plot, {{x, 0.0}, {x, double(plot.height)}}, s.color, st.line_width, s.alpha,
                    st.dashed);
      return;
    }
  }
}

void Axes::draw_legend(RgbImage& canvas, int s) const {
  const Font font(s);
  std::vector<const Series*> entries;
  int text_w = 0;
  for (const Series& series : series_) {
    if (series.style.label.empty()) continue;
    entries.push_back(&series);
    text_w = std::max(text_w, font.width(series.style.label));
  }
  if (entries.empty() || legend_ == LegendLocation::kNone) return;
  const int pad = 4 * s, row = font.line_height() + s, sample = 14 * s, inset = 6 * s;
  const int w = pad + sample + pad + text_w + pad;
  const int h = 2 * pad + static_cast<int>(entries.size()) * row - s;
  const bool left = legend_ == LegendLocation::kUpperLeft || legend_ == LegendLocation::kLowerLeft;
  const bool up = legend_ == LegendLocation::kUpperLeft || legend_ == LegendLocation::kUpperRight;
  const PixelRect box{left ? area_.x + inset : area_.x + area_.width - inset - w,
                      up ? area_.y + inset : area_.y + area_.height - inset - h, w, h};
  fill_rect(canvas, box, kWhite, 0.85);
  draw_rect(canvas, box, kLegendEdge);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Series& e = *entries[k];
    const double x0 = box.x + pad, x1 = x0 + sample, xm = 0.5 * (x0 + x1);
    const int cy = box.y + pad + static_cast<int>(k) * row + font.cap_height() / 2;
    const double y = cy + 0.5;
    if (e.kind == Kind::kBand) {
      fill_rect(canvas, {box.x + pad, cy - row / 3, sample, 2 * row / 3}, e.color, e.alpha);
    } else if (e.kind == Kind::kScatter) {
      const Marker m = e.style.marker == Marker::kNone ? Marker::kCircle : e.style.marker;
      draw_marker(canvas, {xm, y}, m, e.style.marker_size, e.color, e.alpha);
    } else {
      draw_polyline(canvas, {{x0, y}, {x1, y}}, e.color, e.style.line_width, e.alpha,
                    e.style.dashed);
      draw_marker(canvas, {xm, y}, e.style.marker, e.style.marker_size, e.color, e.alpha);
    }
    font.draw(canvas, static_cast<int>(x1) + pad, cy, e.style.label, kBlack, HAlign::kLeft,
              VAlign::kMiddle);
  }
}

void Axes::draw_colorbar(RgbImage& canvas, int s) const {
  if (!colorbar_) return;
  const Colorbar& cb = *colorbar_;
  const Font font(s);
  const int tick = 4 * s, gap = 3 * s, pad = 6 * s;
  const PixelRect bar{area_.x + area_.width + 1 + 8 * s, area_.y, 10 * s, area_.height};
  RgbImage ramp(1, 256);
  for (int k = 0; k < 256; ++k) ramp.set(0, k, colormap(cb.map, 1.0 - (k + 0.5) / 256.0));
  draw_scaled(canvas, ramp, bar.x, bar.y, bar.x + bar.width, bar.y + bar.height);
  draw_rect(canvas, {bar.x - 1, bar.y - 1, bar.width + 2, bar.height + 2}, kBlack);
  const std::vector<double> ticks =
      nice_ticks(cb.lo, cb.hi, std::clamp(bar.height / (2 * font.line_height()), 3, 8));
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
  const int xt = bar.x + bar.width + 1;
  int label_w = 0;
  for (const double t : ticks) {
    const double y = bar.y + (cb.hi - t) / (cb.hi - cb.lo) * bar.height;
    const int py = tick_pixel(y, bar.y, bar.y + bar.height);
    const std::string label = format_tick(t, step);
    label_w = std::max(label_w, font.width(label));
    fill_rect(canvas, {xt, py, tick, std::max(1, s / 2)}, kBlack);
    font.draw(canvas, xt + tick + gap, py, label, kBlack, HAlign::kLeft, VAlign::kMiddle);
  }
  if (!cb.label.empty()) {
    font.draw(canvas, xt + tick + gap + label_w + pad, bar.y + bar.height / 2, cb.label, kBlack,
              HAlign::kCenter, VAlign::kTop, true);
  }
}

// ---------------------------------------------------------------- Figure

Figure::Figure(int width_px, int height_px, int rows, int cols)
    : width_(width_px), height_(height_px), rows_(rows), cols_(cols) {
  VDTNAV_CHECK(width_px >= 1 && height_px >= 1 && rows >= 1 && cols >= 1,
               "Figure: size, rows and cols must be >= 1");
  font_scale_ = std::max(1, std::min(width_px, height_px) / 400);
  axes_.resize(static_cast<std::size_t>(rows) * cols);
}

Axes& Figure::axes(int row, int col) {
  VDTNAV_CHECK(row >= 0 && row < rows_ && col >= 0 && col < cols_,
               "Figure::axes: row or column out of range");
  return axes_[static_cast<std::size_t>(row) * cols_ + col];
}

Figure& Figure::title(std::string text) {
  title_ = std::move(text);
  return *this;
}

Figure& Figure::font_scale(int scale) {
  VDTNAV_CHECK(scale >= 1, "Figure::font_scale: scale must be >= 1");
  font_scale_ = scale;
  return *this;
}

RgbImage Figure::render() {
  RgbImage canvas(width_, height_, kWhite);
  const int s = font_scale_, pad = 6 * s;
  int top = 0;
  if (!title_.empty()) {
    const Font bold(s, true);
    bold.draw(canvas, width_ / 2, pad, title_, kBlack, HAlign::kCenter, VAlign::kTop);
    top = pad + bold.line_height();
  }
  for (int r = 0; r < rows_; ++r) {
    for (int c = 0; c < cols_; ++c) {
      const int x0 = c * width_ / cols_, x1 = (c + 1) * width_ / cols_;
      const int y0 = top + r * (height_ - top) / rows_,
                y1 = top + (r + 1) * (height_ - top) / rows_;
      axes(r, c).draw(canvas, {x0, y0, x1 - x0, y1 - y0}, s);
    }
  }
  return canvas;
}

void Figure::save_png(const std::string& path) { write_png(path, render()); }

}  // namespace vdtnav::viz
