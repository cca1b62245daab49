#pragma once
/// \file
/// \brief How the camera and the downward laser sit on a UAV, and what the IMU and the laser say
/// at a frame.
///
/// Frames (REP-103): body x forward, y left, z up; the *level frame* of a pose has its origin on
/// the ground below the body, z up, and the body's yaw (no roll, no pitch), so that the 3-DOF pose
/// (x, y, yaw) being estimated maps level-frame ground points q to the world as R(yaw) q + (x, y).
/// The body's attitude is R = Rz(yaw) Ry(pitch) Rx(roll) (ZYX Euler angles, as MAVLink and ROS
/// report them).

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vdtnav::uav_camera {

/// \brief The camera-to-body and laser-to-body geometry.
struct UavRig {
  /// Camera pose in the body frame. Default: at the body origin, looking straight down, image
  /// top toward the front (camera x = -body y, camera y = -body x, camera z = -body z).
  Eigen::Isometry3d body_from_camera = default_body_from_camera();
  Eigen::Vector3d laser_origin = Eigen::Vector3d::Zero();             ///< body frame, metres
  Eigen::Vector3d laser_direction = Eigen::Vector3d(0.0, 0.0, -1.0);  ///< body frame, unit

  [[nodiscard]] static Eigen::Isometry3d default_body_from_camera() {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() << 0.0, -1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, -1.0;
    return t;
  }
};

/// \brief What the IMU and the downward laser report at a frame.
struct AttitudeReading {
  double roll = 0.0;         ///< radians, from the IMU
  double pitch = 0.0;        ///< radians, from the IMU
  double laser_range = 0.0;  ///< metres, along UavRig::laser_direction
};

/// \return Ry(pitch) Rx(roll): the body attitude in the level frame.
[[nodiscard]] inline Eigen::Matrix3d level_from_body(double roll, double pitch) {
  return (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace vdtnav::uav_camera
