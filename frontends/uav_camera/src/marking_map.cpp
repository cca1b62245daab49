#include "vdtnav/uav_camera/marking_map.hpp"

#include <cstdint>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/ros_map.hpp"

namespace vdtnav::uav_camera {

OccupancyGrid<2> marking_boundaries(const OccupancyGrid<2>& markings) {
  const Eigen::Vector2i size = markings.size();
  OccupancyGrid<2> out(size, markings.frame(), 0);
  const int nx = size.x();
  const int ny = size.y();
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      if (markings(Eigen::Vector2i(x, y)) == 0) continue;
      // A neighbour outside the grid is not free (the map border is not a marking's edge).
      const bool boundary = (x > 0 && markings(Eigen::Vector2i(x - 1, y)) == 0) ||
                            (x + 1 < nx && markings(Eigen::Vector2i(x + 1, y)) == 0) ||
                            (y > 0 && markings(Eigen::Vector2i(x, y - 1)) == 0) ||
                            (y + 1 < ny && markings(Eigen::Vector2i(x, y + 1)) == 0);
      if (boundary) out(Eigen::Vector2i(x, y)) = 1;
    }
  }
  return out;
}

VdtMap2 load_marking_map(const std::string& yaml_path) {
  const RosMap map = load_ros_map(yaml_path);
  const OccupancyGrid<2> boundaries = marking_boundaries(occupancy(map));
  bool any = false;
  for (std::size_t i = 0; i < boundaries.num_cells() && !any; ++i) any = boundaries[i] != 0;
  if (!any) {
    throw FormatError(yaml_path, 0,
                      "no ground marking: expected occupied cells (p > occupied_thresh; with "
                      "negate: 1 the white pixels) with a free neighbour in '" +
                          map.image_path + "'");
  }
  return VdtMap2::build(boundaries);
}

OccupancyGrid<2> edge_grid(const cv::Mat& photo, double resolution, const Eigen::Vector2d& origin,
                           const EdgeOptions& options) {
  const cv::Mat edges = edge_image(photo, options);
  const GridFrame<2> frame(resolution, origin);
  OccupancyGrid<2> out(Eigen::Vector2i(edges.cols, edges.rows), frame, 0);
  for (int r = 0; r < edges.rows; ++r) {
    const std::uint8_t* row = edges.ptr<std::uint8_t>(r);
    for (int c = 0; c < edges.cols; ++c) {
      if (row[c] != 0) out(Eigen::Vector2i(c, edges.rows - 1 - r)) = 1;
    }
  }
  return out;
}

}  // namespace vdtnav::uav_camera
