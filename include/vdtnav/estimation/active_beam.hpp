#pragma once
/// \file
/// \brief Active localization with a single rotating range beam (thesis ch. 4): where to point
/// the beam next.
///
/// The sensor reads one range per step along its current bearing theta (robot frame) and turns at
/// angular velocity omega within its rotation range, split into n equal segments. When it reaches
/// its goal it picks the next: for each segment i, hypothetical readings at the segment's bearings
/// (a fixed angular resolution) are ray cast in the map from the predicted pose (sphere tracing on
/// the distance field, map/sphere_tracing.hpp), the covariance after them is predicted, and the
/// cost
///   cost(i) = c(P_i) + lambda |i - j|                                              (4.1)
/// (j the current segment) is minimised, c = trace (the thesis), det^(1/3) (D-optimality, in the
/// units of a variance so that lambda weighs the same) or the trace of the Fisher-information
/// prediction below. The sensor then sweeps toward the far end of the
/// chosen segment at omega, reading on the way.
///
/// Predicted covariance (kTrace, kDeterminant): the EKF's information-form update with the
/// hypothetical readings, P_i = (P^-1 + sum_k H_k^T R_k^-1 H_k)^-1, H_k = dd_k/dX and R_k the
/// disparity covariance of the VDT sensor model at the predicted pose — what VdtEkfLocalizer's
/// first iteration computes for the same readings. kFisher skips the disparity model: a range beam
/// along the world direction u that meets a surface of normal n at q = t + r u carries the Fisher
/// information g g^T / sigma_r^2 about the pose, g = dr/dX = -(n^T [I | J_phi q]) / (n^T u)
/// (J_phi q = (-(q-t)_y, (q-t)_x)), n the map's VDT gradient direction at q.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief The rotating single-beam range sensor.
struct RotatingBeamOptions {
  double rotation_range = 2.0 * 3.14159265358979323846;  ///< radians, centred on the robot's x
  double angular_velocity = 0.525;                       ///< rad/s
  int segments = 8;                                      ///< n
  double lambda = 1e-5;                                  ///< of (4.1), per segment moved
  double range_min = 0.5;                                ///< metres; closer reads nothing
  double range_max = 3.0;                                ///< metres; further reads nothing
  double sigma_range = 0.02;                             ///< metres
  /// Radians between the hypothetical readings of a segment (the fixed angular resolution).
  double hypothesis_resolution = 2.0 * 3.14159265358979323846 / 180.0;
  /// Data association of one reading (ActiveBeamSelector::consistent): a reading whose range
  /// differs from the range ray cast from the predicted pose by more than `gate` standard
  /// deviations is not used. With one 30 m beam, an endpoint that went past a door edge can land
  /// near some other surface and look plausible to the VDT model; the ray cast tells. Four sigma
  /// refuses one consistent Gaussian reading in ~16000. <= 0: no gate.
  double gate = 4.0;

  /// \brief Table 4.1 (Dataset 1): 360 degrees, 0.525 rad/s, 8 segments, 0.5-3 m.
  [[nodiscard]] static RotatingBeamOptions table_4_1();
  /// \brief Table 4.3 (Dataset 2): 270 degrees, 0.1745 rad/s, 23 segments, 0.5-30 m.
  [[nodiscard]] static RotatingBeamOptions table_4_3();
  /// \return whether the rotation range is a full turn (the beam then wraps around).
  [[nodiscard]] bool full_turn() const noexcept;
  /// \throws ConfigError for a non-positive range, velocity, segment count or sigma.
  void validate() const;
};

/// \brief How the beam is pointed.
enum class BeamStrategy {
  kActiveTrace,   ///< (4.1) with trace(P_i), the thesis
  kActiveDet,     ///< (4.1) with det(P_i)^(1/3): D-optimality
  kActiveFisher,  ///< (4.1) with the trace of the Fisher-information prediction
  kPassiveFixed,  ///< kept at the robot's heading
  kPassiveRotate  ///< turning at omega over the whole range, back and forth (around on 360)
};

/// \return "active-trace", "active-det", "active-fisher", "passive-fixed", "passive-rotate".
[[nodiscard]] const char* to_string(BeamStrategy s) noexcept;
/// \throws ConfigError for another name (the message lists them).
[[nodiscard]] BeamStrategy beam_strategy_from_string(const std::string& name);

