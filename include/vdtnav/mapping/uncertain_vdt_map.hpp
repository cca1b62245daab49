#pragma once
/// \file
/// \brief Uncertain VDT maps (thesis ch. 5): cubic B-spline surfaces for DT_x and DT_y fitted to
/// noisy scans through the Eikonal equation, with the covariance of their control points.
///
/// The field. Control points c_m = (cx_m, cy_m) on a square lattice of spacing h; for u = (p - o)/h
/// in cell (i, j), t = u - (i, j),
///   DT_v(p) = sum_{a,b=0..3} w_a(t_x) w_b(t_y) c_{i-1+a, j-1+b}                    (5.8)-(5.10)
/// with the uniform cubic B-spline weights w (the rows of (5.9) / 6). Only the control points of
/// cells within `band` of an observed point are unknowns; elsewhere the map is not defined
/// (inside = false).
///
/// The fit (5.15), a weighted sparse non-linear least-squares problem solved by Ceres:
///  - Eikonal samples s (a few per cell of the band, not on a cut locus, where the nearest observed
///    point jumps), with J = dDT_v/dp and v = DT_v(s):
///      away from the boundary (|v| >= near)  r_E = (J^T - I) v / |v|,
///      near it                               r_E = (det(J - I), J_01 - J_10),
///    both weighted by 1 / eikonal_sigma. The VDT satisfies grad(|v|^2 / 2) = J^T v = v, which
///    implies (5.3) (|J^T v|^2 / |v|^2 = 1) and also fixes the direction of v, which (5.3) leaves
///    free; near the boundary both divide by ~0, so there the residual says what stays true across
///    it: J is the (symmetric) Hessian of DT_u^2 / 2 with a unit eigenvalue (along the normal).
///    Without it noisy points pull a flat zero plateau across the wall.
///  - boundary points (5.4), (5.12) corrected per SPEC: reading k of scan s ends at
///      o_k = R(phi_s) p_k + t_s,   r_B = DT_v(o_k) / sigma_k,
///    sigma_k^2 = sigma_r^2 + boundary_sigma^2 + sigma_X,k^2: range noise, the spline's
///    approximation error at corners, and the scan's pose noise at the point, the mean variance
///    of do_k/dX cov(X_s) (do_k/dX)^T (5.13) — this is (5.14)'s weight of the boundary term.
///    The pose noise is shared by all the readings of a scan, which the weight cannot say: the
///    covariance below carries it as one error per scan (5.13 applied per point as if
///    independent would make the map far too confident).
///  - optionally (estimate_scan_poses) the scans' pose errors dX_s are unknowns with the prior
///    N(0, cov(X_s)), o_k = R(phi_s + dphi_s) p_k + t_s + dt_s, and sigma_k drops sigma_X,k: the
///    scans are aligned by the way. Measured on Experiment 2 (README), the alignment is biased —
///    started at the true poses it moves them 4.4 cm away, absorbing what the spline cannot follow
///    at corners into the poses — so the default holds the poses and considers their errors.
///  - free space (free_space): a beam passes through the cells between its sensor and its end.
///    A reading whose endpoint cell (on the raster of h / 4, at most 5 cm) the beams cross more
///    often than they end in — a person who walked on, a reflection — is dropped, with the
///    occupancy grid's rule: l_occ hits + l_free crossings <= 0 (OccupancyMapperOptions' log-odds).
///    And at an Eikonal sample the beams cross, farther than `near` from the observed points, the
///    field may not come closer to zero than the observed points are:
///      r_F = max(0, d(s) - 2 sigma_r - |DT_v(s)|) / free_sigma,  d(s) = distance to the nearest
///    observed point. Without it the spline carries a wall's zero level a few centimetres on into
///    a doorway the beams pass through (the wall-end bias, README: Uncertain VDT maps).
///  - a weak prior N(c0, prior_sigma^2) on every control point (c0: the exact VDT of the observed
///    points at the control point) keeps the control points at the band's edge determined.
///
/// The covariance (5.16)-(5.19). At the optimum the gradient of the cost in the control points c
/// vanishes, so by the implicit function theorem dc/dz = -A^-1 d^2h/(dc dz) for the observations
/// z (ranges, scan poses), A the Gauss-Newton information of c. Every residual is weighted by the
/// inverse of its noise, so the ranges (and the Eikonal pseudo-observations, of weight
/// 1 / eikonal_sigma^2) contribute A^-1 (conservatively: the pose share of sigma_k is counted
/// there as independent too), and the scans' pose errors, shared per scan, A^-1 B cov(X) B^T A^-1
/// with B = d^2h/(dc dX):
///   cov(c) = Z + Y Y^T,   Z = A^-1,   Y = Z B L,   L L^T = cov(X)
/// (with estimate_scan_poses, the marginal of the joint information instead: Y = Z B L^-T,
/// L L^T = D - B^T Z B; mapping/marginal_covariance.hpp). Z is sparse and local, and only its
/// blocks for pairs of control points that share a cell's support are computed, on the pattern
/// of A's sparse Cholesky factor by Takahashi's recursion; Y (control points x 3 per scan) carries
/// the scans' shared pose errors exactly. Never a dense inverse of A.
///
/// What the spline cannot follow (corners come out rounded, thesis 5.4; a staircase of cells is
/// smoothed) is not in cov(c): it is measured per cell from the readings' residuals, with each
/// scan's pose error (fitted to all its readings) taken out and the range noise and the field's
/// own variance subtracted, and added as a variance of DT_v shared by the cell. Where no reading
/// shows it — a wall end the spline extends a few centimetres into a doorway — it stays unknown.
///
/// A query returns DT_v, its Jacobian and the 2 x 2 covariance of DT_v, B cov(c) B^T over the
/// cell's 16 control points plus the cell's approximation variance. B cov(c) B^T is a quadratic
/// form in the cell's 16 B-spline weights, whose 3 x 136 coefficients are kept per cell of the
/// band (the cell's block of Z + Y Y^T, summed once after the fit): a query costs as much on a
/// building as on a room, whatever the number of scans. propagate() gives a pose
/// estimate's map term with the correlations between its readings' endpoints (the local blocks of
/// Z within three control points, all of Y Y^T, and the approximation variance per cell).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/map_uncertainty.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/mapping/eikonal_residuals.hpp"
#include "vdtnav/mapping/map_scan.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::mapping {

