#pragma once
/// \file
/// \brief Renders what a PMD's rear RGB-D camera sees in a ParkScene: per pixel, the ray is
/// intersected with the ground and the obstacles; the ground is coloured by its surface with a
/// texture fixed to the ground (so that it moves with the scene), darkened in the obstacles'
/// shadows; the depth is the hit's z-depth with the sensor's noise (depth_noise.hpp), holes and a
/// range limit; above the horizon is sky without depth. The light (gain, offset, sun direction)
/// is a RenderOptions setting: the localization day differs from the mapping day.

#include <random>

#include <Eigen/Geometry>

#include "vdtnav/camera/camera_model.hpp"
#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/rgbd_ground/depth_noise.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

namespace vdtnav::rgbd_ground {

/// \brief The light and the sensor's imperfections.
struct RenderOptions {
  double gain = 1.0;    ///< multiplies every colour (exposure, cloud cover)
  double offset = 0.0;  ///< added to every channel
  Eigen::Vector3d sun = Eigen::Vector3d(0.5, 0.3, 0.81).normalized();  ///< toward the sun
  double shadow = 0.55;                                                ///< brightness in shadow
  DepthNoiseModel noise;
  double holes = 0.02;       ///< fraction of pixels without a depth reading
  double max_depth = 8.0;    ///< metres: farther has no reading
  double pixel_noise = 4.0;  ///< grey levels of sensor noise per channel
  /// The mapping day (bright, sun from the north-east) and a localization day (overcast, a lower
  /// sun from the west): the illumination change RTAB-Map failed on in the thesis.
  static RenderOptions mapping_day() { return {}; }
  static RenderOptions localization_day();
};

/// \brief The default camera of the study: 640 x 480, 525 px focal length, a mild barrel lens.
[[nodiscard]] camera::CameraCalibration default_rgbd_calibration();
/// \brief Rear-mounted, 1.0 m above the ground, 0.4 m behind the robot's origin, looking
/// backwards and 35 degrees down (robot frame x forward, y left, z up).
[[nodiscard]] Eigen::Isometry3d default_rear_camera();

/// \brief Renders one frame from the robot pose `robot` (world frame of the scene).
class ParkRenderer {
 public:
  ParkRenderer(const ParkScene& scene, camera::CameraCalibration calibration,
               Eigen::Isometry3d camera_to_robot);
  [[nodiscard]] RgbdFrame render(const Pose2& robot, const RenderOptions& options,
                                 std::mt19937& rng) const;

 private:
  const ParkScene& scene_;
  camera::CameraCalibration calibration_;
  Eigen::Isometry3d camera_to_robot_;
  std::vector<Eigen::Vector3d> rays_;  ///< undistorted ray (x_n, y_n, 1) of every pixel
};

}  // namespace vdtnav::rgbd_ground
