// vdtnav::estimation built without Ceres (CMake found none, or -DCMAKE_DISABLE_FIND_PACKAGE_Ceres):
// the dense solver does every scan solve; what needs the Ceres backend (ceres_backend.hpp) says so.
#include <string>
#include <vector>

#include "ceres_backend.hpp"
#include "scan_solve.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::detail {
namespace {

[[noreturn]] void no_ceres(const char* what) {
  throw ConfigError(std::string(what) +
                    " needs Ceres, and this vdtnav was built without it (install libceres-dev "
                    "and rebuild)");
}

}  // namespace

bool ceres_backend_available() { return false; }

ChamferSolve solve_chamfer(const DistanceFieldMap<2>& /*udt*/, const ScanPoints& /*scan*/,
                           const std::vector<int>& /*beams*/, int /*max_iterations*/,
                           double* /*x*/) {
  no_ceres("udt-opt's chamfer solve");
}

template <int Dim>
ScanLmSummary run_ceres_solver(const VdtSensorModelT<Dim>& /*model*/,
                               const ObservationSet<Dim>& /*scan*/,
                               const std::vector<int>& /*beams*/,
                               const std::vector<double>& /*sqrt_w*/, RobustLoss /*loss*/,
                               double /*loss_scale*/, const SolveSetup& /*setup*/,
                               const PosePrior<Dim>* /*prior*/, double* /*x*/) {
  no_ceres("the optimizer's solver 'ceres'");
}

VDTNAV_INSTANTIATE_RUN_CERES_SOLVER(2);
VDTNAV_INSTANTIATE_RUN_CERES_SOLVER(3);

}  // namespace vdtnav::detail