/// \brief Settings of the fit. Defaults come from the spacing h (documented per field).
struct UncertainMapOptions {
  /// h, metres between control points; <= 0: from the data (spacing_from_data()).
  double spacing = 0.2;
  /// Metres around the observed points where the map is defined (Eikonal samples, unknowns);
  /// < 0: max(0.75, 3 h), past the default gate (0.5 m) of the sensor model.
  double band = -1.0;
  int samples_per_axis = 2;    ///< Eikonal samples per cell and axis
  double eikonal_sigma = 0.2;  ///< sigma of r_E (dimensionless): 1 / sqrt(rho_e)
  /// Eikonal samples closer than this to an observed point take the form of r_E that holds
  /// across the boundary (see the file comment); < 0: h / 2.
  double near = -1.0;
  /// Approximation floor added to every reading's noise, metres (the spline rounds corners);
  /// < 0: h / 40.
  double boundary_sigma = -1.0;
  double prior_sigma = 1.0;  ///< metres, the weak prior on every control point
  /// Readings kept per scan and cell (evenly spread over the scan's readings there); 0: all.
  int max_points_per_cell = 4;
  /// Estimate the scans' pose errors with the map (their prior: MapScan::pose_covariance) instead
  /// of holding the given poses and considering their errors (see the file comment: biased).
  bool estimate_scan_poses = false;
  /// A sample is on a cut locus when the nearest observed point moves by more than this times
  /// the distance the sample moves (h / 2 along each axis).
  double cut_locus_ratio = 1.5;
  /// Free space from the beams (see the file comment): readings whose endpoint the beams cross
  /// more than they end in are dropped, and the Eikonal samples the beams cross keep the field
  /// off zero there.
  bool free_space = true;
  /// sigma of the free-space residual r_F, metres; < 0: h / 10.
  double free_sigma = -1.0;
  bool compute_covariance = true;
  int max_iterations = 100;
  /// The fit stops when an iteration lowers the cost by less than this fraction. The first few
  /// iterations place the boundary; the rest creep: on Experiment 2, 1e-3 stops after 6
  /// iterations (1.6 s) with the boundary RMS and the localization on the map of 1e-6's 67.
  double function_tolerance = 1e-3;
  int threads = 1;
  /// \throws ConfigError for a non-positive spacing or sigma, or samples_per_axis < 1.
  void validate() const;
};

/// \brief The spacing of the control points the readings support: five times the median gap
/// between consecutive readings of a scan on one surface (gaps under 0.5 m), rounded to 5 cm and
/// held within [0.2, 0.5] m. A cell then holds a few readings of every scan that sees its wall
/// broadside; a closer lattice follows corners no better than the readings' spread (the Intel
/// lab: 0.04 m at 0.15 m against 0.041 m at 0.25 m, README) at 2.5 times the unknowns.
/// \return 0.25 when no two consecutive readings are under 0.5 m apart.
[[nodiscard]] double spacing_from_data(const std::vector<MapScan>& scans);

