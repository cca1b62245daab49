#include "vdtnav/mapping/occupancy_mapper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav::mapping {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// ROS cell values (the kRos* constants of io/ros_map.hpp, which belongs to the io component).
constexpr std::int8_t kUnknown = -1;
constexpr std::int8_t kFree = 0;
constexpr std::int8_t kOccupied = 100;

/// log(p / (1 - p)).
double logit(double p) { return std::log(p / (1.0 - p)); }

/// Calls visit(cell) for every cell the segment a -> b passes through, in order, from the cell
/// of a up to the cell of b (the last one only when include_last). Coordinates are continuous
/// cell coordinates, cell i spanning [i, i + 1) on each axis.
///
/// Amanatides & Woo's traversal: t_max is the ray parameter (0 at a, 1 at b) of the next cell
/// boundary on each axis, t_delta the parameter span of one cell. The number of steps per axis
/// is fixed beforehand (|cell(b) - cell(a)|), so rounding can reorder two steps at a corner but
/// never miss the last cell or run past it.
template <typename Visit>
void traverse(const Eigen::Vector2d& a, const Eigen::Vector2d& b, bool include_last,
              Visit&& visit) {
  Eigen::Vector2i cell(static_cast<int>(std::floor(a.x())), static_cast<int>(std::floor(a.y())));
  const Eigen::Vector2i last(static_cast<int>(std::floor(b.x())),
                             static_cast<int>(std::floor(b.y())));
  const Eigen::Vector2d d = b - a;
  Eigen::Vector2i step, remaining;
  Eigen::Vector2d t_max, t_delta;
  for (int k = 0; k < 2; ++k) {
    remaining[k] = std::abs(last[k] - cell[k]);
    if (d[k] > 0.0) {
      step[k] = 1;
      t_delta[k] = 1.0 / d[k];
      t_max[k] = (cell[k] + 1 - a[k]) * t_delta[k];
    } else if (d[k] < 0.0) {
      step[k] = -1;
      t_delta[k] = -1.0 / d[k];
      t_max[k] = (a[k] - cell[k]) * t_delta[k];
    } else {
      step[k] = 0;
      t_delta[k] = kInf;
      t_max[k] = kInf;
    }
  }
  for (int n = remaining.sum(); n > 0; --n) {
    visit(cell);
    const int axis = remaining[0] == 0 ? 1 : remaining[1] == 0 ? 0 : t_max[1] < t_max[0] ? 1 : 0;
    cell[axis] += step[axis];
    t_max[axis] += t_delta[axis];
    --remaining[axis];
  }
  if (include_last) visit(cell);
}

/// The world points the mapper integrates for one beam: the sensor origin and where the ray
/// stops; `hit` when the stop is an endpoint to mark occupied.
struct Beam {
  enum Kind { kDropNotFinite, kDropTooShort, kHit, kClear, kNothing } kind;
  Eigen::Vector2d end;
};

Beam classify_beam(const LaserScan& scan, std::size_t i, const Eigen::Vector2d& origin,
                   double sensor_yaw, double clearing_length) {
  const double r = scan.ranges[i];
  if (!std::isfinite(r)) return {Beam::kDropNotFinite, origin};
  if (r < scan.range_min) return {Beam::kDropTooShort, origin};
  const double a = sensor_yaw + scan.angle(i);
  const Eigen::Vector2d dir(std::cos(a), std::sin(a));
  if (r < scan.range_max) return {Beam::kHit, origin + r * dir};
  // No return: clear up to the clearing length, mark nothing.
  const double length = std::min(clearing_length, r);
  return {length > 0.0 ? Beam::kClear : Beam::kNothing, origin + length * dir};
}

