#pragma once
/// \file
/// \brief A camera mounted on a ground robot: its camera-to-robot transform from where it sits,
/// the direction it looks in and how far down it is tilted (robot frame x forward, y left, z up;
/// camera frame x right, y down, z forward, OpenCV's).

#include <cmath>

#include <Eigen/Geometry>

namespace vdtnav::rgbd_ground {

/// \param position the optical centre in the robot frame (metres).
/// \param heading the direction of the optical axis about z (0: forward, pi: backwards).
/// \param tilt how far the optical axis points below the horizon (radians).
[[nodiscard]] inline Eigen::Isometry3d tilted_camera(const Eigen::Vector3d& position,
                                                     double heading, double tilt) {
  const double ch = std::cos(heading), sh = std::sin(heading);
  Eigen::Matrix3d r;
  r.col(2) = Eigen::Vector3d(ch * std::cos(tilt), sh * std::cos(tilt), -std::sin(tilt));  // axis
  r.col(0) = Eigen::Vector3d(sh, -ch, 0.0);  // image right: to the right of the axis, level
  r.col(1) = r.col(2).cross(r.col(0));       // image down
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = r;
  t.translation() = position;
  return t;
}

}  // namespace vdtnav::rgbd_ground
