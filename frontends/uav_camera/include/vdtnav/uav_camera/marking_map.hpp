#pragma once
/// \file
/// \brief Maps of ground markings for the downward camera (thesis 3.4.3): a camera sees the
/// *boundaries* of painted markings as edges, so the VDT map is built on those boundaries.

#include <string>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/uav_camera/edge_extraction.hpp"

namespace vdtnav::uav_camera {

/// \brief The boundary cells of a marking grid: occupied cells with at least one free
/// 4-neighbour. Neighbours outside the grid count as the cell itself, so a marking that runs off
/// the map has no boundary along the map's border. Same frame as `markings`.
[[nodiscard]] OccupancyGrid<2> marking_boundaries(const OccupancyGrid<2>& markings);

/// \brief Loads a ROS map_server YAML + image of ground markings (markings are the cells
/// map_server reads as occupied, `negate` as the YAML says: with negate 1 white paint on a dark
/// runway is a marking) and builds the VDT map of their boundaries.
/// \throws IoError / FormatError from reading the map, FormatError when it has no marking.
[[nodiscard]] VdtMap2 load_marking_map(const std::string& yaml_path);

/// \brief The edge map of a photograph laid on the ground (an orthophoto): pixel (col, row) is
/// cell (col, rows - 1 - row) (image row 0 at the top, max y), one pixel per cell of
/// `resolution` metres, `origin` the lower-left corner of cell (0, 0). The edges are those of
/// edge_image() (same threshold rule as extract_edges(), no subsampling).
/// \throws ConfigError for an empty or unsupported image or a bad resolution.
[[nodiscard]] OccupancyGrid<2> edge_grid(const cv::Mat& photo, double resolution,
                                         const Eigen::Vector2d& origin,
                                         const EdgeOptions& options = {});

}  // namespace vdtnav::uav_camera
