#pragma once
/// \file
/// \brief Renders what the UAV's downward camera sees of a textured flat ground: exact ray casting
/// through the calibrated (distorted) lens, then exposure, motion blur and sensor noise.

#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "vdtnav/camera_sim/runway_scene.hpp"
#include "vdtnav/uav_camera/camera_model.hpp"
#include "vdtnav/uav_camera/uav_rig.hpp"

namespace vdtnav::uav_camera {

/// \brief Photometric effects applied after the geometric rendering, in this order.
struct RenderOptions {
  double noise_sigma = 2.0;      ///< additive Gaussian sensor noise, grey levels (std)
  double motion_blur_px = 0.0;   ///< length of a linear motion-blur kernel, pixels (<= 1: none)
  double blur_angle = 0.0;       ///< image direction of the motion, rad (0 = along +u)
  double exposure_gain = 1.0;    ///< out = gain * in + offset, then saturated to [0, 255]
  double exposure_offset = 0.0;  ///< grey levels
  int supersampling = 2;  ///< rays per pixel along each axis: 1 (pixel centre) or 2 (2 x 2 box)
  double max_ground_distance = 500.0;  ///< rays hitting the ground farther: background, metres
};

/// \brief Ray-casting renderer of a GroundTexture seen by a camera on a UavRig.
///
/// Each output pixel (u, v) is a *distorted* pixel: its ray is the undistorted normalized ray
/// (x_n, y_n, 1), precomputed once with cv::undistortPoints (iterated to 1e-12), rotated to the
/// world as R_wb R_bc (x_n, y_n, 1) from the camera centre c = T_wb t_bc and intersected with the
/// ground z = 0: g = c - c_z r / r_z.
class GroundRenderer {
 public:
  /// \throws ConfigError for an unusable calibration (size or focal lengths <= 0).
  GroundRenderer(const CameraCalibration& calibration, const UavRig& rig);

  /// \brief Renders one 8-bit grey image of calibration width x height.
  /// \param texture the ground (z = 0).
  /// \param world_from_body body pose: linear() = Rz(yaw) Ry(pitch) Rx(roll), translation
  ///        (x, y, altitude) above the ground.
  /// \param options photometric effects.
  /// \param rng draws the sensor noise; the image is a deterministic function of its state.
  [[nodiscard]] cv::Mat render(const GroundTexture& texture,
                               const Eigen::Isometry3d& world_from_body,
                               const RenderOptions& options, std::mt19937_64& rng) const;

  /// \return the undistorted normalized ray (x_n, y_n) of the centre of pixel (u, v).
  [[nodiscard]] Eigen::Vector2d ray(int u, int v) const;

  [[nodiscard]] const CameraCalibration& calibration() const noexcept { return calibration_; }
  [[nodiscard]] const UavRig& rig() const noexcept { return rig_; }

 private:
  CameraCalibration calibration_;
  UavRig rig_;
  std::vector<float> ray_x_;  ///< x_n of each pixel centre, row-major
  std::vector<float> ray_y_;  ///< y_n of each pixel centre
  /// 2 x 2 supersampling: (x_n, y_n) of the sub-pixel points (+-1/4, +-1/4), 8 floats per pixel.
  std::vector<float> sub_rays_;
};

/// \return the body pose for the renderer: Rz(yaw) Ry(pitch) Rx(roll), at (x, y, altitude).
[[nodiscard]] Eigen::Isometry3d body_pose(double x, double y, double altitude, double roll,
                                          double pitch, double yaw);

}  // namespace vdtnav::uav_camera
