// The UAV study's scenario: the camera, the runway scene (or a photograph laid on the ground),
// the marking map it localizes on and the simulated flight.
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "uav_study.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/uav_camera/marking_map.hpp"

namespace uav_study {

using namespace vdtnav;
using namespace vdtnav::uav_camera;

namespace {

/// A camera like the thesis's perspective camera: 640 x 480, ~60 degree horizontal field of view,
/// a mild barrel distortion.
CameraCalibration default_camera() {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  const double f = 0.5 * c.width / std::tan(0.5 * 60.0 * kPi / 180.0);  // 554 px
  c.camera_matrix << f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0;
  c.distortion = {-0.12, 0.03, 0.0005, -0.0003, 0.0};
  return c;
}

}  // namespace

Scenario make_scenario(const std::string& out, std::uint64_t seed, std::size_t frames,
                       double altitude, const std::string& texture_path) {
  const bool photo = !texture_path.empty();
  const CameraCalibration calibration = default_camera();
  const UavRig rig;

  // ------------------------------------------------------------------ scene and map
  std::printf("[scene] %s\n", photo ? ("photograph " + texture_path).c_str()
                                    : "figure-of-eight road on a runway (generated)");
  RunwaySceneOptions so;
  so.seed = seed;
  double photo_resolution = 0.0;
  if (photo) {
    // The eight of the flight, scaled to fit inside the photograph laid on the ground.
    so.runway_length = 52.0;
    so.runway_width = 24.0;
    so.loop_radius = 7.0;
    so.loop_separation = 22.0;
    so.grass_margin = 2.0;
  }
  RunwayScene scene = make_runway_scene(so);
  const std::string map_prefix = out + "/map";
  OccupancyGrid<2> boundaries;
  if (photo) {
    const cv::Mat img = cv::imread(texture_path, cv::IMREAD_GRAYSCALE);
    VDTNAV_CHECK(!img.empty(), "cannot read the photograph '" + texture_path + "'");
    // Laid at a scale that makes it cover the flight's footprint with a margin (0.1 m per pixel
    // for a 640 x 480 photograph: 64 m x 48 m).
    photo_resolution = 64.0 / img.cols;
    const Eigen::Vector2d origin(-0.5 * img.cols * photo_resolution,
                                 -0.5 * img.rows * photo_resolution);
    scene.texture = photograph_texture(img, photo_resolution, origin);
    EdgeOptions eo;  // the map: every edge of the photograph, no subsampling
    eo.max_points = 0;
    boundaries = edge_grid(img, photo_resolution, origin, eo);
    scene.runway = Eigen::AlignedBox2d(
        origin, origin + Eigen::Vector2d(img.cols, img.rows) * photo_resolution);
  } else {
    save_marking_map(map_prefix, scene);
    // The user's path: the map_server YAML + PNG read back.
    boundaries = marking_boundaries(occupancy(load_ros_map(map_prefix + ".yaml")));
  }
  VdtMap2 map = photo ? VdtMap2::build(boundaries) : load_marking_map(map_prefix + ".yaml");
  std::printf("[map] %d x %d cells at %.3f m\n", boundaries.size().x(), boundaries.size().y(),
              boundaries.frame().resolution());

  // ------------------------------------------------------------------ flight
  UavFlightOptions fo;
  fo.seed = seed;
  fo.frames = frames;
  fo.altitude_min = altitude * 2.0 / 3.0;
  fo.altitude_max = altitude * 4.0 / 3.0;
  if (photo) {
    fo.off_runway_stretches = false;
    fo.speed = 3.0;
  }
  std::vector<UavFlightSample> flight = simulate_uav_flight(scene, rig, fo);
  std::printf("[flight] %zu frames at %.0f Hz, altitude %.1f-%.1f m\n", flight.size(),
              fo.frame_rate, fo.altitude_min, fo.altitude_max);
  return Scenario{calibration,    rig, std::move(scene), std::move(boundaries),
                  std::move(map), fo,  std::move(flight)};
}

}  // namespace uav_study
