// The simulated robot's true trajectory: exact unicycle arcs, within its speed, turn-rate and
// acceleration limits, clear of obstacles, on the path it was given, and as long as asked.
#include "vdtnav/sim/trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/route_planner.hpp"

namespace vdtnav::sim {
namespace {

/// Distance (at cell precision) from every cell of `occ`'s grid to the nearest of `points`:
/// the exact transform of the points rasterised, an oracle independent of the controller.
Grid<float, 2> distance_to(const OccupancyGrid<2>& occ,
                           const std::vector<Eigen::Vector2d>& points) {
  OccupancyGrid<2> marks(occ.size(), occ.frame(), 0);
  for (const auto& p : points) marks(marks.cell_of(p)) = 1;
  return unsigned_distance_transform(nearest_occupied_cells(marks));
}

/// The polyline resampled every 0.02 m.
std::vector<Eigen::Vector2d> densify(const std::vector<Eigen::Vector2d>& path) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const int n = 1 + static_cast<int>((path[k + 1] - path[k]).norm() / 0.02);
    for (int j = 0; j < n; ++j) out.push_back(path[k] + (path[k + 1] - path[k]) * j / n);
  }
  out.push_back(path.back());
  return out;
}

TEST(UnicycleIncrement, MatchesFineEulerIntegrationAndComposesOverTime) {
  for (const auto& [v, w] : {std::pair{0.5, 0.8}, std::pair{0.3, -0.4}, std::pair{0.0, 1.0},
                             std::pair{0.7, 0.0}, std::pair{0.5, 1e-7}}) {
    const double dt = 0.9;
    // Oracle: classical Runge-Kutta on the unicycle ODE.
    const auto f = [v = v, w = w](const Eigen::Vector3d& x) {
      return Eigen::Vector3d(v * std::cos(x[2]), v * std::sin(x[2]), w);
    };
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    const int n = 1000;
    const double h = dt / n;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d k1 = f(x), k2 = f(x + h / 2 * k1), k3 = f(x + h / 2 * k2),
                            k4 = f(x + h * k3);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    const Pose2 inc = unicycle_increment(v, w, dt);
    EXPECT_NEAR(inc[0], x[0], 1e-12) << v << " " << w;
    EXPECT_NEAR(inc[1], x[1], 1e-12) << v << " " << w;
    EXPECT_NEAR(inc[2], x[2], 1e-12) << v << " " << w;
    // Constant (v, w) for dt/3 then 2dt/3 is the same arc as for dt.
    const Pose2 two =
        compose(unicycle_increment(v, w, dt / 3), unicycle_increment(v, w, 2 * dt / 3));
    EXPECT_LT(pose_error(two, inc).norm(), 1e-14);
  }
  // Continuous across the switch to the small-angle series (|w dt| = 1e-4).
  for (int k = 0; k < 3; ++k) {
    const Pose2 below = unicycle_increment(1.0 + k, 1e-4 * (1 - 1e-12), 1.0);
    const Pose2 above = unicycle_increment(1.0 + k, 1e-4 * (1 + 1e-12), 1.0);
    EXPECT_LT((below - above).norm(), 1e-15);
  }
}

