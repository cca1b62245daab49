// udt-opt's chamfer solve on Ceres (ceres_backend.hpp): all readings as one residual block.
#include <ceres/ceres.h>

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "ceres_backend.hpp"
#include "vdtnav/estimation/udt_localizers.hpp"

namespace vdtnav::detail {
namespace {

/// e_i = DT_u(pose (+) p_i), d e_i / d(x, y, phi) from udt_beam.
class ChamferCost final : public ceres::CostFunction {
 public:
  ChamferCost(const DistanceFieldMap<2>& udt, const ScanPoints& scan, std::vector<int> beams)
      : udt_(udt), scan_(scan), beams_(std::move(beams)) {
    set_num_residuals(static_cast<int>(beams_.size()));
    mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    const Pose2 pose(params[0][0], params[0][1], params[0][2]);
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    for (std::size_t k = 0; k < beams_.size(); ++k) {
      const int i = beams_[k];
      const UdtBeam b = udt_beam(udt_, pose, c, s, scan_.points[i], scan_.directions[i], 1e9);
      residuals[k] = b.e;
      if (jacobians != nullptr && jacobians[0] != nullptr) {
        for (int j = 0; j < 3; ++j) jacobians[0][3 * k + j] = b.e_pose[j];
      }
    }
    return true;
  }

 private:
  const DistanceFieldMap<2>& udt_;
  const ScanPoints& scan_;
  std::vector<int> beams_;
};

}  // namespace

ChamferSolve solve_chamfer(const DistanceFieldMap<2>& udt, const ScanPoints& scan,
                           const std::vector<int>& beams, int max_iterations, double* x) {
  ceres::Problem::Options po;
  po.disable_all_safety_checks = true;
  ceres::Problem problem(po);
  problem.AddResidualBlock(new ChamferCost(udt, scan, beams), nullptr, x);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-6;
  so.parameter_tolerance = 1e-6;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  ChamferSolve out;
  out.iterations = static_cast<int>(summary.iterations.size());
  out.final_cost = summary.final_cost;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.failed = summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost);
  return out;
}

}  // namespace vdtnav::detail
