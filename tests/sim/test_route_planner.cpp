// The tour planner: clear of obstacles by the asked clearance (checked with the UDT and with an
// independent ray cast along every segment), in the largest free region, spread over the map,
// deterministic per seed, and loud about impossible requests.
#include "vdtnav/sim/route_planner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {
namespace {

/// Asserts that `path` keeps `clearance` from every obstacle of `occ`.
void expect_clear(const OccupancyGrid<2>& occ, const std::vector<Eigen::Vector2d>& path,
                  double clearance) {
  ASSERT_GE(path.size(), 2u);
  const auto udt = unsigned_distance_transform(nearest_occupied_cells(occ));
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector2i c = occ.cell_of(path[k]);
    ASSERT_TRUE(occ.contains(c)) << "point " << k;
    // Every vertex lies in a cell with the full clearance.
    ASSERT_GE(udt(c), clearance) << "point " << k << " at " << path[k].transpose();
    if (k == 0) continue;
    // Dense: consecutive points at most a few cells apart.
    const Eigen::Vector2d d = path[k] - path[k - 1];
    ASSERT_LE(d.norm(), 2.5 * occ.resolution()) << "point " << k;
    // Between vertices the UDT drops by at most the distance travelled (1-Lipschitz).
    for (double s = 0.0; s <= 1.0; s += 0.1)
      ASSERT_GE(udt(occ.cell_of(path[k - 1] + s * d)), clearance - occ.resolution() - 1e-6);
    // Independent oracle: no occupied cell on the segment.
    if (d.norm() > 0.0) {
      ASSERT_TRUE(std::isinf(cast_ray<2>(occ, path[k - 1], d.normalized(), d.norm())))
          << "segment " << k - 1 << "-" << k << " crosses an obstacle";
    }
  }
}

double path_length(const std::vector<Eigen::Vector2d>& path) {
  double l = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) l += (path[k] - path[k - 1]).norm();
  return l;
}

TEST(RoutePlanner, TourOnTheFloorPlanKeepsItsClearanceAndSpansTheBuilding) {
  for (const auto& [seed, clearance] : {std::pair{1u, 0.3}, std::pair{2u, 0.5}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " clearance " + std::to_string(clearance));
    FloorPlanOptions o;
    o.seed = seed;
    const auto plan = generate_floor_plan(o);
    const auto path = plan_tour(plan.occupancy, 8, clearance, seed);
    expect_clear(plan.occupancy, path, clearance);
    // Far-apart places: the tour spans most of the 40 m x 18 m building.
    Eigen::Vector2d lo = path[0], hi = path[0];
    for (const auto& p : path) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    EXPECT_GT(hi.x() - lo.x(), 0.6 * 40.0);
    EXPECT_GT(hi.y() - lo.y(), 0.5 * 18.0);
    EXPECT_GT(path_length(path), 60.0);
    // More waypoints, a longer tour.
    EXPECT_LT(path_length(plan_tour(plan.occupancy, 3, clearance, seed)), path_length(path));
  }
}

TEST(RoutePlanner, SameSeedSameTourOtherSeedOtherTour) {
  const auto plan = generate_floor_plan({});
  const auto a = plan_tour(plan.occupancy, 4, 0.4, 11);
  const auto b = plan_tour(plan.occupancy, 4, 0.4, 11);
  const auto c = plan_tour(plan.occupancy, 4, 0.4, 12);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k], b[k]) << k;
  EXPECT_TRUE(a.size() != c.size() || a.front() != c.front() || a.back() != c.back());
}

TEST(RoutePlanner, StaysInTheLargestConnectedRegion) {
  // 10 m x 5 m, closed, with a full wall at x = 3 m: a 3 m room and a 7 m room.
  OccupancyGrid<2> occ(Eigen::Vector2i(100, 50), GridFrame<2>(0.1, Eigen::Vector2d::Zero()), 0);
  for (int i = 0; i < 100; ++i) occ(Eigen::Vector2i(i, 0)) = occ(Eigen::Vector2i(i, 49)) = 1;
  for (int j = 0; j < 50; ++j)
    occ(Eigen::Vector2i(0, j)) = occ(Eigen::Vector2i(99, j)) = occ(Eigen::Vector2i(30, j)) = 1;
  for (std::uint32_t seed = 0; seed < 5; ++seed) {
    const auto path = plan_tour(occ, 4, 0.3, seed);
    expect_clear(occ, path, 0.3);
    for (const auto& p : path) ASSERT_GT(p.x(), 3.0) << "seed " << seed;
  }
  // Open the wall with a 1.2 m door: now both rooms are one region and get visited.
  for (int j = 20; j < 32; ++j) occ(Eigen::Vector2i(30, j)) = 0;
  bool left = false;
  for (std::uint32_t seed = 0; seed < 5; ++seed) {
    const auto path = plan_tour(occ, 4, 0.3, seed);
    expect_clear(occ, path, 0.3);
    for (const auto& p : path) left = left || p.x() < 2.0;
  }
  EXPECT_TRUE(left);
}

TEST(RoutePlanner, ImpossibleRequestsThrowConfigError) {
  const auto plan = generate_floor_plan({});
  EXPECT_THROW((void)plan_tour(plan.occupancy, 8, 5.0, 1), ConfigError);  // nowhere 5 m clear
  EXPECT_THROW((void)plan_tour(plan.occupancy, 1, 0.4, 1), ConfigError);
  EXPECT_THROW((void)plan_tour(plan.occupancy, 8, -0.1, 1), ConfigError);
  EXPECT_THROW((void)plan_tour(plan.occupancy, 8, std::nan(""), 1), ConfigError);
  const OccupancyGrid<2> full(Eigen::Vector2i(20, 20), GridFrame<2>(0.1, Eigen::Vector2d::Zero()),
                              1);
  EXPECT_THROW((void)plan_tour(full, 4, 0.0, 1), ConfigError);
}

TEST(RoutePlanner, TourOnTheStageHospitalSection) {
  const std::string file = std::string(VDTNAV_DATA_DIR) + "/stage_maps/hospital_section.png";
  if (!std::ifstream(file).good()) GTEST_SKIP() << "real data absent: " << file;
  const auto occ = load_occupancy_image(file, Eigen::Vector2d(40.0, 18.0), 0.05);
  const auto path = plan_tour(occ, 10, 0.4, 1);
  expect_clear(occ, path, 0.4);
  EXPECT_GT(path_length(path), 50.0);
}

}  // namespace
}  // namespace vdtnav::sim
