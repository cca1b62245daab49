#pragma once
/// \file
/// \brief The ground plane under an RGB-D camera, fitted to its depth points by RANSAC and a
/// least-squares refinement. The camera-to-robot extrinsics only say where to look (a plane
/// within max_tilt and max_height_error of the one they predict); the fitted plane, not the
/// extrinsics, then gives the camera's roll, pitch and height over the ground (a scooter pitches
/// as it brakes, its suspension sinks).

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/camera/camera_model.hpp"
#include "vdtnav/rgbd_ground/depth_noise.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"

namespace vdtnav::rgbd_ground {

/// \brief A plane n . p + offset = 0 in the camera frame (x right, y down, z forward), n unit and
/// pointing from the ground toward the camera, so that offset > 0 is the camera's height.
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  int inliers = 0;     ///< depth points within the inlier distance
  double rms = 0.0;    ///< metres, of the inliers' distances to the plane
  bool found = false;  ///< false: no plane near the expected one had enough support
  [[nodiscard]] double distance(const Eigen::Vector3d& p) const { return normal.dot(p) + offset; }
};

/// \brief Options of the fit.
struct GroundPlaneOptions {
  int stride = 6;                 ///< sample every stride-th pixel in u and v
  double max_range = 8.0;         ///< metres: farther depths are not used
  int iterations = 150;           ///< RANSAC hypotheses
  double max_tilt = 0.35;         ///< radians between a hypothesis and the expected normal
  double max_height_error = 0.4;  ///< metres between a hypothesis's and the expected height
  double inlier_floor = 0.02;     ///< metres: the inlier distance is max(floor, 3 sigma_z(z))
  int min_inliers = 200;          ///< fewer: found = false
  std::uint32_t seed = 1;         ///< of the hypotheses (deterministic per frame)
};

/// \brief The plane the extrinsics predict: robot frame x forward, y left, z up, ground z = 0.
[[nodiscard]] GroundPlane expected_ground_plane(const Eigen::Isometry3d& camera_to_robot);

/// \brief Fits the ground plane to the frame's depth points (undistorted rays, z-depth).
[[nodiscard]] GroundPlane fit_ground_plane(const RgbdFrame& frame,
                                           const camera::PinholeCamera& camera,
                                           const Eigen::Isometry3d& camera_to_robot,
                                           const DepthNoiseModel& noise = {},
                                           const GroundPlaneOptions& options = {});

/// \brief The camera-to-robot transform with its roll, pitch and height taken from `plane` and
/// its yaw and horizontal position from `camera_to_robot`: the smallest rotation of the camera
/// that turns the expected ground normal into the fitted one.
[[nodiscard]] Eigen::Isometry3d levelled_extrinsics(const Eigen::Isometry3d& camera_to_robot,
                                                    const GroundPlane& plane);

}  // namespace vdtnav::rgbd_ground
