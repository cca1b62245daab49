#pragma once
/// \file
/// \brief The LiDAR sensor model on a VDT map (thesis 2.3.1, corrected per SPEC).
///
/// Beam i ends at the robot-frame point p_i (after the mounting transform); at robot pose
/// X = (x, y, phi) it lies at q_i = t + R(phi) p_i (corrected (2.11)). Its disparity is
///   d_i = DT_v(q_i)                                                  (2.12)
/// with analytic derivatives
///   dd_i/dX = J(q_i) [I | R'(phi) p_i],   dd_i/dr_i = J(q_i) R(phi) u_i,
/// J = dDT_v/dp, u_i the unit beam direction. The scalar cost is the Vector Chamfer Distance
///   d_VCD = sum_i |d_i|^2                                            (2.17)
/// and beams are gated (3.3) on the *magnitudes* of the signed components (SPEC).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav {

/// \brief Which beams count (3.3).
enum class GateMode {
  kComponents,  ///< |DT_x| < alpha and |DT_y| < alpha (the thesis's (3.3) with magnitudes)
  kNorm,        ///< |DT_v| < alpha
  kNone,        ///< every beam inside the map
};

/// \brief How DT_v is read at an endpoint (SPEC, Numerical notes).
enum class ResidualMode {
  kInterpolated,  ///< the C^2 cubic B-spline of each component
  kNearestPoint,  ///< p - c(cell(p)): the stored nearest occupied cell, Jacobian = identity
};

/// \brief The per-beam disparity covariance.
enum class DisparityCovariance {
  kExactRankOne,  ///< sigma_r^2 j j^T + sigma_map^2 I: both components come from one range
  kDiagonal,      ///< the thesis's (2.13): diag(j_x^2, j_y^2) sigma_r^2 (+ sigma_map^2 I)
};

/// \brief Options of the sensor model.
struct VdtSensorModelOptions {
  GateMode gate_mode = GateMode::kComponents;
  double gate = 0.5;  ///< alpha, metres
  ResidualMode residual = ResidualMode::kInterpolated;
  DisparityCovariance covariance = DisparityCovariance::kExactRankOne;
  /// Map-noise floor: standard deviation of each DT_v component due to the map itself
  /// (discretisation and interpolation), metres. Default: resolution / sqrt(12), the spread of a
  /// surface uniformly placed within a cell.
  double map_sigma = -1.0;  ///< < 0: resolution / sqrt(12)
};

/// \brief One beam's disparity and its derivatives at a pose.
struct BeamDisparity {
  Eigen::Vector2d d = Eigen::Vector2d::Zero();                               ///< d_i (2.12)
  Eigen::Matrix<double, 2, 3> d_pose = Eigen::Matrix<double, 2, 3>::Zero();  ///< dd_i/dX
  Eigen::Vector2d d_range = Eigen::Vector2d::Zero();                         ///< dd_i/dr_i
  bool inside = false;  ///< endpoint inside the map
  bool inlier = false;  ///< inside and passes the gate
};

/// \brief Second derivatives of beam i's VCD term |d_i|^2 / 2 (what the implicit-function
/// covariance (3.4)-(3.6), as corrected in SPEC, needs).
struct BeamCurvature {
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();  ///< d^2(|d_i|^2/2)/dX^2
  Eigen::Vector3d cross = Eigen::Vector3d::Zero();    ///< d^2(|d_i|^2/2)/dX dr_i
};

/// \brief The VDT sensor model of one map.
class VdtSensorModel {
 public:
  /// \throws ConfigError for a negative gate.
  VdtSensorModel(const VdtMap2& map, const VdtSensorModelOptions& options = {});

  /// \brief Disparity and first derivatives of beam (p, u) at pose X (gate decided here).
  [[nodiscard]] BeamDisparity disparity(const Pose2& pose, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& u) const;

  /// \brief Disparity, first and second derivatives of beam (p, u) at pose X.
  [[nodiscard]] BeamDisparity disparity(const Pose2& pose, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& u, BeamCurvature* curvature) const;

  /// \brief As above with cos(phi), sin(phi) given (a scan's beams share them).
  [[nodiscard]] BeamDisparity disparity(const Pose2& pose, double cos_phi, double sin_phi,
                                        const Eigen::Vector2d& p, const Eigen::Vector2d& u,
                                        BeamCurvature* curvature = nullptr) const;

  /// \brief Disparity only (no derivatives: the cheaper lookup), and whether the beam is an
  /// inlier, for residual-only evaluations and gating.
  [[nodiscard]] Eigen::Vector2d disparity_value(const Pose2& pose, double cos_phi, double sin_phi,
                                                const Eigen::Vector2d& p, bool* inlier) const;

  /// \brief 2x2 covariance of d_i from the range noise (and the map-noise floor).
  [[nodiscard]] Eigen::Matrix2d disparity_covariance(const BeamDisparity& b,
                                                     double sigma_range) const;

  /// \brief d_VCD (2.17) over the inlier beams of a scan at pose X; counts inliers if asked.
  [[nodiscard]] double vector_chamfer_distance(const Pose2& pose, const ScanPoints& scan,
                                               int* inliers = nullptr) const;

  [[nodiscard]] const VdtSensorModelOptions& options() const noexcept { return options_; }
  [[nodiscard]] double map_sigma() const noexcept { return map_sigma_; }
  [[nodiscard]] const VdtMap2& map() const noexcept { return *map_; }

 private:
  [[nodiscard]] bool passes_gate(const Eigen::Vector2d& d) const noexcept;

  const VdtMap2* map_;
  VdtSensorModelOptions options_;
  double map_sigma_;
};

}  // namespace vdtnav
