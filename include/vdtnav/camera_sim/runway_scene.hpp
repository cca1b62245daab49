#pragma once
/// \file
/// \brief The simulated ground of Dataset 3 (thesis 3.4.3): an MBZIRC-2017-style asphalt runway
/// in grass with a figure-of-eight road marked on it in white paint, as a texture for the renderer
/// and, from the same analytic geometry, the map of markings the localizer uses.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::uav_camera {

/// \brief An 8-bit image (grey or BGR) laid on the ground plane z = 0.
///
/// Pixel (col, row) has its centre at origin + ((col + 1/2) res, (rows - 1 - row + 1/2) res):
/// row 0 is the top (largest y), `origin` the lower-left corner of the image, as in ROS
/// map_server maps.
struct GroundTexture {
  cv::Mat image;                                     ///< CV_8UC1 or CV_8UC3 (BGR)
  double resolution = 0.02;                          ///< metres per pixel
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< world (x, y) of the lower-left corner
  double background = 96.0;  ///< grey level of the ground outside the image (plain grass)

  /// \brief Bilinear grey level at world point xy (BGR is converted with the ITU-R BT.601 luma
  /// weights, as cv::cvtColor does); `background` outside the image.
  [[nodiscard]] double sample(const Eigen::Vector2d& xy) const;
  /// \return the world (x, y) of the centre of pixel (col, row).
  [[nodiscard]] Eigen::Vector2d pixel_center(int col, int row) const;
  /// \return true when xy lies on the image.
  [[nodiscard]] bool contains(const Eigen::Vector2d& xy) const;
};

/// \brief The shape and look of the runway scene. Lengths in metres.
struct RunwaySceneOptions {
  std::uint64_t seed = 1;           ///< texture noise, stains and cracks (not the geometry)
  double resolution = 0.02;         ///< metres per texture pixel
  double map_resolution = 0.05;     ///< metres per cell of `RunwayScene::markings`
  double runway_length = 100.0;     ///< along world x, centred at the origin
  double runway_width = 30.0;       ///< along world y, centred at the origin
  double grass_margin = 25.0;       ///< grass textured around the runway (beyond: plain background)
  double map_margin = 2.0;          ///< grass covered by the marking map around the runway
  double loop_radius = 12.0;        ///< radius of each loop of the eight (road centre)
  double loop_separation = 40.0;    ///< distance between the two loop centres (> 2 loop_radius)
  double lane_width = 3.0;          ///< distance between the two edge lines (line centres)
  double line_width = 0.15;         ///< width of every painted line
  double dash_length = 3.0;         ///< painted length of a centre-line dash
  double dash_gap = 3.0;            ///< gap between centre-line dashes
  double border_width = 0.1;        ///< width of the asphalt/grass boundary as a line in `markings`
  double centreline_spacing = 0.1;  ///< spacing of the points of `RunwayScene::centreline`
};

/// \brief The rendered ground and its map.
struct RunwayScene {
  GroundTexture texture;  ///< grey (CV_8UC1) texture of runway, markings and grass
  /// 1 = white paint, 0 = not; from the same analytic geometry as the texture (not thresholded
  /// from it). The runway's border (the asphalt/grass boundary, a strong edge in every image) is
  /// included as a line `border_width` wide centred on the boundary, so that the map explains
  /// the edges the camera sees there.
  OccupancyGrid<2> markings;
  /// Road centre: a closed figure-of-eight polyline (the last point connects to the first, which
  /// is not repeated), points `centreline_spacing` apart, starting at the crossing.
  std::vector<Eigen::Vector2d> centreline;
  Eigen::AlignedBox2d runway;  ///< the asphalt strip
};

/// \brief Builds the MBZIRC-2017-style scene: asphalt (dark grey, fine noise, low-contrast
/// stains and cracks) in textured grass, a figure-of-eight road (two loops joined by two straight
/// legs crossing at the origin) with two white edge lines and a dashed white centre line.
/// \throws ConfigError when the options are out of their domain or the road does not fit on
/// the runway.
[[nodiscard]] RunwayScene make_runway_scene(const RunwaySceneOptions& options = {});

/// \brief Writes `scene.markings` as PREFIX.png + PREFIX.yaml in ROS map_server format
/// (markings black = occupied, the rest white; trinary, occupied_thresh 0.65, free_thresh 0.196;
/// origin the lower-left corner of cell (0, 0), image row 0 the top).
/// \throws IoError when a file cannot be written.
void save_marking_map(const std::string& prefix, const RunwayScene& scene);

/// \brief Lays a photograph flat on the ground: its lower-left corner at `origin`, `resolution`
/// metres per pixel (a nadir view is assumed; the photo is not rectified).
/// \throws ConfigError when the photo is empty, not 8-bit grey/BGR, or resolution <= 0.
[[nodiscard]] GroundTexture photograph_texture(const cv::Mat& photo, double resolution,
                                               const Eigen::Vector2d& origin);

}  // namespace vdtnav::uav_camera
