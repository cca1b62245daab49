#pragma once
// The solves of VdtOptimizerT (thesis 3.2, Algorithm 1's OPTIMIZE): the pose's parameter block
// per dimension, the settings shared by the solves, one solve and the Cauchy IRLS passes. The
// dense solver (scan_lm.hpp) needs Eigen only; Ceres, the optional backend, is behind
// run_ceres_solver (scan_cost.cpp, or without_ceres.cpp when vdtnav is built without it).

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "scan_lm.hpp"
#include "se3_parameters.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/core/traits.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav::detail {

/// The parameter block of a pose in a solve: its size and the pose it holds (scan_cost.cpp adds
/// the Ceres manifold and how a Jacobian in the pose perturbation becomes one in the block).
template <int Dim>
struct Parameterization;

/// 2D: (x, y, phi) as they are, Euclidean (the additive perturbation of PoseTraits<2>).
template <>
struct Parameterization<2> {
  static constexpr int kAmbient = 3;
  static void set(const Pose2& pose, double* x) {
    x[0] = pose[0];
    x[1] = pose[1];
    x[2] = pose[2];
  }
  static Pose2 pose(const double* x) { return Pose2(x[0], x[1], x[2]); }
  static Pose2 result(const double* x, const Pose2& /*guess*/, bool /*four_dof*/) {
    return Pose2(x[0], x[1], wrap_angle(x[2]));
  }
};

/// 3D: (quaternion, t), se3_parameters.hpp.
template <>
struct Parameterization<3> {
  static constexpr int kAmbient = 7;
  static void set(const Pose3& pose, double* x) { se3_to_parameters(pose, x); }
  static Pose3 pose(const double* x) { return se3_from_parameters(x); }
  /// In the 4-DOF mode the attitude is rebuilt as Rz(psi) R_guess with an exact Rz, whose last
  /// row (0, 0, 1) leaves the last row of R_guess, and so roll and pitch, bit for bit unchanged.
  static Pose3 result(const double* x, const Pose3& guess, bool four_dof) {
    Pose3 p = se3_from_parameters(x);
    if (four_dof) {
      const double psi = so3_log(p.linear() * guess.linear().transpose()).z();
      const double c = std::cos(psi), s = std::sin(psi);
      Eigen::Matrix3d rz;
      rz << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
      p.linear() = rz * guess.linear();
    }
    return p;
  }
};

/// What every solve of one optimizer shares.
struct SolveSetup {
  ScanSolver solver = ScanSolver::kCeres;
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  int max_iterations = 25;
  bool four_dof = false;
  double function_tolerance = 1e-6;   // Ceres's; the dense solver stops by (C) of scan_lm.hpp
  double parameter_tolerance = 1e-6;  // relative: ~10 micrometres at 10 m from the origin
  double step_sigma = 0.01;           // the convergence test (C) (scan_lm.hpp), in sigmas
  bool newton = true;                 // the dense solver's curvature (N) (scan_lm.hpp)
  double newton_floor = 0.25;         // the lowest floor of (K) (scan_lm.hpp)
};

/// The a priori variance of one disparity component, metres^2: the map's floor plus the
/// readings' own noise spread over the Dim components (their point covariances where given).
/// The sigma of the convergence test (C) and the units a prior joins the VCD in.
template <int Dim>
double disparity_variance(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan) {
  double noise = 0.0;
  if (!scan.point_covariances.empty()) {
    for (const auto& c : scan.point_covariances) noise += c.trace() / Dim;
    noise /= static_cast<double>(scan.point_covariances.size());
  } else {
    noise = scan.sigma_range * scan.sigma_range / Dim;
  }
  return model.map_sigma() * model.map_sigma() + noise;
}

/// One solve of the readings in `beams` from x (updated in place), weighted by sqrt_w (empty: 1),
/// with the prior term when `prior` is given: the dense solver, or Ceres's.
template <int Dim>
ScanLmSummary run_solver(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                         const std::vector<int>& beams, const std::vector<double>& sqrt_w,
                         RobustLoss loss, double loss_scale, const SolveSetup& setup,
                         const PosePrior<Dim>* prior, double* x);

/// run_solver's Ceres backend (scan_cost.cpp); throws ConfigError when vdtnav is built without
/// Ceres (without_ceres.cpp).
template <int Dim>
ScanLmSummary run_ceres_solver(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                               const std::vector<int>& beams, const std::vector<double>& sqrt_w,
                               RobustLoss loss, double loss_scale, const SolveSetup& setup,
                               const PosePrior<Dim>* prior, double* x);

/// The explicit instantiation of run_ceres_solver<Dim> (scan_cost.cpp, without_ceres.cpp).
#define VDTNAV_INSTANTIATE_RUN_CERES_SOLVER(Dim)                                                \
  template ScanLmSummary run_ceres_solver<Dim>(                                                 \
      const VdtSensorModelT<Dim>&, const ObservationSet<Dim>&, const std::vector<int>&,         \
      const std::vector<double>&, RobustLoss, double, const SolveSetup&, const PosePrior<Dim>*, \
      double*)

/// Iteratively reweighted least squares with a Cauchy loss of the given scale: each pass fixes
/// the weights w_i = 1 / (1 + |d_i|^2 / scale^2) at the current estimate and solves.
/// \return the solver iterations of all passes.
template <int Dim>
int solve_cauchy_irls(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                      const std::vector<int>& beams, double scale, const SolveSetup& setup,
                      int passes, const PosePrior<Dim>* prior, double* x);

}  // namespace vdtnav::detail
