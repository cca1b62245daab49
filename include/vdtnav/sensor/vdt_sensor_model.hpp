#pragma once
/// \file
/// \brief The range sensor model on a VDT map (thesis 2.3.1, corrected per SPEC), in 2D and 3D.
///
/// Reading i ends at the robot-frame point p_i (after the mounting transform); at robot pose X
/// (2D: (x, y, phi); 3D: (R, t) in SE(3)) it lies at q_i = R p_i + t (corrected (2.11)). Its
/// disparity is
///   d_i = DT_v(q_i)                                                  (2.12)
/// with analytic derivatives, in the pose perturbation of PoseTraits<Dim> (2D: additive;
/// 3D: left, delta = (dt, dtheta) in the world frame):
///   dd_i/dX = J(q_i) dq_i/dX,   dq/dX = [I | R' p_i] (2D),  [I | -[R p_i]_x] (3D),
///   dd_i/dr_i = J(q_i) R u_i,
/// J = dDT_v/dp, u_i = dp_i/dr_i the unit beam direction. The scalar cost is the Vector Chamfer
/// Distance
///   d_VCD = sum_i |d_i|^2                                            (2.17)
/// and beams are gated (3.3) on the *magnitudes* of the signed components (SPEC).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/map/map_uncertainty.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav {

/// \brief Which beams count (3.3).
enum class GateMode {
  kComponents,  ///< |DT_c| < alpha for every component c (the thesis's (3.3) with magnitudes)
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
  kDiagonal,      ///< the thesis's (2.13): diag(j_c^2) sigma_r^2 (+ sigma_map^2 I)
};

/// \brief What VdtSensorModelT::disparities() computes besides d, inside and inlier.
enum class DisparityParts {
  kValue,  ///< nothing more (gates, weights, scores): the value-only lookup
  kPose,   ///< d_pose (the solvers' normal equations)
  kAll,    ///< d_pose, d_point and d_range (covariances)
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
  /// Map errors correlated along the map's surfaces. A wall drawn off by a few centimetres is off
  /// along its length, so the readings that hit it share one error which more readings do not
  /// average away (on the Intel log the per-reading floor alone makes the pose covariance ~30x too
  /// small, although the residuals themselves are only 1.2x larger than it predicts: the shared
  /// part is absorbed by the pose). Model: the readings whose endpoints fall in one square (cube)
  /// of side map_correlation_length, in the world frame, share an error e_k ~ N(0, sigma_c^2 I),
  ///   sigma_c^2 = resolution^2 / 12 + map_pose_sigma^2,
  /// the map's quantisation (a grid-aligned wall is one constant offset of the cell centres) and
  /// the pose error of the scans it was drawn from. The estimators consider it (do not estimate
  /// it): the pose covariance gains sum_k S_k sigma_c^2 S_k^T, S_k the sensitivity of the pose
  /// to a common shift of group k's endpoints. 0: off (each reading's map error independent).
  double map_correlation_length = 0.0;
  /// Pose error of the map builder (the SLAM that drew the map), metres; < 0: resolution / 2, a
  /// scan matcher's accuracy on a grid of that resolution; 0: an exact map (a floor plan).
  double map_pose_sigma = 0.0;
  /// A 2D map that knows its own error jointly over points (an uncertain VDT map fitted to the
  /// scans it was built from, mapping/uncertain_vdt_map.hpp; not owned, must outlive the model).
  /// The estimators then add the map's share of the pose covariance, cov(sum_i s_i e(q_i)) over
  /// the inlier endpoints q_i (MapUncertainty::propagate) with s_i the pose's sensitivity to an
  /// error e of DT_v at q_i, with every correlation the map knows between the endpoints; the
  /// squares of map_correlation_length then model only the endpoints the map does not know.
  /// map_sigma stays the per-reading floor (set it to what sampling the map adds, ~0 for a
  /// smooth fitted map).
  const MapUncertainty2* map_uncertainty = nullptr;
};

/// \brief One reading's disparity and its derivatives at a pose (aliases BeamDisparity for 2D,
/// BeamDisparity3 for 3D).
template <int Dim>
struct BeamDisparityT {
  using Vector = typename SpaceTraits<Dim>::Vector;
  using PoseJacobian = typename PoseTraits<Dim>::PointJacobian;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  Vector d = Vector::Zero();                   ///< d_i (2.12)
  PoseJacobian d_pose = PoseJacobian::Zero();  ///< dd_i/dX (Dim x DoF)
  Vector d_range = Vector::Zero();             ///< dd_i/dr_i = d_point u_i
  Matrix d_point = Matrix::Zero();             ///< dd_i/dp_i = J R (robot-frame point)
  bool inside = false;                         ///< endpoint inside the map
  bool inlier = false;                         ///< inside and passes the gate
};

