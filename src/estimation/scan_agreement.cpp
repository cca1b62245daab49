#include "vdtnav/estimation/scan_agreement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "scan_scores.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {

void ScanAgreementOptions::validate() const {
  VDTNAV_CHECK(std::isfinite(explained_distance) && explained_distance > 0.0,
               "scan agreement: explained_distance must be > 0");
  VDTNAV_CHECK(std::isfinite(margin), "scan agreement: margin must be finite (< 0: default)");
  VDTNAV_CHECK(max_readings >= 0, "scan agreement: max_readings must be >= 0");
}

double first_occupied_crossing(const VdtMap2& map, const Eigen::Vector2d& origin,
                               const Eigen::Vector2d& dir, double from, double to) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto& nearest = map.nearest_cells();
  const double h = map.resolution();
  // nearest_occupied_point(p) is the occupied centre nearest to p's cell centre q: |p - c(q)| is
  // at most the true distance plus 2 |p - q| <= a cell diagonal, and an occupied cell's square
  // lies within half a diagonal of its centre: a step of |p - c(q)| - 1.5 diagonals never skips
  // one. Near walls, steps of half a cell (a corner grazed by less is not a crossing).
  const double slack = 1.5 * std::sqrt(2.0) * h, fine = 0.5 * h;
  for (double t = std::max(from, 0.0); t <= to;) {
    const Eigen::Vector2d p = origin + t * dir;
    const Eigen::Vector2i cell = nearest.cell_of(p);
    if (!nearest.contains(cell)) return kInf;
    const std::ptrdiff_t k = nearest.linear_index(cell);
    const std::int32_t c = nearest[static_cast<std::size_t>(k)];
    if (c == k) return t;  // a surface cell (thick walls are entered through one)
    const double d = (p - nearest.cell_center(nearest.index_of(c))).norm();
    t += std::max(fine, d - slack);
  }
  return kInf;
}

ScanAgreement scan_agreement(const VdtSensorModel& model, const VdtMap2& map,
                             const MapKnowledge& knowledge, const ScanPoints& scan,
                             const Pose2& pose, const ScanAgreementOptions& options) {
  ScanAgreement a;
  if (scan.size() == 0) return a;
  thread_local std::vector<int> subset;  // scratch: no allocation per scan
  thread_local std::vector<BeamDisparity> ds;
  const Eigen::Matrix2d r = PoseTraits<2>::rotation(pose);
  const Eigen::Vector2d t = pose.head<2>();
  detail::agreement_disparities(model, scan, r, t, options.max_readings, &subset, &ds);
  const std::size_t want = subset.size();
  const double d2 = options.explained_distance * options.explained_distance;
  const double margin =
      options.margin >= 0.0 ? options.margin : 2.0 * options.explained_distance + map.resolution();
  for (std::size_t k = 0; k < want; ++k) {
    ++a.readings;
    const BeamDisparity& b = ds[k];
    if (b.inlier && b.d.squaredNorm() < d2) {
      ++a.explained;
      continue;
    }
    const std::size_t i = static_cast<std::size_t>(subset[k]);
    const Eigen::Vector2d end = t + r * scan.points[i];
    const Eigen::Vector2d dir = r * scan.directions[i];
    const Eigen::Vector2d origin = end - scan.ranges[i] * dir;
    // Through a wall: the map says the beam would have stopped before.
    if (std::isfinite(first_occupied_crossing(map, origin, dir, margin, scan.ranges[i] - margin))) {
      ++a.contradicted;
      continue;
    }
    const auto& nearest = map.nearest_cells();
    const Eigen::Vector2i cell = nearest.cell_of(end);
    const bool inside = nearest.contains(cell);
    if (inside) {
      // In a surface cell of a map coarser than explained_distance: on the wall.
      const std::ptrdiff_t c = nearest.linear_index(cell);
      if (nearest[static_cast<std::size_t>(c)] == c) {
        ++a.explained;
        continue;
      }
    }
    // Ending in space the map knows to be free: nothing there, says the map.
    if (inside && knowledge.known(end)) {
      ++a.contradicted;
    } else {
      ++a.unknown;
    }
  }
  return a;
}

}  // namespace vdtnav
