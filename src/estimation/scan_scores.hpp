#pragma once
// How well a map explains an observation set at a pose, in one batch lookup of its readings: the
// explained fraction and the truncated VCD of guess_search.hpp (2D) and multi_start.hpp (3D).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav::detail {

/// The share of the readings that are inliers with |d_i| < distance, given the disparities of all
/// the readings at one pose (any DisparityParts: the values and the gate are the same).
template <int Dim>
double explained_fraction_of(const std::vector<BeamDisparityT<Dim>>& ds, double distance) {
  if (ds.empty()) return 0.0;
  const double d2 = distance * distance;
  std::size_t n = 0;
  for (const BeamDisparityT<Dim>& b : ds) n += b.inlier && b.d.squaredNorm() < d2;
  return static_cast<double>(n) / static_cast<double>(ds.size());
}

/// The share of the readings that are inliers with |d_i| < distance, at the pose (R, t).
template <int Dim>
double explained_fraction_at(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& set,
                             const typename PoseTraits<Dim>::Rotation& r,
                             const typename SpaceTraits<Dim>::Vector& t, double distance) {
  if (set.size() == 0) return 0.0;
  thread_local std::vector<BeamDisparityT<Dim>> ds;  // scratch: no allocation per call
  model.disparities(r, t, set, nullptr, &ds, DisparityParts::kValue);
  return explained_fraction_of(ds, distance);
}

/// The truncated VCD sum_i min(|d_i|^2, tau^2), an unexplained reading counting tau^2, over the
/// readings `beams` (all when null), at the pose (R, t). The sum only grows, so a caller that only
/// wants to know whether it stays below `stop_at` (a window search's best score) gets any value
/// >= stop_at as soon as a prefix of the readings reaches it: the readings are looked up in
/// chunks and the rest is skipped.
template <int Dim>
double truncated_vcd_at(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& set,
                        const typename PoseTraits<Dim>::Rotation& r,
                        const typename SpaceTraits<Dim>::Vector& t, double tau,
                        const std::vector<int>* beams = nullptr,
                        double stop_at = std::numeric_limits<double>::infinity()) {
  constexpr std::size_t kChunk = 64;  // readings per batch lookup between checks of stop_at
  thread_local std::vector<BeamDisparityT<Dim>> ds;  // scratch: no allocation per call
  thread_local std::vector<int> chunk;
  const std::size_t n = beams != nullptr ? beams->size() : set.size();
  const std::size_t step = std::isfinite(stop_at) ? kChunk : std::max<std::size_t>(n, 1);
  const double t2 = tau * tau;
  double sum = 0.0;
  for (std::size_t first = 0; first < n && sum < stop_at; first += step) {
    const std::size_t last = std::min(n, first + step);
    chunk.resize(last - first);
    for (std::size_t k = first; k < last; ++k)
      chunk[k - first] = beams != nullptr ? (*beams)[k] : static_cast<int>(k);
    model.disparities(r, t, set, &chunk, &ds, DisparityParts::kValue);
    for (const BeamDisparityT<Dim>& b : ds) sum += b.inlier ? std::min(b.d.squaredNorm(), t2) : t2;
  }
  return sum;
}

/// The readings scan_agreement() classifies, evenly over the set (at most `max_readings`; 0: all),
/// and their disparities (values only) at the pose (R, t): out[k] for reading (*subset)[k].
template <int Dim>
void agreement_disparities(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& set,
                           const typename PoseTraits<Dim>::Rotation& r,
                           const typename SpaceTraits<Dim>::Vector& t, int max_readings,
                           std::vector<int>* subset, std::vector<BeamDisparityT<Dim>>* out) {
  const std::size_t want =
      max_readings > 0 ? std::min<std::size_t>(set.size(), max_readings) : set.size();
  subset->resize(want);
  for (std::size_t k = 0; k < want; ++k) (*subset)[k] = static_cast<int>(k * set.size() / want);
  model.disparities(r, t, set, subset, out, DisparityParts::kValue);
}

}  // namespace vdtnav::detail