/// The unit normal of the surface hit beam i ended on, from the endpoints of the nearest hit
/// beams on either side that lie 2 to 20 cells from its own (far enough apart that range noise
/// does not swamp the direction; up to 1 m at 5 cm, since at grazing incidence consecutive
/// endpoints are far apart on the wall, and those are the rays that need it). False when there is
/// no such neighbour (an isolated return, a depth jump) or when the three endpoints are not on a
/// line to within a cell (a corner).
bool surface_normal(const std::vector<Beam>& beams, std::size_t i, double res,
                    Eigen::Vector2d& normal) {
  const Eigen::Vector2d& p = beams[i].end;
  const double near = 2.0 * res, far = 20.0 * res;
  const auto count = static_cast<std::ptrdiff_t>(beams.size());
  auto neighbour = [&](std::ptrdiff_t step, Eigen::Vector2d& q) {
    constexpr int kMaxBeams = 64;  // 16 degrees at the UTM-30LX's 0.25 degrees
    std::ptrdiff_t j = static_cast<std::ptrdiff_t>(i) + step;
    for (int n = 0; n < kMaxBeams && j >= 0 && j < count; ++n, j += step) {
      const Beam& b = beams[static_cast<std::size_t>(j)];
      if (b.kind != Beam::kHit) continue;
      const double d = (b.end - p).norm();
      if (d < near) continue;
      if (d > far) return false;
      q = b.end;
      return true;
    }
    return false;
  };
  Eigen::Vector2d left = p, right = p, tangent;
  const bool has_left = neighbour(-1, left), has_right = neighbour(1, right);
  if (has_left && has_right) {
    tangent = (right - left).normalized();
    const Eigen::Vector2d d = p - left;
    if (std::abs(tangent.x() * d.y() - tangent.y() * d.x()) > res) return false;
  } else if (has_left) {
    tangent = (p - left).normalized();
  } else if (has_right) {
    tangent = (right - p).normalized();
  } else {
    return false;
  }
  normal = Eigen::Vector2d(-tangent.y(), tangent.x());
  return true;
}

void check_scan(const LaserScan& scan) {
  VDTNAV_CHECK(scan.mount.allFinite() && std::isfinite(scan.angle_min) &&
                   std::isfinite(scan.angle_increment),
               "occupancy mapper: scan mount and angles must be finite");
  VDTNAV_CHECK(scan.angles.empty() || scan.angles.size() == scan.ranges.size(),
               "occupancy mapper: scan has explicit angles but not one per range");
  VDTNAV_CHECK(!std::isnan(scan.range_min) && !std::isnan(scan.range_max),
               "occupancy mapper: scan range_min and range_max must not be NaN");
}

}  // namespace

void OccupancyMapperOptions::validate() const {
  auto finite = [](double x) { return std::isfinite(x); };
  VDTNAV_CHECK(finite(resolution) && resolution > 0.0,
               "OccupancyMapperOptions: resolution must be finite and > 0");
  VDTNAV_CHECK(finite(margin) && margin >= 0.0,
               "OccupancyMapperOptions: margin must be finite and >= 0");
  VDTNAV_CHECK(finite(l_occ) && finite(l_free) && l_occ > 0.0 && l_free < 0.0,
               "OccupancyMapperOptions: need l_occ > 0 > l_free");
  VDTNAV_CHECK(finite(l_min) && finite(l_max) && l_min < 0.0 && l_max > 0.0,
               "OccupancyMapperOptions: need l_min < 0 < l_max");
  VDTNAV_CHECK(finite(clearing_length) && clearing_length >= 0.0,
               "OccupancyMapperOptions: clearing_length must be finite and >= 0");
  VDTNAV_CHECK(
      free_threshold > 0.0 && free_threshold < occupied_threshold && occupied_threshold < 1.0,
      "OccupancyMapperOptions: need 0 < free_threshold < occupied_threshold < 1");
}

