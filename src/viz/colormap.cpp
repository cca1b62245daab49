#include "vdtnav/viz/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace vdtnav::viz {
namespace {

using Stops = std::array<Rgb, 9>;  // colours at t = 0, 1/8, ..., 1

// Viridis (van der Walt & Smith, CC0) sampled at nine evenly spaced points; piecewise-linear
// interpolation between them stays within a couple of levels of the full 256-entry table.
constexpr Stops kViridis{{{68, 1, 84},
                          {71, 45, 123},
                          {59, 82, 139},
                          {44, 114, 142},
                          {33, 145, 140},
                          {39, 173, 129},
                          {92, 200, 99},
                          {170, 220, 50},
                          {253, 231, 37}}};

// Diverging: saturated blue, through white at the midpoint, to saturated red. The two halves are
// mirror images in lightness so that +v and -v look equally strong.
constexpr Stops kBlueWhiteRed{{{33, 64, 154},
                               {67, 120, 196},
                               {130, 172, 222},
                               {196, 218, 240},
                               {255, 255, 255},
                               {244, 200, 186},
                               {229, 140, 118},
                               {203, 74, 62},
                               {160, 24, 38}}};

Rgb interpolate(const Stops& stops, double t) {
  const double s = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(s), stops.size() - 2);
  const double f = s - static_cast<double>(i);
  const auto mix = [f](std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(std::lround(a + f * (b - a)));
  };
  const Rgb a = stops[i], b = stops[i + 1];
  return {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)};
}

template <typename T, typename F>
RgbImage grid_image(const Grid<T, 2>& grid, F&& colour_of) {
  const int w = grid.size()[0], h = grid.size()[1];
  RgbImage img(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) img.set(x, h - 1 - y, colour_of(grid(Eigen::Vector2i(x, y))));
  }
  return img;
}

}  // namespace

Rgb colormap(Colormap map, double t) {
  if (std::isnan(t)) return kNanColor;
  switch (map) {
    case Colormap::kViridis:
      return interpolate(kViridis, t);
    case Colormap::kBlueWhiteRed:
      return interpolate(kBlueWhiteRed, t);
    case Colormap::kGray:
      break;
  }
  const auto v = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(t, 0.0, 1.0)));
  return {v, v, v};
}

std::pair<double, double> finite_range(const Grid<float, 2>& field) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const float v : field.values()) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, double(v));
    hi = std::max(hi, double(v));
  }
  return lo <= hi ? std::make_pair(lo, hi) : std::make_pair(0.0, 1.0);
}

RgbImage heatmap(const Grid<float, 2>& field, Colormap map, double lo, double hi, Rgb nan_color) {
  return grid_image(field, [&](float v) {
    if (!std::isfinite(v)) return nan_color;
    return colormap(map, hi > lo ? (v - lo) / (hi - lo) : 0.5);
  });
}

RgbImage occupancy_image(const Grid<std::uint8_t, 2>& occupancy) {
  return grid_image(occupancy, [](std::uint8_t v) { return v != 0 ? kBlack : kWhite; });
}

RgbImage occupancy_image(const Grid<std::int8_t, 2>& ros_cells) {
  return grid_image(ros_cells, [](std::int8_t v) {
    const auto g = static_cast<std::uint8_t>(v < 0 ? 205 : 255 - 2.55 * std::min<int>(v, 100));
    return Rgb{g, g, g};
  });
}

}  // namespace vdtnav::viz
