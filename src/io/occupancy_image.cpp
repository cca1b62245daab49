#include "vdtnav/io/occupancy_image.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

OccupancyGrid<2> load_occupancy_image(const std::string& path, const Eigen::Vector2d& size,
                                      double resolution, double dark_threshold) {
  VDTNAV_CHECK(size.allFinite() && (size.array() > 0).all(), "image map size must be > 0 metres");
  VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0, "image map resolution must be > 0");
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open the map image");
  int w = 0, h = 0, channels = 0;
  std::unique_ptr<unsigned char, void (*)(void*)> px(stbi_load(path.c_str(), &w, &h, &channels, 1),
                                                     stbi_image_free);
  if (!px)
    throw FormatError(path, 0,
                      std::string("not a decodable PNG/PGM image (") + stbi_failure_reason() + ")");

  const Eigen::Vector2i cells((size.array() / resolution).round().cast<int>().max(2));
  OccupancyGrid<2> grid(cells, GridFrame<2>(resolution, Eigen::Vector2d::Zero()), 0);
  const double px_w = size.x() / w, px_h = size.y() / h;  // metres per pixel
  const auto limit = static_cast<unsigned char>(std::clamp(dark_threshold, 0.0, 1.0) * 255.0);
  for (int row = 0; row < h; ++row) {
    const double y0 = (h - 1 - row) * px_h;  // image row 0 is the top of the map
    for (int col = 0; col < w; ++col) {
      if (px.get()[static_cast<std::size_t>(row) * w + col] >= limit) continue;
      const double x0 = col * px_w;
      // Every cell this pixel overlaps becomes occupied.
      const int i0 = std::max(0, static_cast<int>(std::floor(x0 / resolution)));
      const int i1 =
          std::min(cells.x() - 1, static_cast<int>(std::ceil((x0 + px_w) / resolution)) - 1);
      const int j0 = std::max(0, static_cast<int>(std::floor(y0 / resolution)));
      const int j1 =
          std::min(cells.y() - 1, static_cast<int>(std::ceil((y0 + px_h) / resolution)) - 1);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) grid(Eigen::Vector2i(i, j)) = 1;
    }
  }
  return grid;
}

}  // namespace vdtnav