/// \brief What one goal selection found.
struct BeamSelection {
  int segment = 0;            ///< the chosen segment
  std::vector<double> cost;   ///< cost(i) of every segment (+inf: nothing in range)
  std::vector<int> readings;  ///< hypothetical readings in range per segment
};

/// \brief Goal selection (4.1) on one map.
class ActiveBeamSelector {
 public:
  /// \param map must outlive the selector.
  ActiveBeamSelector(const VdtMap2& map, const RotatingBeamOptions& beam,
                     const VdtSensorModelOptions& sensor = {});

  /// \brief The bearing (robot frame) of the centre of segment i, and its edges.
  [[nodiscard]] double segment_centre(int i) const;
  [[nodiscard]] double segment_lower(int i) const;
  [[nodiscard]] double segment_upper(int i) const;
  /// \return the segment holding bearing theta (robot frame, wrapped into the range).
  [[nodiscard]] int segment_of(double theta) const;

  /// \brief The hypothetical reading along bearing theta (robot frame) from pose: the sphere-traced
  /// range, or +inf outside [range_min, range_max).
  [[nodiscard]] double hypothetical_range(const Pose2& pose, double theta) const;

  /// \brief P after the hypothetical readings of segment i from pose (kTrace, kDeterminant: the
  /// EKF's information-form update; kFisher: the range-beam Fisher information). Readings in
  /// range are counted in *readings when given.
  [[nodiscard]] Eigen::Matrix3d predicted_covariance(const Pose2& pose, const Eigen::Matrix3d& p,
                                                     int segment, BeamStrategy strategy,
                                                     int* readings = nullptr) const;

  /// \brief The range-beam Fisher information vector g = dr/dX of a beam along bearing theta
  /// (robot frame) from pose, and whether it hits within range (see the file comment).
  [[nodiscard]] bool range_gradient(const Pose2& pose, double theta, Eigen::Vector3d* g) const;

  /// \brief Whether a reading of `range` along bearing theta (robot frame) agrees with the map
  /// seen from the predicted pose (P its covariance): |range - r(pose)| <= gate * sigma with
  /// sigma^2 = g^T P g + sigma_range^2 + map_sigma^2, g = dr/dX (range_gradient()). False when
  /// the ray cast from the pose reads nothing in range; always true when beam().gate <= 0.
  [[nodiscard]] bool consistent(const Pose2& pose, const Eigen::Matrix3d& p, double theta,
                                double range) const;

  /// \brief The next goal segment for an active strategy, from the current segment.
  [[nodiscard]] BeamSelection select(const Pose2& pose, const Eigen::Matrix3d& p, int current,
                                     BeamStrategy strategy) const;

  [[nodiscard]] const RotatingBeamOptions& beam() const noexcept { return beam_; }

 private:
  const VdtMap2* map_;
  RotatingBeamOptions beam_;
  VdtSensorModel model_;
};

/// \brief The sensor's bearing over time under a strategy: where it points now, and where it
/// turns next.
class RotatingBeamController {
 public:
  RotatingBeamController(const RotatingBeamOptions& beam, BeamStrategy strategy);

  /// \brief The bearing of the reading of this step (robot frame).
  [[nodiscard]] double bearing() const noexcept { return theta_; }
  /// \brief The goal segment (active), -1 before the first selection or for passive strategies.
  [[nodiscard]] int goal() const noexcept { return goal_; }
  /// \brief Whether an active strategy needs a new goal (at the start and when the sweep reached
  /// the far end of the goal segment).
  [[nodiscard]] bool needs_goal() const noexcept;
  /// \brief Sets the goal segment: the beam sweeps toward its far end from the current bearing.
  void set_goal(int segment, const ActiveBeamSelector& selector);
  /// \brief Turns the beam for dt seconds at the angular velocity.
  void advance(double dt);

 private:
  RotatingBeamOptions beam_;
  BeamStrategy strategy_;
  double theta_ = 0.0;
  double target_ = 0.0;     ///< bearing the sweep heads for
  double direction_ = 1.0;  ///< passive-rotate's sense of rotation
  int goal_ = -1;
  bool reached_ = true;
};

}  // namespace vdtnav
