#pragma once
/// \file
/// \brief Edge pixels of the downward camera -> points on a flat ground in the level frame, with
/// their covariance and the errors they share (thesis 3.4.3; replaces (3.22), which has sign
/// slips, by the ray-plane intersection of the pinhole model).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/uav_camera/camera_model.hpp"
#include "vdtnav/uav_camera/uav_rig.hpp"

namespace vdtnav::uav_camera {

/// \brief Noise of what a frame's ground points are made of. The defaults are those of the
/// simulator of the issue; all are user-settable.
struct GroundProjectionNoise {
  /// Edge localisation noise, standard deviation in *distorted* pixels (per axis).
  double sigma_pixel = 0.5;
  double sigma_roll = 0.2 * 3.14159265358979323846 / 180.0;   ///< IMU roll, radians (0.2 deg)
  double sigma_pitch = 0.2 * 3.14159265358979323846 / 180.0;  ///< IMU pitch, radians (0.2 deg)
  double sigma_laser_range = 0.05;                            ///< laser range, metres
  /// Errors correlated along an observed line (an edge's bias, the map's rasterisation of the
  /// marking): one offset of this standard deviation, metres, shared by the points within
  /// correlation_length of each other, modelled as an effective sample size: every point of a
  /// square of that size on the ground gets n sigma_correlated^2 I added to its covariance, n the
  /// points in the square, so the square as a whole carries one sigma_correlated. 0: off.
  double sigma_correlated = 0.0;
  double correlation_length = 1.0;  ///< metres on the ground
};

/// \brief Largest |roll| and |pitch| (radians, 80 deg) at which a frame is projected at all.
inline constexpr double kMaxTilt = 80.0 * 3.14159265358979323846 / 180.0;

/// \brief A hit is dropped when it lies farther from the camera than this many altitudes (a ray
/// grazing the horizon: its position is dominated by attitude noise).
inline constexpr double kMaxRayLengthOverAltitude = 50.0;

/// \return the body's altitude h above a flat ground from the laser, which hits the ground:
/// h = -[Ry(pitch) Rx(roll) (laser_origin + r laser_direction)]_z.
[[nodiscard]] double altitude(const AttitudeReading& attitude, const UavRig& rig);

/// \return "" when `attitude` can be projected, else why not ("roll is NaN",
/// "laser range -1.2 m: expected > 0", "altitude -0.3 m: expected > 0", ...).
[[nodiscard]] std::string check_attitude(const AttitudeReading& attitude, const UavRig& rig);

/// \brief One ground point and its derivatives.
struct GroundPoint {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();  ///< level frame, metres
  /// dp / d(x_n, y_n), the undistorted normalized coordinates.
  Eigen::Matrix2d d_normalized = Eigen::Matrix2d::Zero();
  /// dp / d(roll, pitch, laser_range), the altitude's dependence included.
  Eigen::Matrix<double, 2, 3> d_attitude = Eigen::Matrix<double, 2, 3>::Zero();
  bool valid = false;  ///< false: the ray misses the ground (or hits it absurdly far away)
};

/// \brief Intersects the ray of normalized coordinates (x_n, y_n) with the ground plane z = 0 of
/// the level frame, with analytic Jacobians. Does not check the attitude (check_attitude()).
[[nodiscard]] GroundPoint project_to_ground(const Eigen::Vector2d& normalized,
                                            const AttitudeReading& attitude, const UavRig& rig);

/// \brief A frame's edge pixels as level-frame ground points (the observations of the 3-DOF
/// localizer, x, y, yaw).
///
/// Each point carries the covariance of its pixel noise, Sigma_p = A sigma_pixel^2 A^T with
/// A = dp/d(x_n, y_n) (d pixel / d(x_n, y_n))^-1, and shares the frame's attitude errors
/// theta = (roll, pitch, laser_range): G_i = dp_i/dtheta, cov(theta) = diag(sigma_roll^2,
/// sigma_pitch^2, sigma_laser_range^2). `beam` holds the pixel's index in `edge_pixels`.
///
/// Never throws on data: an unusable attitude (check_attitude() not empty) gives an empty set
/// with every pixel counted in dropped_not_finite (a NaN/inf reading) or dropped_out_of_range;
/// non-finite pixels count as not finite, rays that miss the ground as out of range.
[[nodiscard]] ObservationSet2 ground_observations(const std::vector<Eigen::Vector2d>& edge_pixels,
                                                  const PinholeCamera& camera, const UavRig& rig,
                                                  const AttitudeReading& attitude,
                                                  const GroundProjectionNoise& noise = {});

}  // namespace vdtnav::uav_camera
