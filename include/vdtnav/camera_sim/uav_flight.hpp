#pragma once
/// \file
/// \brief A simulated flight of Dataset 3 (thesis 3.4.3): a multirotor following the
/// figure-of-eight road of a RunwayScene, with the IMU's roll and pitch, the downward laser's
/// range and an odometry whose drift is like a visual-inertial odometry's.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/camera_sim/runway_scene.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/odometry.hpp"
#include "vdtnav/uav_camera/uav_rig.hpp"

namespace vdtnav::uav_camera {

/// \brief The flight and its sensors' noise.
struct UavFlightOptions {
  std::uint64_t seed = 1;         ///< phases of the attitude/altitude motions and all noise
  std::size_t frames = 1200;      ///< number of samples
  double frame_rate = 10.0;       ///< Hz
  double speed = 4.0;             ///< ground speed along the path, m/s
  double altitude_min = 10.0;     ///< m; the altitude varies sinusoidally between min and max
  double altitude_max = 20.0;     ///< m
  double altitude_period = 47.0;  ///< s, period of the altitude oscillation
  double max_tilt = 5.0 * 3.14159265358979323846 / 180.0;     ///< |roll|, |pitch| bound, rad
  double sigma_roll = 0.2 * 3.14159265358979323846 / 180.0;   ///< IMU roll noise (std), rad
  double sigma_pitch = 0.2 * 3.14159265358979323846 / 180.0;  ///< IMU pitch noise (std), rad
  double sigma_laser_range = 0.05;                            ///< downward laser noise (std), m
  /// Odometry noise, like a visual-inertial odometry's drift: each increment's x and y get
  /// independent noise of std `odometry_sigma_xy_per_m` x (distance travelled in the step); its
  /// yaw gets std `odometry_sigma_yaw_per_rad` |yaw change| + `odometry_sigma_yaw_per_s` dt
  /// (the gyro's bias drift, present even when not turning).
  double odometry_sigma_xy_per_m = 0.05;
  double odometry_sigma_yaw_per_rad = 0.05;  ///< rad of yaw noise per rad turned
  double odometry_sigma_yaw_per_s = 0.005;   ///< rad of yaw noise per second
  /// Leave the runway for grass twice per loop of the eight (the outer sides of the two loops,
  /// a few seconds each) where few edges are visible, as in Fig. 3.13 of the thesis.
  bool off_runway_stretches = true;
  double off_runway_offset = 10.0;  ///< m, peak sideways offset of those stretches from the road
  double off_runway_length = 40.0;  ///< m of road over which such a detour goes out and back
};

/// \brief One frame of the flight.
struct UavFlightSample {
  double time = 0.0;                                                  ///< s since the start
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();  ///< truth
  Pose2 pose = Pose2::Zero();  ///< truth (x, y, yaw) of the body's level frame
  /// Noisy IMU roll and pitch, and the noisy range the laser measures along
  /// UavRig::laser_direction to the flat ground.
  AttitudeReading reading;
  /// dt, v, w and the noisy increment from the previous sample's level frame; zero at the first.
  OdometryStep odometry;
  bool over_runway = false;  ///< the camera's footprint centre (optical axis) hits the runway
};

/// \brief Simulates the flight over `scene`: along the figure-of-eight centreline at `speed`,
/// yaw along the (smoothed) direction of travel, roll and pitch from the accelerations a
/// multirotor needs (pitch = atan(a_forward / g), roll = -atan(a_left / g)) plus slow gusts,
/// softly limited to `max_tilt`, and the altitude oscillating between its bounds.
/// \throws ConfigError for options out of their domain or a centreline of fewer than 8 points.
[[nodiscard]] std::vector<UavFlightSample> simulate_uav_flight(const RunwayScene& scene,
                                                               const UavRig& rig,
                                                               const UavFlightOptions& options);

}  // namespace vdtnav::uav_camera
