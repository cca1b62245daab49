#pragma once
/// \file
/// \brief The pan-tilt point laser of Dataset 4 (thesis 3.4.4): a single-beam range finder
/// (LIDAR-Lite v3) on a pan-tilt unit. A reading (pan, tilt, range) and the unit's calibration
/// give a 3D point in the robot frame and its derivatives.
///
/// Frames and sign conventions (REP-103: x forward, y left, z up, angles right-handed):
///  - mount  M: the unit's base in the robot frame (`PanTiltCalibration::mount`); the pan axis is
///    z of M.
///  - panned P = M Rz(pan): pan is a right-handed rotation about +z of M, so a positive pan turns
///    the beam counter-clockwise seen from above (x towards y).
///  - tilted T = P Trans(pan_to_tilt) Ry(tilt): the tilt axis is y of P through the point
///    `pan_to_tilt` (expressed in P). Tilt is a right-handed rotation about +y, so a **positive
///    tilt points the beam down** (Ry(tilt) e_x = (cos tilt, 0, -sin tilt)); negative looks up.
///  - laser L = T Trans(tilt_to_laser): the beam starts at `tilt_to_laser` (expressed in T) and
///    runs along +x of T.
/// Hence, with R_m, t_m the mount's rotation and translation,
///   p(pan, tilt, r) = t_m + R_m Rz(pan) (o_pt + Ry(tilt) (o_l + r e_x))
///   dp/dr    = R_m Rz(pan) Ry(tilt) e_x                        (unit beam direction)
///   dp/dpan  = R_m (e_z x Rz(pan) (o_pt + Ry(tilt) (o_l + r e_x)))
///   dp/dtilt = R_m Rz(pan) (e_y x Ry(tilt) (o_l + r e_x))
/// using d/da Rz(a) = [e_z]_x Rz(a) and d/da Ry(a) = [e_y]_x Ry(a).

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief One reading of the pan-tilt point laser.
struct PanTiltReading {
  double pan = 0.0;    ///< radians, positive counter-clockwise about the pan axis (+z)
  double tilt = 0.0;   ///< radians, positive about +y of the panned frame: the beam looks down
  double range = 0.0;  ///< metres along the beam; +inf (or NaN) when nothing returned
  double time = 0.0;   ///< seconds (0 when the source has no time stamps)
};

/// \brief Geometry of the pan-tilt unit (see the file comment for the frame chain).
/// A default-constructed calibration has the unit at the robot origin and no offsets.
struct PanTiltCalibration {
  Pose3 mount = Pose3::Identity();                          ///< unit base in the robot frame
  Eigen::Vector3d pan_to_tilt = Eigen::Vector3d::Zero();    ///< tilt axis point, panned frame
  Eigen::Vector3d tilt_to_laser = Eigen::Vector3d::Zero();  ///< beam origin, tilted frame

  /// \brief A Turtlebot-like unit used by the simulator by default: the base 0.36 m above the
  /// robot origin and 0.05 m behind it, the tilt axis 0.045 m above the pan bearing, the beam
  /// 0.02 m ahead of and 0.015 m above the tilt axis (beam origin 0.42 m above the robot origin
  /// at zero pan and tilt).
  [[nodiscard]] static PanTiltCalibration turtlebot_example() {
    PanTiltCalibration c;
    c.mount.translation() = Eigen::Vector3d(-0.05, 0.0, 0.36);
    c.pan_to_tilt = Eigen::Vector3d(0.0, 0.0, 0.045);
    c.tilt_to_laser = Eigen::Vector3d(0.02, 0.0, 0.015);
    return c;
  }
};

/// \brief Range limits and noise of the point laser; defaults are the LIDAR-Lite v3
/// (5 cm to 40 m, +-2.5 cm accuracy read as sigma).
struct PointLaserSpec {
  double range_min = 0.05;     ///< metres; readings below are dropped
  double range_max = 40.0;     ///< metres; readings at or beyond are dropped (no return)
  double sigma_range = 0.025;  ///< range noise standard deviation, metres
};

/// \brief A reading's point in the robot frame and its derivatives (see the file comment).
struct PanTiltPoint {
  Eigen::Vector3d point;    ///< p, robot frame
  Eigen::Vector3d d_range;  ///< dp/dr, the unit beam direction in the robot frame
  Eigen::Vector3d d_pan;    ///< dp/dpan
  Eigen::Vector3d d_tilt;   ///< dp/dtilt
};

namespace detail {
[[nodiscard]] inline Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}
[[nodiscard]] inline Eigen::Matrix3d rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  return r;
}
}  // namespace detail

/// \return the laser frame L (origin at the beam start, beam along +x) in the robot frame.
[[nodiscard]] inline Pose3 pan_tilt_laser_pose(const PanTiltCalibration& calibration, double pan,
                                               double tilt) {
  const Eigen::Matrix3d rz = detail::rot_z(pan), ry = detail::rot_y(tilt);
  const Eigen::Matrix3d& rm = calibration.mount.linear();
  Pose3 laser = Pose3::Identity();
  laser.linear() = rm * rz * ry;
  laser.translation() = calibration.mount.translation() +
                        rm * (rz * (calibration.pan_to_tilt + ry * calibration.tilt_to_laser));
  return laser;
}

/// \return the robot-frame point of reading (pan, tilt, range) and dp/d(range, pan, tilt).
/// The range is used as given (no validity check; see point_laser_observations for that).
[[nodiscard]] inline PanTiltPoint pan_tilt_point(const PanTiltCalibration& calibration, double pan,
                                                 double tilt, double range) {
  const Eigen::Matrix3d rz = detail::rot_z(pan), ry = detail::rot_y(tilt);
  const Eigen::Matrix3d& rm = calibration.mount.linear();
  const Eigen::Vector3d in_tilted = calibration.tilt_to_laser + range * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d tilted = ry * in_tilted;                              // Ry (o_l + r e_x)
  const Eigen::Vector3d in_panned = rz * (calibration.pan_to_tilt + tilted);  // Rz (o_pt + ...)
  PanTiltPoint out;
  out.point = calibration.mount.translation() + rm * in_panned;
  out.d_range = rm * (rz * ry.col(0));
  out.d_pan = rm * Eigen::Vector3d::UnitZ().cross(in_panned);
  out.d_tilt = rm * (rz * Eigen::Vector3d::UnitY().cross(tilted));
  return out;
}

/// \return the robot-frame point of `reading` (derivatives in pan_tilt_point).
[[nodiscard]] inline PanTiltPoint pan_tilt_point(const PanTiltCalibration& calibration,
                                                 const PanTiltReading& reading) {
  return pan_tilt_point(calibration, reading.pan, reading.tilt, reading.range);
}

}  // namespace vdtnav