OccupancyMapper::OccupancyMapper(const GridFrame<2>& frame, const Eigen::Vector2i& size,
                                 const OccupancyMapperOptions& options)
    : options_(options) {
  options_.validate();
  log_odds_ = Grid<float, 2>(size, frame, 0.0f);
  observations_ = Grid<std::uint32_t, 2>(size, frame, 0u);
  pending_.assign(log_odds_.num_cells(), 0.0f);
}

void OccupancyMapper::update(std::ptrdiff_t linear, float delta) {
  float& p = pending_[static_cast<std::size_t>(linear)];
  if (p == 0.0f) touched_.push_back(linear);
  if (p <= 0.0f) p = delta;  // a hit overrides a miss, never the reverse
}

void OccupancyMapper::insert(const Pose2& pose, const LaserScan& scan) {
  VDTNAV_CHECK(pose.allFinite(), "OccupancyMapper::insert: the pose must be finite");
  check_scan(scan);
  ++stats_.scans;
  const Pose2 sensor = compose(pose, scan.mount);
  const Eigen::Vector2d origin = sensor.head<2>();
  const auto& frame = log_odds_.frame();
  // Continuous cell coordinates with cell i spanning [i, i + 1).
  auto grid_point = [&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return frame.continuous_index(p) + Eigen::Vector2d::Constant(0.5);
  };
  const Eigen::Vector2d a = grid_point(origin);
  const auto l_occ = static_cast<float>(options_.l_occ);
  const auto l_free = static_cast<float>(options_.l_free);
  auto miss = [&](const Eigen::Vector2i& c) {
    if (log_odds_.contains(c)) update(log_odds_.linear_index(c), l_free);
  };

  std::vector<Beam> beams;
  beams.reserve(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i)
    beams.push_back(classify_beam(scan, i, origin, sensor[2], options_.clearing_length));

  const double res = frame.resolution();
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const Beam& beam = beams[i];
    switch (beam.kind) {
      case Beam::kDropNotFinite:
        ++stats_.dropped_not_finite;
        break;
      case Beam::kDropTooShort:
        ++stats_.dropped_too_short;
        break;
      case Beam::kNothing:
        ++stats_.no_returns;
        break;
      case Beam::kClear:
        ++stats_.no_returns;
        traverse(a, grid_point(beam.end), true, miss);
        break;
      case Beam::kHit: {
        ++stats_.hits;
        const Eigen::Vector2d b = grid_point(beam.end);
        Eigen::Vector2d normal = Eigen::Vector2d::Zero();
        if (options_.keep_surface_cells && surface_normal(beams, i, res, normal)) {
          // The cells the observed surface runs through (centre within half a cell of its line)
          // are not cleared by the ray that observed it: a grazing ray crosses several of them
          // before it reaches the surface.
          traverse(a, b, false, [&](const Eigen::Vector2i& c) {
            if (!log_odds_.contains(c)) return;
            if (std::abs(normal.dot(frame.cell_center(c) - beam.end)) < 0.5 * res) return;
            update(log_odds_.linear_index(c), l_free);
          });
        } else {
          traverse(a, b, false, miss);
        }
        const Eigen::Vector2i end = log_odds_.cell_of(beam.end);
        if (log_odds_.contains(end))
          update(log_odds_.linear_index(end), l_occ);
        else
          ++stats_.endpoints_outside;
        break;
      }
    }
  }

  // Apply each touched cell's one update of this scan, clamped (Probabilistic Robotics Table
  // 9.1 line 4, l_0 = 0).
  const auto lo = static_cast<float>(options_.l_min), hi = static_cast<float>(options_.l_max);
  for (const std::ptrdiff_t linear : touched_) {
    const auto k = static_cast<std::size_t>(linear);
    log_odds_[k] = std::clamp(log_odds_[k] + pending_[k], lo, hi);
    ++observations_[k];
    pending_[k] = 0.0f;
  }
  touched_.clear();
}