/// Every property a trajectory must have, checked on `traj` following `path` through `occ`.
void expect_feasible(const std::vector<TimedPose>& traj, const std::vector<Eigen::Vector2d>& path,
                     const OccupancyGrid<2>& occ, const TrajectoryOptions& o) {
  ASSERT_GE(traj.size(), static_cast<std::size_t>(o.min_steps));
  const auto udt = unsigned_distance_transform(nearest_occupied_cells(occ));
  const auto to_path = distance_to(occ, densify(path));
  const double dt = 1.0 / o.rate_hz;
  // Cell-precision slack of the distance fields: two half cell diagonals.
  const double slack = occ.resolution() * std::sqrt(2.0);
  EXPECT_EQ(traj[0].t, 0.0);
  EXPECT_LT((traj[0].pose.head<2>() - path.front()).norm(), 1e-12);
  std::vector<Eigen::Vector2d> driven;
  for (std::size_t k = 0; k < traj.size(); ++k) {
    const TimedPose& s = traj[k];
    driven.push_back(s.pose.head<2>());
    const Eigen::Vector2i c = occ.cell_of(s.pose.head<2>());
    ASSERT_TRUE(occ.contains(c)) << k;
    ASSERT_GE(udt(c), 0.2) << "sample " << k << " at " << s.pose.transpose();
    ASSERT_GE(s.v, 0.0) << k;
    ASSERT_LE(s.v, o.speed + 1e-12) << k;
    ASSERT_LE(std::abs(s.w), o.max_turn_rate + 1e-12) << k;
    ASSERT_LT(to_path(c), 0.2 + slack) << "sample " << k << " off the path";
    if (k == 0) continue;
    const TimedPose& p = traj[k - 1];
    ASSERT_NEAR(s.t - p.t, dt, 1e-9) << k;
    ASSERT_LE(std::abs(s.v - p.v), o.max_acceleration * dt + 1e-12) << k;
    ASSERT_LE(std::abs(s.w - p.w), o.max_angular_acceleration * dt + 1e-12) << k;
    // The pose is the exact arc of the stored (v, w) from the previous pose.
    const Pose2 expected = compose(p.pose, unicycle_increment(s.v, s.w, s.t - p.t));
    ASSERT_LT(pose_error(s.pose, expected).norm(), 1e-12) << k;
  }
  // The whole path was driven: every path point is passed closely.
  const auto to_driven = distance_to(occ, driven);
  for (const auto& q : path)
    ASSERT_LT(to_driven(occ.cell_of(q)), 0.2 + slack)
        << "path point " << q.transpose() << " missed";
}

TEST(FollowPath, PlannedToursOnFloorPlansAreFeasibleClearAndComplete) {
  for (std::uint32_t seed : {1u, 4u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    FloorPlanOptions fo;
    fo.seed = seed;
    const auto plan = generate_floor_plan(fo);
    const auto path = plan_tour(plan.occupancy, 8, 0.4, seed);
    TrajectoryOptions o;
    o.min_steps = 100;  // shorter than the tour: the tour is driven once, completely
    const auto traj = follow_path(path, plan.occupancy, o);
    expect_feasible(traj, path, plan.occupancy, o);
    // It moves at cruise speed most of the time on a long tour.
    double mean_v = 0.0;
    for (const auto& s : traj) mean_v += s.v / static_cast<double>(traj.size());
    EXPECT_GT(mean_v, 0.6 * o.speed);
  }
}

TEST(FollowPath, TheFloorPlansOwnTourIsFeasibleOverTwoLaps) {
  // The generated tour is closed, visits rooms and turns back in them (cusps, where the robot
  // stops and turns in place), and turns back where it closes too.
  const auto plan = generate_floor_plan({});
  ASSERT_LT((plan.tour.front() - plan.tour.back()).norm(), 0.5);
  const std::vector<Eigen::Vector2d> dense = densify(plan.tour);  // the tour is sparse
  TrajectoryOptions o;
  o.min_steps = 1;
  const auto once = follow_path(plan.tour, plan.occupancy, o);
  o.min_steps = 2 * static_cast<int>(once.size());
  const auto traj = follow_path(plan.tour, plan.occupancy, o);
  EXPECT_EQ(traj.size(), static_cast<std::size_t>(o.min_steps));
  expect_feasible(traj, dense, plan.occupancy, o);
  // The room visits are reached, not cut: where the tour turns back, the robot gets within
  // 0.15 m of the turning point (it stops there and turns in place).
  int cusps = 0;
  for (std::size_t k = 1; k + 1 < plan.tour.size(); ++k) {
    const Eigen::Vector2d in = plan.tour[k] - plan.tour[k - 1],
                          out = plan.tour[k + 1] - plan.tour[k];
    if (in.dot(out) > -0.5 * in.norm() * out.norm()) continue;  // turns by less than 120 degrees
    ++cusps;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : traj) best = std::min(best, (s.pose.head<2>() - plan.tour[k]).norm());
    EXPECT_LT(best, 0.15) << plan.tour[k].transpose();
  }
  EXPECT_GE(cusps, 6);
}

