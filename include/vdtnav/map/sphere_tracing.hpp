#pragma once
/// \file
/// \brief Ray casting on a VDT map (what an estimator predicts a range sensor reads): sphere
/// tracing on the distance field, |DT_v| being the radius of an empty ball around every point.

#include <algorithm>
#include <cmath>
#include <limits>

#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {

/// \brief Distance along the unit direction `dir` from `origin` to the first surface of the map
/// (where DT_v = 0: the thin walls through the occupied cells' centres), or +inf when the ray
/// leaves the map or travels `max_range` without one.
///
/// Far from surfaces, steps of the stored distance to the nearest occupied cell centre less a cell
/// diagonal and a half (never past a surface; the interpolated |DT_v| is not used there because
/// near a cut locus it can exceed the true distance). Within two cells of one, |DT_v| along the ray
/// is V-shaped about the surface (both sides of a thin wall, or a thick wall's first surface cell,
/// where the field inside may point either way): steps of half |DT_v| (at least a twentieth of a
/// cell) find the first local minimum of |DT_v|, a golden-section search places it (to 0.02 mm),
/// and it is a hit when |DT_v| there is below a tenth of a cell and an occupied cell centre lies
/// within half a cell (else the ray passed a corner and goes on). A ray starting on a surface reads
/// 0.
template <int Dim>
[[nodiscard]] double sphere_trace(const VdtMap<Dim>& map,
                                  const typename SpaceTraits<Dim>::Vector& origin,
                                  const typename SpaceTraits<Dim>::Vector& dir, double max_range) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double res = map.resolution();
  const double near = 0.25 * res, fine = 0.05 * res, hit_below = 0.1 * res;
  const auto distance = [&](double t, bool* inside) {
    return map.value(origin + t * dir, inside).norm();
  };
  double t = 0.0;
  bool inside = false;
  double d = distance(t, &inside);
  if (!inside) return kInf;
  if (d < 1e-9) return 0.0;
  // nearest_occupied_point(p) is the centre nearest to p's *cell*: within a cell diagonal of the
  // one nearest to p, and a thin wall lies within half a cell of a centre.
  const double slack = (std::sqrt(static_cast<double>(Dim)) + 0.5) * res;
  while (t <= max_range) {
    const typename SpaceTraits<Dim>::Vector p = origin + t * dir;
    const double safe = (p - map.nearest_occupied_point(p)).norm() - slack;
    if (safe > near) {
      t += safe;
      d = distance(t, &inside);
      if (!inside) return kInf;
      continue;
    }
    // Near a surface: march until |DT_v| stops decreasing, in steps of half of it (at least a
    // twentieth of a cell).
    double prev = d, t_prev = t;
    double t_next = t + std::max(0.5 * d, fine);
    double d_next = distance(t_next, &inside);
    if (!inside) return kInf;
    while (d_next < prev && t_next <= max_range + fine) {
      t_prev = t;
      t = t_next;
      prev = d_next;
      t_next = t + std::max(0.5 * prev, fine);
      d_next = distance(t_next, &inside);
      if (!inside) return kInf;
    }
    // The minimum lies in [t_prev, t_next]: golden-section search.
    double lo = t_prev, hi = t_next;
    constexpr double kGolden = 0.6180339887498949;
    double a = hi - kGolden * (hi - lo), b = lo + kGolden * (hi - lo);
    double fa = distance(a, &inside), fb = distance(b, &inside);
    for (int it = 0; it < 40 && hi - lo > 2e-5; ++it) {
      if (fa < fb) {
        hi = b;
        b = a;
        fb = fa;
        a = hi - kGolden * (hi - lo);
        fa = distance(a, &inside);
      } else {
        lo = a;
        a = b;
        fa = fb;
        b = lo + kGolden * (hi - lo);
        fb = distance(b, &inside);
      }
    }
    const double t_min = 0.5 * (lo + hi);
    // A hit also needs an occupied cell centre within half a cell (the thin walls join them):
    // near a corner's cut locus the interpolated DT_v collapses without a surface there.
    const typename SpaceTraits<Dim>::Vector q = origin + t_min * dir;
    if (std::min(fa, fb) < hit_below && (q - map.nearest_occupied_point(q)).norm() < 0.55 * res) {
      return t_min <= max_range ? t_min : kInf;
    }
    // Passed a corner at that distance: go on beyond the minimum.
    t = t_next;
    d = d_next;
  }
  return kInf;
}

}  // namespace vdtnav
