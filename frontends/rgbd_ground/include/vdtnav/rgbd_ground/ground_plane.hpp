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
  int inliers = 0;   ///< depth points within the inlier distance
  double rms = 0.0;  ///< metres, of the inliers' distances to the plane
  /// Covariance of the fitted normal (camera frame, rank 2: its error is perpendicular to it)
  /// from the total least-squares fit (see fit_ground_plane()).
  Eigen::Matrix3d normal_covariance = Eigen::Matrix3d::Zero();
  double offset_sigma = 0.0;  ///< metres, standard deviation of the fitted offset
  bool found = false;         ///< false: no plane near the expected one had enough support
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
///
/// The refinement is the maximum-likelihood plane of the inliers: total least squares weighted
/// by each inlier's depth noise along the normal, sigma_i below. The covariance of the fit is the
/// Gauss-Newton one of that plane: with the normal moved to n + a e1 + b e2 (e1, e2
/// perpendicular to n) and the offset to d + c, inlier i's residual is r_i = n . p_i + d,
/// dr_i/d(a, b, c) = j_i = (e1 . p_i, e2 . p_i, 1), and its noise is the depth noise along the
/// ray, sigma_i = |n . (x_n, y_n, 1)| sigma_z(z_i). Then
///   cov(a, b, c) = s^2 (sum_i j_i j_i^T / sigma_i^2)^-1,
///   s^2 = max(1, sum_i r_i^2 / sigma_i^2 / (N - 3)),
/// the reduced chi-square scaling it up where the ground is rougher than the depth noise (grass,
/// a real floor's unevenness). Neighbouring pixels' depth errors are taken as independent (the
/// samples are stride pixels apart).
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

/// \brief Covariance of the levelled extrinsics' tilt error delta = (about robot x, about robot
/// y), the rotation Exp(delta) R' that the fit's normal error leaves on the levelled rotation R'
/// (`levelled`). R' n = e_z: a normal error dn (camera frame) tilts the robot-frame normal by
/// m = R' dn, and the rotation that turns e_z + m back to e_z is delta = (m_y, -m_x) to first
/// order, so cov(delta) = T [R' C R'^T]_xy T^T with T = [[0, 1], [-1, 0]], C = normal_covariance.
[[nodiscard]] Eigen::Matrix2d levelled_tilt_covariance(const Eigen::Isometry3d& levelled,
                                                       const GroundPlane& plane);

}  // namespace vdtnav::rgbd_ground