Grid<std::int8_t, 2> OccupancyMapper::ros_cells() const {
  Grid<std::int8_t, 2> cells(log_odds_.size(), log_odds_.frame(), kUnknown);
  const double occ = logit(options_.occupied_threshold), free = logit(options_.free_threshold);
  for (std::size_t k = 0; k < log_odds_.num_cells(); ++k) {
    if (observations_[k] == 0) continue;
    const double l = log_odds_[k];
    cells[k] = l >= occ ? kOccupied : l <= free ? kFree : kUnknown;
  }
  return cells;
}

OccupancyGrid<2> OccupancyMapper::occupancy() const {
  const Grid<std::int8_t, 2> cells = ros_cells();
  OccupancyGrid<2> occupied(cells.size(), cells.frame(), 0);
  for (std::size_t k = 0; k < cells.num_cells(); ++k) occupied[k] = cells[k] == kOccupied ? 1 : 0;
  return occupied;
}

std::pair<GridFrame<2>, Eigen::Vector2i> map_extent(const std::vector<Pose2>& poses,
                                                    const std::vector<LaserScan>& scans,
                                                    const OccupancyMapperOptions& options) {
  options.validate();
  VDTNAV_CHECK(poses.size() == scans.size(), "map_extent: need one pose per scan (" +
                                                 std::to_string(poses.size()) + " poses, " +
                                                 std::to_string(scans.size()) + " scans)");
  VDTNAV_CHECK(!poses.empty(), "map_extent: no poses");
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(kInf), hi = Eigen::Vector2d::Constant(-kInf);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    VDTNAV_CHECK(poses[k].allFinite(), "map_extent: pose " + std::to_string(k) + " is not finite");
    check_scan(scans[k]);
    const Pose2 sensor = compose(poses[k], scans[k].mount);
    lo = lo.cwiseMin(sensor.head<2>());
    hi = hi.cwiseMax(sensor.head<2>());
    for (std::size_t i = 0; i < scans[k].ranges.size(); ++i) {
      const Beam beam =
          classify_beam(scans[k], i, sensor.head<2>(), sensor[2], options.clearing_length);
      if (beam.kind != Beam::kHit && beam.kind != Beam::kClear) continue;
      lo = lo.cwiseMin(beam.end);
      hi = hi.cwiseMax(beam.end);
    }
  }
  const double res = options.resolution;
  lo -= Eigen::Vector2d::Constant(options.margin);
  hi += Eigen::Vector2d::Constant(options.margin);
  Eigen::Vector2d origin = lo;
  // The slack keeps a corner that is a multiple of res up to rounding from adding a cell.
  if (options.align_origin) origin = ((lo / res).array() + 1e-9).floor() * res;
  Eigen::Vector2i size;
  for (int d = 0; d < 2; ++d) {
    // Every point must fall in a cell: cells = floor((hi - origin) / res) + 1.
    const double cells = std::floor((hi[d] - origin[d]) / res) + 1.0;
    VDTNAV_CHECK(cells < 2147483647.0, "map_extent: the map is too large for its resolution");
    size[d] = static_cast<int>(cells);
  }
  VDTNAV_CHECK(static_cast<double>(size[0]) * size[1] < 2147483648.0,
               "map_extent: the map has more than 2^31 cells");
  return {GridFrame<2>(res, origin), size};
}

OccupancyMap build_occupancy_map(const std::vector<Pose2>& poses,
                                 const std::vector<LaserScan>& scans,
                                 const OccupancyMapperOptions& options) {
  const auto [frame, size] = map_extent(poses, scans, options);
  OccupancyMapper mapper(frame, size, options);
  for (std::size_t k = 0; k < poses.size(); ++k) mapper.insert(poses[k], scans[k]);
  OccupancyMap map;
  map.cells = mapper.ros_cells();
  map.occupancy = mapper.occupancy();
  map.log_odds = mapper.log_odds();
  map.observations = mapper.observations();
  map.stats = mapper.stats();
  return map;
}

}  // namespace vdtnav::mapping