/// \brief What a fit did.
struct UncertainMapSummary {
  bool converged = false;      ///< Ceres reached a minimum within max_iterations
  bool covariance_ok = false;  ///< the marginal blocks were computed (H positive definite)
  std::string message;         ///< Ceres's report, or why the covariance failed
  int iterations = 0;
  double spacing = 0.0;    ///< h the fit used, metres (spacing_from_data() when not given)
  int control_points = 0;  ///< unknown control points (2 coefficients each)
  int boundary_points = 0;
  int eikonal_samples = 0;
  int cut_locus_samples = 0;   ///< samples removed near cut loci
  int free_space_samples = 0;  ///< Eikonal samples the beams cross, with the free-space residual
  int cleared_readings = 0;  ///< readings dropped: the beams cross their endpoint more than end in
  int scan_poses = 0;        ///< scans whose pose errors were estimated (3 unknowns each)
  double initial_cost = 0.0, final_cost = 0.0;
  double fit_seconds = 0.0, covariance_seconds = 0.0;
};

/// \brief DT_v at a point with its Jacobian and covariance.
struct UncertainMapSample {
  Eigen::Vector2d value = Eigen::Vector2d::Zero();       ///< DT_v, metres
  Eigen::Matrix2d jacobian = Eigen::Matrix2d::Zero();    ///< dDT_v/dp (row c: gradient of DT_c)
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  ///< cov(DT_v), metres^2
  bool inside = false;  ///< the point is in the fitted band (else everything is zero)
};

/// \brief A fitted uncertain VDT map.
class UncertainVdtMap final : public MapUncertainty<2> {
 public:
  /// \brief The covariance of the control points, cov(c) = Z + Y Y^T, as flat arrays (map files:
  /// io/uncertain_map_file.hpp), with whoever keeps them alive (the fit's vectors or a file
  /// mapping). n control points, m cells in the band (in the lattice's order, x fastest).
  static constexpr int kFormTerms = 136;  ///< pairs k <= l of a cell's 16 weights

  struct CovarianceArrays {
    /// n x 49 blocks 2 x 2 (row-major): Z between a control point and the one at (da, db) in
    /// [-3, 3]^2 (da fastest); NaN where that neighbour is not an unknown.
    const float* z = nullptr;
    /// Y, 2n rows (c_x, c_y of each control point) by y_columns (3 per scan), compressed rows.
    const std::uint32_t* y_row_start = nullptr;  ///< 2n + 1 offsets into y_column, y_value
    const std::uint32_t* y_column = nullptr;
    const float* y_value = nullptr;
    std::uint32_t y_columns = 0;
    /// m x 3 x 136: per cell of the band, cov(DT_v)'s xx, xy and yy entries as quadratic forms in
    /// the cell's 16 weights w (coefficients of w_k w_l for k <= l, k-major; see evaluate()).
    const float* cell_forms = nullptr;
    std::shared_ptr<const void> owner;
    [[nodiscard]] bool empty() const noexcept { return z == nullptr; }
  };

  /// \brief Everything a map is (map files): the lattice, the band, the control points, the
  /// per-cell approximation variance, the observed points and the covariance's arrays.
  struct Parts {
    double spacing = 0.0;              ///< h, metres
    double approximation_sigma = 0.0;  ///< see approximation_sigma()
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    Eigen::Vector2i cells = Eigen::Vector2i::Zero();
    std::vector<char> active;               ///< per cell, x fastest
    std::vector<float> approximation_var;   ///< per cell, metres^2 (empty: none)
    std::vector<std::int32_t> vars;         ///< per padded control point: its unknown, or -1
    std::vector<double> coefficients;       ///< 2 per unknown, metres
    std::vector<Eigen::Vector2d> observed;  ///< the observed points
    CovarianceArrays covariance;            ///< empty: no covariance
  };

  /// \brief A map from its parts, checked (sizes, indices, finite values).
  /// \throws ConfigError naming what is inconsistent.
  [[nodiscard]] static UncertainVdtMap assemble(Parts parts);
  /// \brief The map's parts (the covariance's arrays shared, not copied).
  [[nodiscard]] Parts parts() const;
  /// \return the number of cells in the band.
  [[nodiscard]] std::size_t band_cells() const noexcept { return band_cells_; }

  /// \brief Fits the map to the scans (see the file comment).
  /// \throws ConfigError for invalid options, or when no scan has a reading.
  [[nodiscard]] static UncertainVdtMap fit(const std::vector<MapScan>& scans,
                                           const UncertainMapOptions& options);

