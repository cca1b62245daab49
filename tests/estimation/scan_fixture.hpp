#pragma once
// Test scans: ray cast in the generated floor plan with thin-wall surfaces (consistent with the
// VDT), so that noise-free scans fit the map exactly up to interpolation.

#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/sensor/laser_scan.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::test {

struct World {
  sim::FloorPlan plan = sim::generate_floor_plan({});
  VdtMap2 map = VdtMap2::build(plan.occupancy);
};

inline const World& world() {
  static const World w;
  return w;
}

/// A UTM-30LX-like scan (270 degrees, `beams` beams) from `pose`, range noise sigma (0: none).
inline LaserScan simulate_scan(const Pose2& pose, double sigma, std::mt19937& rng,
                               int beams = 1081);

/// The map a user would have of the plan around tour_pose(7), made as a user's is: mapping::
/// OccupancyMapper over 35 scans (range noise 0.02 m) along the tour's legs 4-10, each
/// registered at its pose moved by the map builder's error, N(0, sigma^2) per axis and
/// N(0, heading_sigma^2) in heading. Errors the estimators' models do not draw.
inline VdtMap2 rebuilt_map(double sigma, double heading_sigma, std::mt19937& rng) {
  const sim::FloorPlan& plan = world().plan;
  std::normal_distribution<double> n01(0.0, 1.0);
  mapping::OccupancyMapper mapper(plan.occupancy.frame(), plan.occupancy.size());
  for (std::size_t k = 4; k <= 10; ++k) {
    const Eigen::Vector2d a = plan.tour[k % plan.tour.size()],
                          b = plan.tour[(k + 1) % plan.tour.size()];
    for (int s = 0; s < 5; ++s) {
      const Eigen::Vector2d p = a + 0.2 * s * (b - a);
      const Pose2 pose(p.x(), p.y(), std::atan2(b.y() - a.y(), b.x() - a.x()));
      const LaserScan scan = simulate_scan(pose, 0.02, rng);
      mapper.insert(Pose2(pose[0] + sigma * n01(rng), pose[1] + sigma * n01(rng),
                          pose[2] + heading_sigma * n01(rng)),
                    scan);
    }
  }
  return VdtMap2::build(mapper.occupancy());
}

inline LaserScan simulate_scan(const Pose2& pose, double sigma, std::mt19937& rng, int beams) {
  LaserScan scan;
  scan.angle_min = -0.75 * M_PI;
  scan.angle_increment = 1.5 * M_PI / (beams - 1);
  scan.range_min = 0.1;
  scan.range_max = 30.0;
  scan.sigma_range = sigma > 0 ? sigma : 0.02;
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  for (int i = 0; i < beams; ++i) {
    const double a = pose[2] + scan.angle(static_cast<std::size_t>(i));
    const double r = sim::cast_ray<2>(world().plan.occupancy, pose.head<2>(),
                                      Eigen::Vector2d(std::cos(a), std::sin(a)), scan.range_max,
                                      sim::RaySurface::kCellCentre);
    scan.ranges.push_back(std::isfinite(r) && sigma > 0 ? r + noise(rng) : r);
  }
  return scan;
}

/// A pose on the tour: in a room, looking along the tour.
inline Pose2 tour_pose(std::size_t k) {
  const auto& t = world().plan.tour;
  const Eigen::Vector2d a = t[k % t.size()], b = t[(k + 1) % t.size()];
  const Eigen::Vector2d p = 0.6 * a + 0.4 * b;
  return Pose2(p.x(), p.y(), std::atan2(b.y() - a.y(), b.x() - a.x()) + 0.2);
}

/// One error per square of side `length` (world frame), drawn when the square is first needed.
using SharedMapErrors = std::map<std::pair<long, long>, Eigen::Vector2d>;

/// Map errors shared per square of side `length` (world frame): every endpoint in one square is
/// moved by one draw of N(0, sigma_c^2 I) — the model of
/// VdtSensorModelOptions::map_correlation_length. `errors`, when given, keeps the draws across
/// calls (one map seen in several scans); otherwise each call draws a new map.
inline void shift_by_shared_map_errors(ScanPoints& scan, const Pose2& pose, double length,
                                       double sigma_c, std::mt19937& rng,
                                       SharedMapErrors* errors = nullptr) {
  std::normal_distribution<double> n01(0.0, 1.0);
  const Eigen::Rotation2Dd rot(pose[2]);
  SharedMapErrors fresh_map;
  SharedMapErrors& shift = errors != nullptr ? *errors : fresh_map;
  for (Eigen::Vector2d& p : scan.points) {
    const Eigen::Vector2d w = rot * p + pose.head<2>();
    const std::pair<long, long> key(static_cast<long>(std::floor(w.x() / length)),
                                    static_cast<long>(std::floor(w.y() / length)));
    auto [it, fresh] = shift.try_emplace(key);
    if (fresh) it->second = sigma_c * Eigen::Vector2d(n01(rng), n01(rng));
    p += rot.inverse() * it->second;
  }
}

/// A 5 x 3 m empty rectangle of 0.1 m cells (walls through cell centres 3 and 53, 3 and 33) in
/// a margin: every pose has its twin turned by pi about the centre (2.85, 1.85), so global
/// localization must refuse every scan in it as ambiguous.
inline OccupancyGrid<2> symmetric_room() {
  OccupancyGrid<2> g(Eigen::Vector2i(57, 37), GridFrame<2>(0.1, Eigen::Vector2d::Zero()), 0);
  for (int y = 0; y < 37; ++y) {
    for (int x = 0; x < 57; ++x) {
      const bool in = x >= 3 && x <= 53 && y >= 3 && y <= 33;
      g(Eigen::Vector2i(x, y)) = (in && (x == 3 || x == 53 || y == 3 || y == 33)) ? 1 : 0;
    }
  }
  return g;
}

}  // namespace vdtnav::test