/// \brief Second derivatives of reading i's VCD term |d_i|^2 / 2 (what the implicit-function
/// covariance (3.4)-(3.6), as corrected in SPEC, needs), in the perturbation of PoseTraits<Dim>.
template <int Dim>
struct BeamCurvatureT {
  using Hessian = typename PoseTraits<Dim>::Covariance;
  using Cross = typename PoseTraits<Dim>::Tangent;
  using CrossPoint = Eigen::Matrix<double, PoseTraits<Dim>::kDoF, Dim>;
  Hessian hessian = Hessian::Zero();            ///< d^2(|d_i|^2/2)/dX^2
  Cross cross = Cross::Zero();                  ///< d^2(|d_i|^2/2)/dX dr_i = cross_point u_i
  CrossPoint cross_point = CrossPoint::Zero();  ///< d^2(|d_i|^2/2)/dX dp_i (robot-frame point)
};

/// \brief The VDT sensor model of one map (aliases VdtSensorModel for 2D, VdtSensorModel3 for
/// 3D).
template <int Dim>
class VdtSensorModelT {
 public:
  using Traits = PoseTraits<Dim>;
  using Pose = typename Traits::Pose;
  using Rotation = typename Traits::Rotation;
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  using Map = VdtField<Dim>;  // the dense VdtMap or a SparseVdtMap3
  using Observations = ObservationSet<Dim>;
  using Disparity = BeamDisparityT<Dim>;
  using Curvature = BeamCurvatureT<Dim>;

  /// \throws ConfigError for a negative gate.
  VdtSensorModelT(const Map& map, const VdtSensorModelOptions& options = {});

  /// \brief Disparity and first derivatives of reading (p, u) at pose X (gate decided here), and
  /// the second derivatives when `curvature` is given.
  [[nodiscard]] Disparity disparity(const Pose& pose, const Vector& p, const Vector& u,
                                    Curvature* curvature = nullptr) const {
    return disparity(Traits::rotation(pose), Traits::translation(pose), p, u, curvature);
  }

  /// \brief As above at the pose with rotation R and translation t (the readings of one set share
  /// them).
  [[nodiscard]] Disparity disparity(const Rotation& r, const Vector& t, const Vector& p,
                                    const Vector& u, Curvature* curvature = nullptr) const;

  /// \brief disparity() without curvature for many readings of one set at one pose, through the
  /// map's batch lookup (SIMD kernels): out[k] for reading (*beams)[k], or for reading k when
  /// beams is null. What the estimators' passes over a scan call; `parts` says which derivatives
  /// they need (the others are left as they were).
  void disparities(const Rotation& r, const Vector& t, const Observations& observations,
                   const std::vector<int>* beams, std::vector<Disparity>* out,
                   DisparityParts parts = DisparityParts::kAll) const;

  /// \brief Disparity only (no derivatives: the cheaper lookup), whether the reading is an
  /// inlier and whether it is inside the map, for residual-only evaluations and gating.
  [[nodiscard]] Vector disparity_value(const Rotation& r, const Vector& t, const Vector& p,
                                       bool* inlier, bool* inside = nullptr) const;

  /// \brief Dim x Dim covariance of d_i from the range noise (and the map-noise floor).
  [[nodiscard]] Matrix disparity_covariance(const Disparity& b, double sigma_range) const;

  /// \brief Dim x Dim covariance of d_i from a point covariance (robot frame) and the map-noise
  /// floor: d_point cov d_point^T + sigma_map^2 I (the diagonal mode keeps only its diagonal).
  [[nodiscard]] Matrix disparity_covariance_point(const Disparity& b, const Matrix& cov) const;

  /// \brief d_VCD (2.17) over the inlier readings at pose X; counts inliers if asked.
  [[nodiscard]] double vector_chamfer_distance(const Pose& pose, const Observations& observations,
                                               int* inliers = nullptr) const;

  [[nodiscard]] const VdtSensorModelOptions& options() const noexcept { return options_; }
  [[nodiscard]] double map_sigma() const noexcept { return map_sigma_; }
  /// \brief sigma_c of the map error shared by a group of readings (0: the model is off).
  [[nodiscard]] double map_sigma_correlated() const noexcept { return map_sigma_correlated_; }
  /// \brief The group of a world-frame endpoint: a key of its square (cube) of side
  /// options().map_correlation_length (call only when map_sigma_correlated() > 0).
  [[nodiscard]] std::int64_t map_error_group(const Vector& world_point) const noexcept;
  [[nodiscard]] const Map& map() const noexcept { return *map_; }

 private:
  [[nodiscard]] bool passes_gate(const Vector& d) const noexcept;
  /// The disparity of the reading (p, u) from the map's sample at its endpoint R p + t, given
  /// rp = R p.
  [[nodiscard]] Disparity from_sample(const VdtSample<Dim>& sample, const Rotation& r,
                                      const Vector& rp, const Vector& u) const;

  const Map* map_;
  VdtSensorModelOptions options_;
  double map_sigma_;
  double map_sigma_correlated_ = 0.0;
};

extern template class VdtSensorModelT<2>;
extern template class VdtSensorModelT<3>;

using BeamDisparity = BeamDisparityT<2>;
using BeamDisparity3 = BeamDisparityT<3>;
using BeamCurvature = BeamCurvatureT<2>;
using BeamCurvature3 = BeamCurvatureT<3>;
using VdtSensorModel = VdtSensorModelT<2>;
using VdtSensorModel3 = VdtSensorModelT<3>;

}  // namespace vdtnav
