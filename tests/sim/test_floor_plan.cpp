// The generated floor plan: deterministic per seed, closed, and its tour runs through free space.
#include "vdtnav/sim/floor_plan.hpp"

#include <gtest/gtest.h>

#include <queue>

#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav::sim {
namespace {

TEST(FloorPlan, SameSeedSamePlanOtherSeedOtherPlan) {
  const auto a = generate_floor_plan({}), b = generate_floor_plan({});
  FloorPlanOptions other;
  other.seed = 2;
  const auto c = generate_floor_plan(other);
  EXPECT_EQ(a.occupancy.values(), b.occupancy.values());
  EXPECT_NE(a.occupancy.values(), c.occupancy.values());
  EXPECT_EQ(a.occupancy.size(), Eigen::Vector2i(800, 360));
}

TEST(FloorPlan, TourStaysClearOfObstaclesAndEveryRoomIsReachable) {
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    FloorPlanOptions o;
    o.seed = seed;
    const auto plan = generate_floor_plan(o);
    const auto& occ = plan.occupancy;
    ASSERT_GE(plan.rooms.size(), 6u);
    const auto udt = unsigned_distance_transform(nearest_occupied_cells(occ));
    // Every tour segment keeps >= 0.3 m from obstacles (a robot of radius 0.2 m fits).
    for (std::size_t k = 0; k + 1 < plan.tour.size(); ++k) {
      for (double s = 0; s <= 1.0; s += 0.01) {
        const Eigen::Vector2d p = (1 - s) * plan.tour[k] + s * plan.tour[k + 1];
        ASSERT_GE(udt(occ.cell_of(p)), 0.3) << "seed " << seed << " segment " << k << " s " << s;
      }
    }
    // Flood fill from the tour start reaches every room centre.
    std::vector<char> seen(occ.num_cells(), 0);
    std::queue<Eigen::Vector2i> q;
    q.push(occ.cell_of(plan.tour.front()));
    seen[occ.linear_index(q.front())] = 1;
    while (!q.empty()) {
      const Eigen::Vector2i c = q.front();
      q.pop();
      for (const Eigen::Vector2i& d : {Eigen::Vector2i(1, 0), Eigen::Vector2i(-1, 0),
                                       Eigen::Vector2i(0, 1), Eigen::Vector2i(0, -1)}) {
        const Eigen::Vector2i nb = c + d;
        if (!occ.contains(nb) || occ(nb) || seen[occ.linear_index(nb)]) continue;
        seen[occ.linear_index(nb)] = 1;
        q.push(nb);
      }
    }
    for (const auto& room : plan.rooms)
      EXPECT_TRUE(seen[occ.linear_index(occ.cell_of(room.centre))]);
    // The building is closed: the grid border cells are never reached.
    for (int i = 0; i < occ.size().x(); ++i)
      EXPECT_FALSE(seen[occ.linear_index(Eigen::Vector2i(i, 0))]);
  }
}

}  // namespace
}  // namespace vdtnav::sim
