#pragma once
// What vdtnav::estimation asks of Ceres, its optional solver backend: the scan solves of
// ScanSolver::kCeres (scan_solve.hpp's run_ceres_solver) and udt-opt's chamfer solve. Built with
// Ceres: scan_cost.cpp and udt_chamfer_cost.cpp; without: without_ceres.cpp, where each throws
// ConfigError and ceres_backend_available() is false, so a setting that needs Ceres is refused
// when it is read, with a message that says so.

#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::detail {

/// \return whether this build of vdtnav has the Ceres backend.
[[nodiscard]] bool ceres_backend_available();

/// What one chamfer solve did (the fields of ceres::Solver::Summary udt-opt reads).
struct ChamferSolve {
  int iterations = 0;
  double final_cost = 0.0;  ///< Ceres's: 1/2 sum e_i^2
  bool converged = false;
  bool failed = false;  ///< the solver failed, or the cost is not finite
};

/// Chamfer matching (thesis Table 3.3's C-LOG): minimises sum_i DT_u(pose (+) p_i)^2 over the
/// readings in `beams` from x = (x, y, phi), updated in place.
ChamferSolve solve_chamfer(const DistanceFieldMap<2>& udt, const ScanPoints& scan,
                           const std::vector<int>& beams, int max_iterations, double* x);

}  // namespace vdtnav::detail
