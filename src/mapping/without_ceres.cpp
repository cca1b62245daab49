// vdtnav::mapping built without Ceres (CMake found none, or -DCMAKE_DISABLE_FIND_PACKAGE_Ceres):
// occupancy mapping, the Eikonal residuals and reading a fitted map (uncertain_map_file) work;
// fitting one (the weighted problem (5.15), solved by Ceres) and its covariance (CHOLMOD, which
// comes with Ceres) say that they need them.
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/mapping/marginal_covariance.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"

namespace vdtnav::mapping {
namespace {

[[noreturn]] void no_ceres(const char* what) {
  throw ConfigError(std::string(what) +
                    " needs Ceres and SuiteSparse, and this vdtnav was built without them "
                    "(install libceres-dev and rebuild)");
}

}  // namespace

UncertainVdtMap UncertainVdtMap::fit(const std::vector<MapScan>& /*scans*/,
                                     const UncertainMapOptions& /*options*/) {
  no_ceres("fitting an uncertain VDT map");
}

UncertainVdtMap UncertainVdtMap::approximate(
    const std::vector<Eigen::Vector2d>& /*boundary*/,
    const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& /*vdt*/,
    const UncertainMapOptions& /*options*/) {
  no_ceres("the B-spline approximation of a VDT");
}

bool MarginalCovariance::compute(const Eigen::SparseMatrix<double>& /*h*/, Eigen::Index /*n_a*/,
                                 const std::vector<Eigen::MatrixXd>* /*considered*/,
                                 double /*drop*/) {
  no_ceres("the marginal covariance");
}

double MarginalCovariance::z(Eigen::Index /*a*/, Eigen::Index /*b*/) const {
  no_ceres("the marginal covariance");
}

}  // namespace vdtnav::mapping
