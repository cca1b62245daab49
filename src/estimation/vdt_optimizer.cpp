// VdtOptimizerT (thesis 3.2, Algorithm 1's OPTIMIZE; 3D: 3.4.4): construction, the coarse map
// pyramid, and the solve: coarse-to-fine alignment, gating (3.3) and the fine solves of (2.17).
#include "vdtnav/estimation/vdt_optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "ceres_backend.hpp"
#include "lookup_order.hpp"
#include "scan_lm.hpp"
#include "scan_solve.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

/// Iterations of each coarse solve in 3D, and readings it uses at most (see solve()).
constexpr int kCoarseIterations3d = 6;
constexpr std::size_t kCoarsePoints3d = 1000;

using detail::lookup_order;
using detail::Parameterization;
using detail::run_solver;
using detail::solve_cauchy_irls;
using detail::SolveSetup;

}  // namespace

template <int Dim>
VdtOptimizerT<Dim>::VdtOptimizerT(const Field& map, const VdtOptimizerOptions& options)
    : model_(map, options.sensor), options_(options) {
  validate_and_default();
  coarse_maps_ = build_pyramid(map, options_.pyramid_levels);
  options_.pyramid_levels = static_cast<int>(coarse_maps_->size());  // 0 on a sparse map
  make_coarse_models();
}

template <int Dim>
VdtOptimizerT<Dim>::VdtOptimizerT(const VdtOptimizerT& other, const VdtOptimizerOptions& options)
    : model_(other.model_.map(), options.sensor), options_(options) {
  validate_and_default();
  coarse_maps_ = options_.pyramid_levels == other.options_.pyramid_levels
                     ? other.coarse_maps_
                     : build_pyramid(other.model_.map(), options_.pyramid_levels);
  options_.pyramid_levels = static_cast<int>(coarse_maps_->size());
  make_coarse_models();
}

template <int Dim>
void VdtOptimizerT<Dim>::validate_and_default() {
  const VdtOptimizerOptions& options = options_;
  VDTNAV_CHECK(options.max_iterations >= 1, "optimizer: max_iterations must be >= 1");
  VDTNAV_CHECK(options.solver != ScanSolver::kCeres || detail::ceres_backend_available(),
               "optimizer: solver 'ceres' needs Ceres, and this vdtnav was built without it "
               "(install libceres-dev and rebuild, or use the default solver 'dense')");
  VDTNAV_CHECK(options.function_tolerance > 0.0 && options.function_tolerance < 1.0,
               "optimizer: function_tolerance must be in (0, 1)");
  VDTNAV_CHECK(options.step_sigma > 0.0 && std::isfinite(options.step_sigma),
               "optimizer: step_sigma must be finite and > 0");
  VDTNAV_CHECK(options.gate_rounds >= 1, "optimizer: gate_rounds must be >= 1");
  VDTNAV_CHECK(options.min_inliers >= 3, "optimizer: min_inliers must be >= 3");
  VDTNAV_CHECK(options.loss_scale > 0.0, "optimizer: loss_scale must be > 0");
  VDTNAV_CHECK(options.pyramid_levels >= -1, "optimizer: pyramid_levels must be >= -1");
  VDTNAV_CHECK(std::isfinite(options.coarse_threshold), "optimizer: coarse_threshold not finite");
  // Per-dimension defaults (see VdtOptimizerOptions).
  if (options_.pyramid_levels < 0) options_.pyramid_levels = Dim == 2 ? 2 : 3;
  if (options_.newton_floor < 0.0) options_.newton_floor = Dim == 2 ? 0.25 : 1.0 / 64.0;
  VDTNAV_CHECK(options_.newton_floor > 0.0 && options_.newton_floor <= 0.25,
               "optimizer: newton_floor must be in (0, 0.25] (< 0: the default)");
  if (options_.coarse_threshold < 0.0) options_.coarse_threshold = Dim == 2 ? 0.1 : 0.0;
  if constexpr (Dim == 2) options_.four_dof = false;  // a 3D option
}

template <int Dim>
std::shared_ptr<const std::vector<std::unique_ptr<VdtMap<Dim>>>> VdtOptimizerT<Dim>::build_pyramid(
    const Field& field, int levels) {
  auto maps = std::make_shared<std::vector<std::unique_ptr<Map>>>();
  // Coarse levels from a dense map's features; a sparse map has none (see the constructor).
  const auto* dense = dynamic_cast<const Map*>(&field);
  if (dense == nullptr) return maps;
  const Map& map = *dense;
  // Occupancy of the map: the cells that are their own nearest feature.
  using Index = typename SpaceTraits<Dim>::Index;
  const auto& nearest = map.nearest_cells();
  for (int level = levels; level >= 1; --level) {
    const int f = 1 << level;
    const Index size = ((nearest.size().array() + f - 1) / f).max(2);
    OccupancyGrid<Dim> coarse(
        size, GridFrame<Dim>(map.resolution() * f, map.frame().origin(), map.frame().yaw()), 0);
    for (std::size_t c = 0; c < nearest.num_cells(); ++c) {
      if (nearest[c] == static_cast<std::int32_t>(c))
        coarse(nearest.index_of(static_cast<std::ptrdiff_t>(c)) / f) = 1;
    }
    maps->push_back(std::make_unique<Map>(Map::build(coarse)));
  }
  return maps;
}

