#pragma once
/// \file
/// \brief A small matplotlib-like figure API: `Figure` of `Axes` with lines, scatters, bands,
/// background images in data coordinates, nice ticks, grid, legend and colorbar, saved as PNG.
///
/// \code
///   viz::Figure fig(1200, 800, 1, 2);
///   fig.axes(0, 0).image(map_png, x0, x1, y0, y1).equal_aspect().line(xs, ys, {});
///   fig.axes(0, 1).band(t, lo, hi, viz::Style().with_label("2 sigma")).line(t, err, {});
///   fig.save_png("out.png");
/// \endcode

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/image.hpp"

namespace vdtnav::viz {

/// \brief Default colour cycle: the Okabe-Ito palette (distinguishable with colour-blindness)
/// without its yellow, which is unreadable on white.
inline constexpr std::array<Rgb, 7> kColorCycle{{{0, 114, 178},
                                                 {213, 94, 0},
                                                 {0, 158, 115},
                                                 {204, 121, 167},
                                                 {230, 159, 0},
                                                 {86, 180, 233},
                                                 {0, 0, 0}}};

/// \brief How a series is drawn. Chain the setters: `Style().with_color(c).with_label("EKF")`.
struct Style {
  std::optional<Rgb> color;  ///< unset: the next colour of the axes' cycle
  double line_width = 2.0;   ///< pixels
  Marker marker = Marker::kNone;
  double marker_size = 8.0;     ///< marker diameter in pixels
  std::optional<double> alpha;  ///< opacity; unset: 1, or 0.25 for bands
  bool dashed = false;
  std::string label;  ///< shown in the legend when not empty

  Style& with_color(Rgb c) {
    color = c;
    return *this;
  }
  Style& with_width(double w) {
    line_width = w;
    return *this;
  }
  Style& with_marker(Marker m, double size = 8.0) {
    marker = m;
    marker_size = size;
    return *this;
  }
  Style& with_alpha(double a) {
    alpha = a;
    return *this;
  }
  Style& with_dashes(bool on = true) {
    dashed = on;
    return *this;
  }
  Style& with_label(std::string text) {
    label = std::move(text);
    return *this;
  }
};

/// \brief Where the legend box goes inside the plot area.
enum class LegendLocation { kUpperRight, kUpperLeft, kLowerLeft, kLowerRight, kNone };

/// \return tick values i * step covering [lo, hi], step = {1, 2, 5} x 10^k the smallest such that
/// at most `max_ticks` ticks fall in the range (>= 3 of them when max_ticks >= 8). Empty if the
/// range is not finite; {lo} if lo == hi.
[[nodiscard]] std::vector<double> nice_ticks(double lo, double hi, int max_ticks = 8);

/// \return a compact label for tick `value` on an axis with tick spacing `step`: fixed notation
/// with as many decimals as the step needs ("0.005", "-2.5", "1200"), or "1e-4" / "2.5e6" style
/// when the step is below 1e-3 or at least 1e5 (decided by the step, so one axis never mixes).
[[nodiscard]] std::string format_tick(double value, double step);

/// \brief One plot of a Figure. Setters return *this for chaining. The pixel mapping (plot_area,
/// to_pixel, to_data) is set when the axes are drawn (Figure::render or save_png).
class Axes {
 public:
  Axes& title(std::string text);
  Axes& xlabel(std::string text);
  Axes& ylabel(std::string text);

  /// \brief Polyline through (xs[i], ys[i]); non-finite points break the line.
  Axes& line(const std::vector<double>& xs, const std::vector<double>& ys, const Style& style = {});
  /// \brief Markers at (xs[i], ys[i]) (a circle unless style.marker says otherwise).
  Axes& scatter(const std::vector<double>& xs, const std::vector<double>& ys,
                const Style& style = {});
  /// \brief Filled region between lo[i] and hi[i] over xs[i] (e.g. a +-2 sigma envelope).
  /// Without a colour it takes the colour the *next* line will get: draw a band just before its
  /// line and both match.
  Axes& band(const std::vector<double>& xs, const std::vector<double>& lo,
             const std::vector<double>& hi, const Style& style = {});
  /// \brief Horizontal line at y across the plot (dark gray unless coloured).
  Axes& hline(double y, const Style& style = {});
  /// \brief Vertical line at x across the plot (dark gray unless coloured).
  Axes& vline(double x, const Style& style = {});
  /// \brief Background image spanning [x_min, x_max] x [y_min, y_max] in data coordinates, its
  /// row 0 at y_max (as heatmap() and occupancy_image() produce for world y up). Copied.
  Axes& image(const RgbImage& img, double x_min, double x_max, double y_min, double y_max);
  /// \brief Colorbar on the right of the plot for values lo..hi of `map`.
  Axes& colorbar(Colormap map, double lo, double hi, std::string label = {});

