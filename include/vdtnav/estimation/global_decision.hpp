#pragma once
/// \file
/// \brief The end of a global localization in either dimension (global_localization.hpp in 2D,
/// global_localization3d.hpp in 3D): the distinct leaves of the branch and bound refined by the
/// VDT optimizer, and the decision — the best by truncated VCD, refused when it explains less
/// than accept_fraction of the scan, ambiguous (and refused) when a distinct refined alternative
/// explains at least as much less ambiguity_margin and passes accept_fraction itself.

#include <algorithm>
#include <utility>
#include <vector>

#include "vdtnav/core/parallel.hpp"
#include "vdtnav/estimation/guess_search.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {

/// \brief What the decision needs of the search's options.
struct GlobalDecisionOptions {
  double truncation = 0.3;  ///< tau of the truncated VCD that ranks the refined poses
  double explained_distance = 0.1;
  double accept_fraction = 0.75;
  double ambiguity_margin = 0.05;
};

/// \brief The refined best and the decision.
template <int Dim>
struct GlobalDecision {
  using Pose = typename PoseTraits<Dim>::Pose;
  /// The best refined pose; status kRefused when unexplained or ambiguous (or when no
  /// refinement succeeded), else the refinement's own.
  LocalizationResultT<Dim> result;
  bool ambiguous = false;
  std::vector<Pose> alternatives;  ///< distinct refined poses that explain the scan as well
  double explained = 0.0;          ///< fraction of the scan the best explains
};

/// \brief Refines `starts` (on the pool's threads, each into its own place; a solve stopped at
/// its iteration limit continues once) and decides (the file comment). `distinct(a, b)` says
/// whether two poses are different places.
template <int Dim, typename Distinct>
[[nodiscard]] GlobalDecision<Dim> refine_and_decide(
    const VdtOptimizerT<Dim>& optimizer, const ObservationSet<Dim>& scan,
    const std::vector<typename PoseTraits<Dim>::Pose>& starts, const GlobalDecisionOptions& o,
    Distinct distinct) {
  struct Refined {
    LocalizationResultT<Dim> result;
    double score = 0.0, explained = 0.0;
  };
  const auto& model = optimizer.sensor_model();
  std::vector<Refined> solved(starts.size());
  parallel_for(starts.size(), [&](std::size_t k) {
    Refined& f = solved[k];
    f.result = optimizer.solve(scan, starts[k]);
    if (f.result.status == LocalizationStatus::kNotConverged) {
      // Stopped at its iteration limit from a start a cell and a heading step away: once more.
      const int spent = f.result.iterations;
      f.result = optimizer.solve(scan, f.result.pose);
      f.result.iterations += spent;
    }
    if (f.result.status == LocalizationStatus::kDiverged) return;
    f.score = truncated_vcd(model, scan, f.result.pose, o.truncation);
    f.explained = explained_fraction(model, scan, f.result.pose, o.explained_distance);
  });
  std::vector<Refined> refined;
  for (Refined& f : solved) {
    if (f.result.status != LocalizationStatus::kDiverged) refined.push_back(std::move(f));
  }
  GlobalDecision<Dim> out;
  if (refined.empty()) {
    out.result.status = LocalizationStatus::kRefused;
    return out;
  }
  std::sort(refined.begin(), refined.end(),
            [](const Refined& a, const Refined& b) { return a.score < b.score; });
  const Refined& best = refined.front();
  out.result = best.result;
  out.explained = best.explained;
  for (std::size_t k = 1; k < refined.size(); ++k) {
    const Refined& alt = refined[k];
    if (!distinct(alt.result.pose, best.result.pose)) continue;
    if (alt.explained >= o.accept_fraction &&
        alt.explained >= best.explained - o.ambiguity_margin) {
      out.ambiguous = true;
      out.alternatives.push_back(alt.result.pose);
    }
  }
  if (best.explained < o.accept_fraction || out.ambiguous) {
    out.result.status = LocalizationStatus::kRefused;
  }
  return out;
}

}  // namespace vdtnav
