#include "vdtnav/estimation/local_scan_map.hpp"

#include <algorithm>
#include <cmath>

#include "vdtnav/estimation/guess_search.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace vdtnav {

void LocalScanMap::add(const ScanPoints& scan, const Pose2& pose) {
  if (!options_.enabled || options_.scans <= 0) return;
  std::vector<Eigen::Vector2d> world;
  world.reserve(scan.size());
  for (const Eigen::Vector2d& p : scan.points) world.push_back(transform_point(pose, p));
  scans_.push_back(std::move(world));
  while (static_cast<int>(scans_.size()) > options_.scans) scans_.pop_front();
}

std::optional<Pose2> LocalScanMap::match(const ScanPoints& scan, const Pose2& guess,
                                         const VdtOptimizerOptions& optimizer,
                                         double explained_distance) const {
  if (!options_.enabled || scans_.empty() || scan.size() == 0) return std::nullopt;
  // The endpoints within `radius` of the guess, and their bounding box plus a margin of one
  // gate (so that no endpoint of the scan lands outside the local map for a small motion).
  const double r2 = options_.radius * options_.radius;
  std::vector<Eigen::Vector2d> pts;
  Eigen::Vector2d lo = guess.head<2>(), hi = guess.head<2>();
  for (const auto& s : scans_) {
    for (const Eigen::Vector2d& p : s) {
      if ((p - guess.head<2>()).squaredNorm() > r2) continue;
      pts.push_back(p);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  if (pts.size() < 10) return std::nullopt;
  const double res = options_.resolution;
  const double margin = std::max(1.0, optimizer.sensor.gate);
  // The origin on the world lattice of the resolution: every local map then rasterizes a wall
  // into the same cells, so the half-cell offsets between walls and cell centres stay the same
  // from one match to the next instead of adding up along the gap.
  const Eigen::Vector2d origin =
      ((lo - Eigen::Vector2d::Constant(margin)) / res).array().floor().matrix() * res;
  const Eigen::Vector2i size =
      ((hi - lo + Eigen::Vector2d::Constant(2.0 * margin)) / res).array().ceil().cast<int>();
  OccupancyGrid<2> grid(size, GridFrame<2>(res, origin));
  for (const Eigen::Vector2d& p : pts) {
    const Eigen::Vector2i c = grid.cell_of(p);
    if ((c.array() >= 0).all() && (c.array() < size.array()).all()) grid(c) = 1;
  }
  const VdtMap2 local = VdtMap2::build(grid);
  VdtOptimizerOptions o = optimizer;
  o.pyramid_levels = 0;
  o.search.enabled = false;
  o.bridge.enabled = false;
  const VdtOptimizer opt(local, o);
  const LocalizationResult r = opt.solve(scan, guess);
  if (r.status != LocalizationStatus::kConverged && r.status != LocalizationStatus::kNotConverged) {
    return std::nullopt;
  }
  if (explained_fraction(opt.sensor_model(), scan, r.pose, explained_distance) <
      options_.accept_fraction) {
    return std::nullopt;
  }
  return r.pose;
}

}  // namespace vdtnav