  /// \brief Same data units per pixel on both axes (the plot box shrinks to fit).
  Axes& equal_aspect(bool on = true);
  /// \brief Fixed x range; otherwise the data range plus 5 % (images: their extent exactly).
  Axes& xlim(double lo, double hi);
  Axes& ylim(double lo, double hi);
  /// \brief Grid lines at the ticks; default on, except for axes showing an image.
  Axes& grid(bool on);
  /// \brief Legend of the labelled series; default upper right.
  Axes& legend(LegendLocation where);

  /// \return the plot area in figure pixels (frame excluded).
  [[nodiscard]] const PixelRect& plot_area() const { return area_; }
  /// \return the x and y data ranges shown, {lo, hi} each.
  [[nodiscard]] std::pair<double, double> x_range() const { return {x0_, x1_}; }
  [[nodiscard]] std::pair<double, double> y_range() const { return {y0_, y1_}; }
  /// \return the figure pixel position (continuous, see image.hpp) of data point (x, y).
  [[nodiscard]] Point to_pixel(double x, double y) const;
  /// \return the data point (as .x, .y) at figure pixel position p; inverse of to_pixel.
  [[nodiscard]] Point to_data(Point p) const;

  /// \brief Lays the axes out in `cell` of `canvas` and draws them; text at `font_scale`.
  void draw(RgbImage& canvas, const PixelRect& cell, int font_scale);

 private:
  enum class Kind { kLine, kScatter, kBand, kHLine, kVLine };
  struct Series {
    Kind kind;
    std::vector<double> x, y, y2;
    Style style;
    Rgb color;
    double alpha;
  };
  struct Background {
    RgbImage img;
    double x_min, x_max, y_min, y_max;
  };
  struct Colorbar {
    Colormap map;
    double lo, hi;
    std::string label;
  };

  Axes& add(Kind kind, std::vector<double> x, std::vector<double> y, std::vector<double> y2,
            const Style& style);
  void auto_limits();
  void draw_series(RgbImage& area, const Series& s) const;
  void draw_legend(RgbImage& canvas, int scale) const;
  void draw_colorbar(RgbImage& canvas, int scale) const;

  std::string title_, xlabel_, ylabel_;
  std::vector<Series> series_;
  std::vector<Background> images_;
  std::optional<Colorbar> colorbar_;
  std::optional<std::pair<double, double>> xlim_, ylim_;
  std::optional<bool> grid_;
  bool equal_aspect_ = false;
  LegendLocation legend_ = LegendLocation::kUpperRight;
  std::size_t next_color_ = 0;
  // Layout, set by draw().
  PixelRect area_;
  double x0_ = 0.0, x1_ = 1.0, y0_ = 0.0, y1_ = 1.0;
};

/// \brief A grid of rows x cols Axes on a white canvas.
class Figure {
 public:
  /// \throws ConfigError unless all arguments are >= 1.
  Figure(int width_px = 1200, int height_px = 800, int rows = 1, int cols = 1);

  /// \return the axes in row `row`, column `col` (0-based); throws ConfigError if out of range.
  [[nodiscard]] Axes& axes(int row = 0, int col = 0);
  /// \brief A title above all the axes.
  Figure& title(std::string text);
  /// \brief Text magnification; default max(1, min(width, height) / 400), i.e. 2 at 1200x800.
  Figure& font_scale(int scale);

  /// \brief Lays out and draws every axes; afterwards their pixel mappings are valid.
  [[nodiscard]] RgbImage render();
  /// \brief render() then write_png(); throws IoError naming the path on failure.
  void save_png(const std::string& path);

 private:
  int width_, height_, rows_, cols_, font_scale_;
  std::string title_;
  std::vector<Axes> axes_;
};

}  // namespace vdtnav::viz
