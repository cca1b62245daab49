#pragma once
/// \file
/// \brief Motion during a LiDAR sweep, and deskewing: a spinning sensor takes its readings over
/// the sweep (0.1 s at 10 Hz) while the robot moves; each reading is in the sensor's frame at its
/// own time. Under constant velocity from the scan's stamp, the robot's pose τ seconds after the
/// stamp, in the frame it had at the stamp, is
///   T(τ) = (R(τ), t(τ)),   R(τ) = Exp(τ ω),   t(τ) = τ v,                              (1)
/// ω the body rates (rad/s) and v the velocity in the stamp's frame (m/s): the rotation at a
/// constant rate about one axis, the position along a straight line (over a sweep the difference
/// from the SE(3) exponential, a circular arc, is ½ |v| |ω| τ², 1.5 mm at 2 m/s, 30 °/s, 0.1 s).
/// Deskewing moves reading i, taken τ_i after the stamp at robot-frame point p_i along the unit
/// direction u_i, to where it is in the stamp's frame:
///   p_i ← T(τ_i) p_i,   u_i ← R(τ_i) u_i,   C_i ← R(τ_i) C_i R(τ_i)ᵀ,                 (2)
/// so the scan is what a sensor at rest at the stamp's pose would have measured; its range and the
/// range noise stay. The localizers take the motion from the prediction (the odometry increment
/// over its dt, or constant velocity from the last two estimates) and hold it during the solve:
/// the deskewed points are constants of the pose being estimated, so the sensor model's Jacobians
/// (d p_world / d pose) are unchanged — an error of the predicted velocity δv moves reading i by
/// τ_i δv, under 1 cm for 0.1 m/s off over a 0.1 s sweep.

#include <cstddef>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav {

/// \brief Constant velocity over a sweep, (1).
struct SweepMotion {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< v, m/s, in the stamp's frame
  Eigen::Vector3d rates = Eigen::Vector3d::Zero();     ///< ω, rad/s, body rates

  /// \return T(τ) of (1): the robot's pose τ seconds after the stamp in the stamp's frame.
  [[nodiscard]] Pose3 at(double tau) const {
    Pose3 t = Pose3::Identity();
    t.linear() = so3_exp(tau * rates);
    t.translation() = tau * velocity;
    return t;
  }

  /// \return the motion that moves by `increment` (the pose at the end in the frame at the start)
  /// in `dt` seconds: v = t_Δ / dt, ω = Log(R_Δ) / dt. \throws ConfigError unless dt > 0.
  [[nodiscard]] static SweepMotion from_increment(const Pose3& increment, double dt);
};

/// \brief Deskews `observations` in place by (2): reading i by observations.times[i] (seconds
/// after the stamp). A set without times is left as it is (an instantaneous sweep).
/// \return the number of readings moved (0 without times).
/// \throws ConfigError when times has another size than points or a time is not finite.
std::size_t deskew(ObservationSet3& observations, const SweepMotion& motion);

}  // namespace vdtnav
