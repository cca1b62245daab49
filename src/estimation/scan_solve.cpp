// One solve of VdtOptimizerT (the dense LM of scan_lm.hpp, or the Ceres backend behind
// run_ceres_solver) and the Cauchy IRLS passes of the coarse alignment. Eigen only.
#include "scan_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "scan_lm.hpp"

namespace vdtnav::detail {

template <int Dim>
ScanLmSummary run_solver(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                         const std::vector<int>& beams, const std::vector<double>& sqrt_w,
                         RobustLoss loss, double loss_scale, const SolveSetup& setup,
                         const PosePrior<Dim>* prior, double* x) {
  if (setup.solver == ScanSolver::kCeres) {
    return run_ceres_solver<Dim>(model, scan, beams, sqrt_w, loss, loss_scale, setup, prior, x);
  }
  ScanLmSettings ls;
  ls.max_iterations = setup.max_iterations;
  ls.parameter_tolerance = setup.parameter_tolerance;
  ls.step_sigma = setup.step_sigma;
  ls.newton = setup.newton;
  ls.floor_min = setup.newton_floor;
  // sigma of (C); a floor of 1 mm for a noiseless reading on an exact map.
  ls.sigma = std::sqrt(std::max(disparity_variance(model, scan), 1e-6));
  ls.held_mask = (Dim == 3 && setup.four_dof) ? (1u << 3 | 1u << 4) : 0u;  // see is_free()
  typename PoseTraits<Dim>::Pose pose = Parameterization<Dim>::pose(x);
  const ScanLmSummary out =
      solve_scan_lm<Dim>(model, scan, beams, sqrt_w, loss, loss_scale, ls, &pose, prior);
  Parameterization<Dim>::set(pose, x);
  return out;
}

template <int Dim>
int solve_cauchy_irls(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                      const std::vector<int>& beams, double scale, const SolveSetup& setup,
                      int passes, const PosePrior<Dim>* prior, double* x) {
  using Traits = PoseTraits<Dim>;
  int iterations = 0;
  std::vector<double> sqrt_w(beams.size());
  thread_local std::vector<BeamDisparityT<Dim>> ds;  // scratch: no allocation per scan
  for (int pass = 0; pass < passes; ++pass) {
    const typename Traits::Pose at = Parameterization<Dim>::pose(x);
    model.disparities(Traits::rotation(at), Traits::translation(at), scan, &beams, &ds,
                      DisparityParts::kValue);
    for (std::size_t k = 0; k < beams.size(); ++k) {
      sqrt_w[k] = std::sqrt(robust_weight(RobustLoss::kCauchy, scale, ds[k].d.squaredNorm()));
    }
    iterations +=
        run_solver(model, scan, beams, sqrt_w, RobustLoss::kNone, 1.0, setup, prior, x).iterations;
  }
  return iterations;
}

template ScanLmSummary run_solver<2>(const VdtSensorModelT<2>&, const ObservationSet<2>&,
                                     const std::vector<int>&, const std::vector<double>&,
                                     RobustLoss, double, const SolveSetup&, const PosePrior<2>*,
                                     double*);
template ScanLmSummary run_solver<3>(const VdtSensorModelT<3>&, const ObservationSet<3>&,
                                     const std::vector<int>&, const std::vector<double>&,
                                     RobustLoss, double, const SolveSetup&, const PosePrior<3>*,
                                     double*);
template int solve_cauchy_irls<2>(const VdtSensorModelT<2>&, const ObservationSet<2>&,
                                  const std::vector<int>&, double, const SolveSetup&, int,
                                  const PosePrior<2>*, double*);
template int solve_cauchy_irls<3>(const VdtSensorModelT<3>&, const ObservationSet<3>&,
                                  const std::vector<int>&, double, const SolveSetup&, int,
                                  const PosePrior<3>*, double*);

}  // namespace vdtnav::detail