  /// \brief The least-squares B-spline approximation of a known VDT (Fig. 5.2): control points
  /// at spacing options.spacing over the band around `boundary`, fitted to `vdt` at 4 x 4 samples
  /// per cell away from its cut loci (no covariance).
  [[nodiscard]] static UncertainVdtMap approximate(
      const std::vector<Eigen::Vector2d>& boundary,
      const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& vdt,
      const UncertainMapOptions& options);

  /// \brief DT_v, its Jacobian and covariance at world point p.
  [[nodiscard]] UncertainMapSample evaluate(const Eigen::Vector2d& p) const;

  bool dt_covariance(const Eigen::Vector2d& p, Eigen::Matrix2d* cov) const override;

  /// \brief cov(sum_i s_i e(q_i)) over the points in the band (MapUncertainty): with g_m the
  /// sum of s_i w_m(q_i) over the readings whose support holds control point m,
  /// sum_{m,n} g_m Z_mn g_n^T (pairs within three control points) + (sum_m g_m Y_m)(...)^T.
  [[nodiscard]] Eigen::Matrix3d propagate(const std::vector<Eigen::Vector2d>& q,
                                          const std::vector<Sensitivity>& s,
                                          std::vector<char>* known) const override;

  /// \brief A VdtMap sampling the fitted field at `resolution` (the exact VDT of the observed
  /// points outside the band), for the localizers.
  [[nodiscard]] VdtMap2 to_vdt_map(double resolution) const;

  /// \brief The scan poses after the fit (pose + dX*).
  [[nodiscard]] const std::vector<Pose2>& scan_poses() const noexcept { return scan_poses_; }
  [[nodiscard]] const UncertainMapSummary& summary() const noexcept { return summary_; }
  [[nodiscard]] double spacing() const noexcept { return h_; }
  /// \return the per-reading floor the fit gave the boundary residuals, metres (the spline's
  /// approximation error at corners, UncertainMapOptions::boundary_sigma): a localizer's
  /// per-reading map floor on this map (VdtSensorModelOptions::map_sigma).
  [[nodiscard]] double approximation_sigma() const noexcept { return approximation_sigma_; }
  [[nodiscard]] const Eigen::Vector2d& origin() const noexcept { return origin_; }
  [[nodiscard]] const Eigen::Vector2i& cells() const noexcept { return cells_; }
  /// \return whether cell (i, j) is in the band.
  [[nodiscard]] bool cell_active(int i, int j) const noexcept;
  /// \return the observed points (world frame, at the given poses) the map was fitted to.
  [[nodiscard]] const std::vector<Eigen::Vector2d>& observed_points() const noexcept {
    return observed_;
  }

 private:
  UncertainVdtMap() = default;
  struct Problem;
  friend struct Problem;
  /// The variable index of control point (a, b) of the padded lattice, -1 when not an unknown.
  [[nodiscard]] int variable(int a, int b) const noexcept {
    return vars_[static_cast<std::size_t>(b) * (cells_.x() + 3) + a];
  }
  /// The basis and the variables of the 16 control points of the patch holding p.
  /// \return false outside the fitted band.
  bool locate(const Eigen::Vector2d& p, SplinePatchBasis* basis, std::array<int, 16>* vars,
              std::size_t* cell = nullptr) const;

  double h_ = 0.0;
  double approximation_sigma_ = 0.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  Eigen::Vector2i cells_ = Eigen::Vector2i::Zero();  // cells per axis
  std::vector<char> active_;                         // per cell
  /// Per cell: the variance of DT_v the spline cannot follow there (see fit()), metres^2.
  std::vector<float> approximation_var_;
  std::vector<int> vars_;           // per padded control point
  std::vector<int> v_col_, v_row_;  // padded lattice position per variable
  std::vector<double> coef_;        // 2 per variable
  /// The covariance's arrays (empty: no covariance); cov(c) = Z + Y Y^T.
  CovarianceArrays cov_;
  std::vector<std::int32_t> cell_slot_;  // per cell: its index among the band's cells, or -1
  std::size_t band_cells_ = 0;
  /// Numbers the band's cells (cell_slot_, band_cells_) and the unknowns' lattice positions.
  void index_cells();
  std::vector<Pose2> scan_poses_;
  std::vector<Eigen::Vector2d> observed_;
  UncertainMapSummary summary_;
  // The exact VDT of the observed points (initial guess, cut loci, the map outside the band).
  std::shared_ptr<const VdtMap2> raster_;
};

}  // namespace vdtnav::mapping