template <int Dim>
void VdtOptimizerT<Dim>::make_coarse_models() {
  for (const std::unique_ptr<Map>& coarse : *coarse_maps_) {
    VdtSensorModelOptions so = options_.sensor;
    so.gate = std::max(options_.sensor.gate, 4.0 * coarse->resolution());
    coarse_models_.emplace_back(*coarse, so);
  }
}

template <int Dim>
bool VdtOptimizerT<Dim>::is_free(int k) const noexcept {
  return !(Dim == 3 && options_.four_dof && (k == 3 || k == 4));
}

template <int Dim>
typename VdtOptimizerT<Dim>::Result VdtOptimizerT<Dim>::solve(const Observations& scan,
                                                              const Pose& guess) const {
  return solve_with(scan, guess, nullptr, 0.0);
}

template <int Dim>
typename VdtOptimizerT<Dim>::Result VdtOptimizerT<Dim>::solve(const Observations& scan,
                                                              const Pose& guess,
                                                              const PosePrior<Dim>& prior) const {
  VDTNAV_CHECK(prior.information.allFinite(), "optimizer: the prior's information is not finite");
  // The solvers minimise the plain VCD, 1/2 sum |d_i|^2 (2.17), not 1/2 sum d_i^T R_i^-1 d_i: the
  // prior joins it in the same units, times s^2, the a priori variance of one disparity component
  // (the map floor plus the readings' own noise spread over the Dim components):
  //   G = 1/2 sum |d_i|^2 + s^2 / 2 e^T I e,   i.e.  s^2 (1/2 sum |d_i|^2 / s^2 + 1/2 e^T I e).
  const double s2 = detail::disparity_variance(model_, scan);
  VDTNAV_CHECK(s2 > 0.0, "optimizer: a prior needs a disparity variance > 0 (map floor or noise)");
  PosePrior<Dim> scaled = prior;
  scaled.information *= s2;
  return solve_with(scan, guess, &scaled, s2);
}

