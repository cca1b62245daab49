#pragma once
// The solvers the optimizer tests run with: Ceres with either trust region (the default: LM) and
// the dense Levenberg-Marquardt.

#include <ostream>

#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav::test {

struct SolverChoice {
  ScanSolver solver = ScanSolver::kCeres;
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;

  void apply(VdtOptimizerOptions& o) const {
    o.solver = solver;
    o.trust_region = trust_region;
  }
};

inline std::ostream& operator<<(std::ostream& os, const SolverChoice& c) {
  if (c.solver == ScanSolver::kDense) return os << "dense";
  return os << (c.trust_region == TrustRegion::kDogleg ? "ceres-dogleg" : "ceres-lm");
}

inline const SolverChoice kSolverChoices[] = {
    {ScanSolver::kDense, TrustRegion::kLevenbergMarquardt},
    {ScanSolver::kCeres, TrustRegion::kLevenbergMarquardt},
    {ScanSolver::kCeres, TrustRegion::kDogleg}};

}  // namespace vdtnav::test
