#include "vdtnav/map/grid.hpp"

#include <gtest/gtest.h>

namespace vdtnav {
namespace {

TEST(GridFrame, RosCornerConventionPutsCellCentresHalfACellIn) {
  const GridFrame<2> f(0.05, Eigen::Vector2d(-10.0, 2.0));
  // Cell (0, 0) spans [-10, -9.95] x [2, 2.05]: its centre is half a cell in from the origin.
  EXPECT_NEAR(f.cell_center(Eigen::Vector2i(0, 0)).x(), -9.975, 1e-12);
  EXPECT_NEAR(f.cell_center(Eigen::Vector2i(3, 1)).y(), 2.075, 1e-12);
  EXPECT_EQ(f.cell_of(Eigen::Vector2d(-9.9501, 2.0001)), Eigen::Vector2i(0, 0));
  EXPECT_EQ(f.cell_of(Eigen::Vector2d(-10.0001, 2.0)), Eigen::Vector2i(-1, 0));
}

TEST(GridFrame, RotatedFrameRoundTrips) {
  const GridFrame<2> f(0.1, Eigen::Vector2d(1.0, -2.0), 0.7);
  const Eigen::Vector2d u(3.25, -1.5);
  EXPECT_TRUE(f.continuous_index(f.world_point(u)).isApprox(u, 1e-12));
  // One cell along grid x moves resolution along (cos yaw, sin yaw).
  const Eigen::Vector2d step =
      f.cell_center(Eigen::Vector2i(1, 0)) - f.cell_center(Eigen::Vector2i(0, 0));
  EXPECT_NEAR(step.x(), 0.1 * std::cos(0.7), 1e-12);
  EXPECT_NEAR(step.y(), 0.1 * std::sin(0.7), 1e-12);
}

TEST(Grid, LinearIndexIsXFastestAndInvertible) {
  const Grid<int, 3> g(Eigen::Vector3i(4, 5, 6), GridFrame<3>(1.0, Eigen::Vector3d::Zero()));
  EXPECT_EQ(g.linear_index(Eigen::Vector3i(1, 0, 0)), 1);
  EXPECT_EQ(g.linear_index(Eigen::Vector3i(0, 1, 0)), 4);
  EXPECT_EQ(g.linear_index(Eigen::Vector3i(0, 0, 1)), 20);
  for (std::ptrdiff_t l = 0; l < static_cast<std::ptrdiff_t>(g.num_cells()); ++l) {
    ASSERT_EQ(g.linear_index(g.index_of(l)), l);
  }
  EXPECT_TRUE(g.contains(Eigen::Vector3i(3, 4, 5)));
  EXPECT_FALSE(g.contains(Eigen::Vector3i(4, 0, 0)));
  EXPECT_FALSE(g.contains(Eigen::Vector3i(0, -1, 0)));
}

TEST(Grid, RejectsBadConfiguration) {
  EXPECT_THROW(GridFrame<2>(0.0, Eigen::Vector2d::Zero()), ConfigError);
  EXPECT_THROW(GridFrame<2>(-1.0, Eigen::Vector2d::Zero()), ConfigError);
  EXPECT_THROW((Grid<int, 2>(Eigen::Vector2i(0, 3), GridFrame<2>(1.0, Eigen::Vector2d::Zero()))),
               ConfigError);
}

}  // namespace
}  // namespace vdtnav
