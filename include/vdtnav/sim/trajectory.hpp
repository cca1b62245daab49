#pragma once
/// \file
/// \brief A kinematically feasible unicycle trajectory that follows a planned path through an
/// occupancy map: the ground-truth motion of the simulated Dataset 1 (thesis 3.4.1).
///
/// The robot is a unicycle with piecewise-constant (v, w) over each sample interval, so every
/// step is an exact circular arc (unicycle_increment); the simulated odometry integrates its noisy
/// (v, w) with the same arc, and noise-free odometry composes back to this trajectory exactly.

#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/grid.hpp"

namespace vdtnav::sim {

/// \brief Limits and controller settings of the simulated robot.
struct TrajectoryOptions {
  double speed = 0.5;          ///< cruise (maximum) linear velocity, m/s
  double max_turn_rate = 0.8;  ///< maximum |w|, rad/s
  double rate_hz = 40.0;       ///< sample (scan) rate; the Hokuyo UTM-30LX scans at 40 Hz
  int min_steps = 2000;        ///< the path is repeated/reversed until this many samples exist
  double look_ahead = 0.6;     ///< pure-pursuit look-ahead along the path, metres
  /// The pure-pursuit arc towards the look-ahead point must keep this far (UDT, metres) from
  /// obstacles; the look-ahead shrinks until it does (this is what stops corners being cut).
  double min_clearance = 0.25;
  double max_acceleration = 0.5;          ///< |dv/dt| limit, m/s^2
  double max_angular_acceleration = 3.0;  ///< |dw/dt| limit, rad/s^2
};

/// \brief One sample of the true trajectory.
struct TimedPose {
  double t = 0.0;              ///< seconds since the start
  Pose2 pose = Pose2::Zero();  ///< true robot pose in the map frame
  double v = 0.0;              ///< true linear velocity over the step into this pose, m/s
  double w = 0.0;              ///< true angular velocity over the step into this pose, rad/s
};

/// \brief The exact unicycle increment: constant (v, w) for dt, expressed in the start frame.
///
/// With theta = w dt: (dx, dy) = v dt (sin theta / theta, (1 - cos theta) / theta), dphi = theta;
/// the Euler step of (3.7) is its first-order approximation. Stable for w -> 0.
[[nodiscard]] Pose2 unicycle_increment(double v, double w, double dt);

/// \brief Follows `path` with a pure-pursuit controller and returns the sampled trajectory.
///
/// The robot starts at path.front() facing along the path. Each step it projects itself onto the
/// path (monotonically), picks the look-ahead point (shrinking the look-ahead until the circular
/// arc to it keeps `min_clearance` from obstacles in `map`), and steers on that arc with
/// v <= min(speed, max_turn_rate / |curvature|) (slowing in turns), rotating in place when the
/// target is more than 60 degrees off its heading; v and w are acceleration limited. It brakes to
/// a stop at the end of the path. A closed path (end within 0.5 m of the start, with a clear
/// segment between) is repeated; an open one is driven back and forth. Samples continue until the
/// path has been driven once and at least `min_steps` samples exist.
/// \param path a polyline in free space (e.g. plan_tour's result), at least two distinct points.
/// \param map the occupancy the clearance is checked against (its UDT is computed once).
/// \throws ConfigError for invalid options or path, or if the robot stops making progress.
[[nodiscard]] std::vector<TimedPose> follow_path(const std::vector<Eigen::Vector2d>& path,
                                                 const OccupancyGrid<2>& map,
                                                 const TrajectoryOptions& options = {});

}  // namespace vdtnav::sim