template <int Dim>
typename VdtOptimizerT<Dim>::Result VdtOptimizerT<Dim>::solve_with(const Observations& scan,
                                                                   const Pose& guess,
                                                                   const PosePrior<Dim>* prior,
                                                                   double prior_s2) const {
  using P = Parameterization<Dim>;
  Result result;
  result.pose = guess;
  result.dropped = static_cast<int>(scan.dropped_not_finite + scan.dropped_out_of_range);
  double x[P::kAmbient];
  P::set(guess, x);
  const double alpha = options_.sensor.gate;
  SolveSetup setup{options_.solver, options_.trust_region, options_.max_iterations,
                   options_.four_dof, options_.function_tolerance};
  setup.step_sigma = options_.step_sigma;
  setup.newton = options_.newton;
  setup.newton_floor = options_.newton_floor;
  // IRLS passes per level of the coarse alignment: in 3D one pass per level already lands in the
  // basin of the fine solve, and each pass is a full solve over thousands of 3D lookups.
  constexpr int kIrlsPasses = Dim == 2 ? 3 : 1;
  // The coarse solves only have to land in the basin of the next level: in 3D, where an iteration
  // costs milliseconds, they stop early (a few iterations, ~0.5 mm at 5 m from the origin).
  SolveSetup coarse_setup = setup;
  if constexpr (Dim == 3) {
    coarse_setup.max_iterations = std::min(setup.max_iterations, kCoarseIterations3d);
    coarse_setup.function_tolerance = 1e-4;
    coarse_setup.parameter_tolerance = 1e-4;
  }
  // The coarse-to-fine passes only have to land in the basin of the next level: their test (C)
  // asks for a step within one sigma (of that level), and their IRLS weights, fixed per pass,
  // make Newton's curvature (N) moot (each pass's weighted Gauss-Newton solve is re-weighted).
  coarse_setup.step_sigma = std::max(setup.step_sigma, 1.0);
  coarse_setup.newton = false;
  const std::vector<int> order = lookup_order<Dim>(model_.map(), scan, guess);

  // Coarse alignment, only when the guess is poor (median disparity > coarse_threshold, 10 cm in
  // 2D, e.g. after a kidnap or a bad odometry step; always in 3D): a wide gate and a Cauchy loss
  // first pull the readings into the basin of the right surfaces without letting far, wrongly
  // associated ones dominate. In 2D a Cauchy pass on the fine map follows; in 3D the coarse pass
  // already lands in the basin of the fine solve (scenarios A and B of Table 3.4), which then
  // needs fewer fine lookups than a fine Cauchy pass would.
  constexpr bool kFineIrls = Dim == 2;
  const auto coarse_to_fine = [&](const std::vector<int>& wide) {
    // 3D: the coarse levels use an even subset of at most kCoarsePoints3d readings (every s-th
    // along the Z-order curve), plenty to find the basin at their resolution.
    const std::size_t stride =
        Dim == 2 ? 1 : std::max<std::size_t>(1, order.size() / kCoarsePoints3d);
    std::vector<int> subset;
    for (std::size_t k = 0; k < order.size(); k += stride) subset.push_back(order[k]);
    thread_local std::vector<BeamDisparityT<Dim>> ds;  // scratch: no allocation per scan
    for (const SensorModel& coarse : coarse_models_) {
      std::vector<int> beams;
      const Pose at = P::pose(x);
      coarse.disparities(Traits::rotation(at), Traits::translation(at), scan, &subset, &ds,
                         DisparityParts::kValue);
      for (std::size_t k = 0; k < subset.size(); ++k) {
        if (ds[k].inlier) beams.push_back(subset[k]);
      }
      if (beams.size() < static_cast<std::size_t>(options_.min_inliers)) continue;
      result.iterations += solve_cauchy_irls(coarse, scan, beams, coarse.options().gate / 4,
                                             coarse_setup, kIrlsPasses, prior, x);
    }
    if (kFineIrls) {
      result.iterations +=
          solve_cauchy_irls(model_, scan, wide, 0.1, coarse_setup, kIrlsPasses, prior, x);
    }
    result.work.coarse_to_fine = 1;
  };
  if (!kFineIrls && options_.coarse_threshold <= 0.0) {
    coarse_to_fine({});  // always: no need for the median
  } else {
    std::vector<double> norms;
    std::vector<int> wide;
    thread_local std::vector<BeamDisparityT<Dim>> ds;  // scratch: no allocation per scan
    model_.disparities(Traits::rotation(guess), Traits::translation(guess), scan, &order, &ds,
                       DisparityParts::kValue);
    for (std::size_t k = 0; k < order.size(); ++k) {
      if (!ds[k].inside) continue;
      const double n = ds[k].d.norm();
      norms.push_back(n);
      if (n < std::max(1.0, 2.0 * alpha)) wide.push_back(order[k]);
    }
    if (norms.size() >= static_cast<std::size_t>(options_.min_inliers)) {
      std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
      if (norms[norms.size() / 2] > options_.coarse_threshold) coarse_to_fine(wide);
    }
  }

  std::vector<char> inlier(scan.size(), 0);
  bool converged = false;
  thread_local std::vector<BeamDisparityT<Dim>> gated;  // scratch: no allocation per scan
  for (int round = 0; round < options_.gate_rounds; ++round) {
    // Gate (3.3) at the current estimate.
    const Pose at = P::pose(x);
    model_.disparities(Traits::rotation(at), Traits::translation(at), scan, &order, &gated,
                       DisparityParts::kValue);
    std::vector<int> beams;
    int changed = 0;
    for (std::size_t k = 0; k < order.size(); ++k) {
      const int i = order[k];
      const bool in = gated[k].inlier;
      changed += (in != (inlier[i] != 0)) ? 1 : 0;
      inlier[i] = in ? 1 : 0;
      if (in) beams.push_back(i);
    }
    // Solve again only if the gate changed its mind about more than 1 % of the beams.
    if (round > 0 && changed * 100 <= static_cast<int>(beams.size())) break;
    result.inliers = static_cast<int>(beams.size());
    result.dropped =
        static_cast<int>(scan.size() + scan.dropped_not_finite + scan.dropped_out_of_range) -
        result.inliers;
    if (result.inliers < options_.min_inliers) {
      result.status = LocalizationStatus::kTooFewObservations;
      result.pose = guess;
      return result;
    }
    const detail::ScanLmSummary summary =
        run_solver(model_, scan, beams, {}, options_.loss, options_.loss_scale, setup, prior, x);
    result.iterations += summary.iterations;
    ++result.work.solves;
    result.final_cost = 2.0 * summary.final_cost;  // solvers report sum/2: d_VCD = sum |d|^2
    if (summary.failed) {
      result.status = LocalizationStatus::kDiverged;
      result.pose = guess;
      return result;
    }
    converged = summary.converged;
  }
  result.pose = P::result(x, guess, options_.four_dof);
  result.status = converged ? LocalizationStatus::kConverged : LocalizationStatus::kNotConverged;
  // The covariance is reported whenever the Hessian at the estimate is positive definite, also
  // when Ceres stopped at its iteration limit (the status says so); otherwise it is not a minimum.
  result.has_covariance =
      covariance(scan, result.pose, inlier, order, prior != nullptr ? &prior->information : nullptr,
                 prior_s2, &result.covariance);
  if (!result.has_covariance) result.status = LocalizationStatus::kNotConverged;
  return result;
}

template class VdtOptimizerT<2>;
template class VdtOptimizerT<3>;

}  // namespace vdtnav