TEST(FollowPath, ASmoothClosedLoopIsRepeatedWithoutStopping) {
  // A 12 m x 12 m walled room and a counter-clockwise circle of radius 4 m in it.
  OccupancyGrid<2> occ(Eigen::Vector2i(240, 240), GridFrame<2>(0.05, Eigen::Vector2d::Zero()), 0);
  for (int k = 0; k < 240; ++k) {
    occ(Eigen::Vector2i(k, 0)) = occ(Eigen::Vector2i(k, 239)) = 1;
    occ(Eigen::Vector2i(0, k)) = occ(Eigen::Vector2i(239, k)) = 1;
  }
  std::vector<Eigen::Vector2d> circle;
  const double kPi = 3.14159265358979323846;
  for (int k = 0; k <= 400; ++k)
    circle.emplace_back(6.0 + 4.0 * std::cos(2 * kPi * k / 400),
                        6.0 + 4.0 * std::sin(2 * kPi * k / 400));
  circle.back() = circle.front();
  TrajectoryOptions o;
  o.min_steps = 6000;  // about three laps of 25 m at 0.5 m/s
  const auto traj = follow_path(circle, occ, o);
  ASSERT_EQ(traj.size(), 6000u);
  expect_feasible(traj, circle, occ, o);
  double turned = 0.0;
  for (std::size_t k = 1; k < traj.size(); ++k) {
    turned += traj[k].w * (traj[k].t - traj[k - 1].t);
    if (traj[k].t < 2.0) continue;   // accelerating from rest
    ASSERT_GT(traj[k].v, 0.4) << k;  // never slows for the junction
    ASSERT_GT(traj[k].w, 0.0) << k;  // always counter-clockwise: repeated, not reversed
  }
  EXPECT_GT(turned, 2 * 2 * kPi);
}

TEST(FollowPath, ShortOpenPathIsDrivenBackAndForthUntilMinSteps) {
  const auto plan = generate_floor_plan({});
  // 6 m along the middle of the main corridor, on both sides of the cross corridor.
  const double y = plan.corridor_y, x0 = plan.cross_corridor_x - 3.0;
  const std::vector<Eigen::Vector2d> path{{x0, y}, {x0 + 6.0, y}};
  TrajectoryOptions o;
  o.min_steps = 3000;
  const auto traj = follow_path(path, plan.occupancy, o);
  ASSERT_EQ(traj.size(), 3000u);
  expect_feasible(traj, path, plan.occupancy, o);
  // 75 s at <= 0.5 m/s over 6 m: it turned at both ends several times, stopping to turn.
  int turnarounds = 0;
  for (std::size_t k = 1; k < traj.size(); ++k) {
    const bool stopped = traj[k].v == 0.0 && traj[k - 1].v > 0.0;
    if (stopped) {
      const double x = traj[k].pose.x();
      EXPECT_TRUE(std::abs(x - x0) < 0.15 || std::abs(x - x0 - 6.0) < 0.15) << "stopped at " << x;
      ++turnarounds;
    }
  }
  EXPECT_GE(turnarounds, 4);
}

TEST(FollowPath, InvalidInputThrowsConfigError) {
  const auto plan = generate_floor_plan({});
  const std::vector<Eigen::Vector2d> path{{20.0, plan.corridor_y}, {25.0, plan.corridor_y}};
  TrajectoryOptions bad;
  bad.speed = 0.0;
  EXPECT_THROW((void)follow_path(path, plan.occupancy, bad), ConfigError);
  bad = {};
  bad.rate_hz = -1.0;
  EXPECT_THROW((void)follow_path(path, plan.occupancy, bad), ConfigError);
  bad = {};
  bad.min_steps = 0;
  EXPECT_THROW((void)follow_path(path, plan.occupancy, bad), ConfigError);
  EXPECT_THROW((void)follow_path({path[0]}, plan.occupancy, {}), ConfigError);
  EXPECT_THROW((void)follow_path({path[0], path[0]}, plan.occupancy, {}), ConfigError);
  EXPECT_THROW((void)follow_path({path[0], Eigen::Vector2d(100.0, 0.0)}, plan.occupancy, {}),
               ConfigError);
}

}  // namespace
}  // namespace vdtnav::sim
