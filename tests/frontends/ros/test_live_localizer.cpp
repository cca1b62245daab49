// LiveLocalizer, the ROS-free core of the node: scans rendered by ray casting in a room with a
// known map -> odom offset, messages fed in the orders a live graph delivers them. A scan waits
// for the odometry at its stamp, is localized at the truth, and map -> odom is the offset the
// test chose; amcl's update_min_d skips scans until the robot moved; a scan the odometry never
// covers is reported and does not block the ones behind it; a missing mounting is named, not
// guessed, and a scan older than the first mounting transform is no_transform while the next are
// localized; global localization finds the pose without a prior.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "vdtnav/ros/live_localizer.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::ros {
namespace {

constexpr std::int64_t kSecond = 1000000000;
/// Stamps start here: tf2 reads a stamp of 0 as "the latest".
constexpr std::int64_t kT0 = 100 * kSecond;

/// A 12 m x 8 m room, 5 cm cells, with three boxes that make every pose unique.
RosMap room() {
  RosMap m;
  m.metadata.resolution = 0.05;
  m.metadata.origin = {-1.0, -1.0, 0.0};
  m.cells = Grid<std::int8_t, 2>(Eigen::Vector2i(240, 160),
                                 GridFrame<2>(0.05, Eigen::Vector2d(-1.0, -1.0), 0.0), 0);
  for (int i = 0; i < 240; ++i) {
    for (int j = 0; j < 160; ++j) {
      const bool wall = i < 2 || j < 2 || i >= 238 || j >= 158;
      const bool box1 = i >= 40 && i < 70 && j >= 100 && j < 120;    // 1.5 m x 1 m
      const bool box2 = i >= 150 && i < 190 && j >= 30 && j < 40;    // 2 m x 0.5 m
      const bool box3 = i >= 200 && i < 210 && j >= 110 && j < 150;  // 0.5 m x 2 m
      if (wall || box1 || box2 || box3) m.cells(Eigen::Vector2i(i, j)) = 100;
    }
  }
  return m;
}

const Pose2 kMount(0.1, 0.0, 0.0);       // laser in base_link
const Pose2 kMapToOdom(1.5, -0.7, 0.4);  // the offset the node must find

/// The scan at robot pose `truth` (map frame): 360 beams over the full turn, exact ranges.
LaserScanMsg render(const OccupancyGrid<2>& grid, const Pose2& truth, std::int64_t stamp) {
  LaserScanMsg m;
  m.header.stamp_ns = kT0 + stamp;
  m.header.frame_id = "laser";
  m.angle_min = static_cast<float>(-kPi);
  m.angle_increment = static_cast<float>(2.0 * kPi / 360.0);
  m.angle_max = static_cast<float>(kPi - 2.0 * kPi / 360.0);
  m.range_min = 0.05F;
  m.range_max = 20.0F;
  const Pose2 sensor = compose(truth, kMount);
  for (int i = 0; i < 360; ++i) {
    const double a = sensor[2] + m.angle_min + i * m.angle_increment;
    const double r =
        sim::cast_ray<2>(grid, sensor.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)), 20.0,
                         sim::RaySurface::kCellCentre);
    m.ranges.push_back(std::isfinite(r) ? static_cast<float>(r) : 0.0F);
  }
  return m;
}

TransformStampedMsg transform(const std::string& parent, const std::string& child, const Pose2& p,
                              std::int64_t stamp) {
  TransformStampedMsg t;
  t.header.stamp_ns = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.translation = {p[0], p[1], 0.0};
  t.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(p[2], Eigen::Vector3d::UnitZ()));
  return t;
}

/// odom -> base_link at the robot's true map pose (odometry without drift).
TfMsg odometry(const Pose2& truth, std::int64_t stamp) {
  return TfMsg{{transform("odom", "base_link", between(kMapToOdom, truth), kT0 + stamp)}};
}

TfMsg mounting() { return TfMsg{{transform("base_link", "laser", kMount, 0)}}; }

struct LiveStream : ::testing::Test {
  RosMap map = room();
  OccupancyGrid<2> grid = occupancy(map);
};

void expect_near(const Pose2& a, const Pose2& b, double d, double yaw) {
  EXPECT_LE(std::hypot(a[0] - b[0], a[1] - b[1]), d) << a.transpose() << " vs " << b.transpose();
  EXPECT_LE(std::abs(wrap_angle(a[2] - b[2])), yaw) << a.transpose() << " vs " << b.transpose();
}

TEST_F(LiveStream, AScanWaitsForItsOdometryThenIsLocalizedAndMapToOdomIsTheOffset) {
  LiveLocalizer loc(map, log_settings(), {});
  const Pose2 truth(4.0, 3.0, 0.3);
  loc.set_pose(truth + Pose2(0.15, -0.1, 0.04), Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal());
  EXPECT_TRUE(loc.add_transforms(mounting(), true).empty());
  // The scan first, its odometry after (a scanner faster than the odometry's TF).
  EXPECT_TRUE(loc.add_transforms(odometry(truth, 9 * kSecond / 10), false).empty());
  EXPECT_TRUE(loc.add_scan(render(grid, truth, kSecond)).empty());
  EXPECT_EQ(loc.waiting(), 1U);
  const std::vector<LiveEstimate> e = loc.add_transforms(odometry(truth, 11 * kSecond / 10), false);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(loc.waiting(), 0U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kLocalized);
  EXPECT_EQ(e[0].stamp_ns, kT0 + kSecond);
  EXPECT_EQ(e[0].result.status, LocalizationStatus::kConverged);
  expect_near(e[0].result.pose, truth, 0.01, 0.005);
  ASSERT_TRUE(e[0].has_map_to_odom);
  expect_near(e[0].map_to_odom, kMapToOdom, 0.01, 0.005);
  EXPECT_EQ(loc.mount_source(), "TF base_link -> laser");
}

TEST_F(LiveStream, UpdateMinDistanceSkipsScansUntilTheRobotMovedThenStepsFromTheLastLocalized) {
  LiveLocalizerOptions o;
  o.update_min_d = 0.2;
  o.update_min_a = 0.5;
  LiveLocalizer loc(map, log_settings(), o);
  ASSERT_TRUE(loc.add_transforms(mounting(), true).empty());
  Pose2 truth(3.0, 2.0, 0.0);
  loc.set_pose(truth, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  std::vector<LiveEstimate::Event> events;
  std::vector<LiveEstimate> localized;
  for (int k = 0; k <= 5; ++k) {
    const Pose2 p = truth + Pose2(0.06 * k, 0.0, 0.0);  // 6 cm per scan
    const std::int64_t t = k * kSecond / 10;
    (void)loc.add_transforms(odometry(p, t - kSecond / 100), false);
    (void)loc.add_scan(render(grid, p, t));
    for (const LiveEstimate& e : loc.add_transforms(odometry(p, t + kSecond / 100), false)) {
      events.push_back(e.event);
      if (e.event == LiveEstimate::Event::kLocalized) localized.push_back(e);
    }
  }
  // Scan 0 starts the track; 1-3 moved 6, 12, 18 cm (< 20): skipped; 4 moved 24 cm; 5 skipped.
  using E = LiveEstimate::Event;
  EXPECT_EQ(events, (std::vector<E>{E::kLocalized, E::kSkipped, E::kSkipped, E::kSkipped,
                                    E::kLocalized, E::kSkipped}));
  ASSERT_EQ(localized.size(), 2U);
  expect_near(localized[1].result.pose, truth + Pose2(0.24, 0.0, 0.0), 0.01, 0.005);
}

TEST_F(LiveStream, AScanTheOdometryNeverCoversIsReportedAndDoesNotBlockTheOnesBehindIt) {
  LiveLocalizer loc(map, log_settings(), {});
  ASSERT_TRUE(loc.add_transforms(mounting(), true).empty());
  const Pose2 truth(6.0, 4.0, -1.0);
  loc.set_pose(truth, Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal());
  // A scan stamped before the first odometry (a driver started early).
  EXPECT_TRUE(loc.add_scan(render(grid, truth, 0)).empty());
  EXPECT_TRUE(loc.add_transforms(odometry(truth, kSecond / 2), false).empty());
  EXPECT_TRUE(loc.add_scan(render(grid, truth, kSecond)).empty());
  EXPECT_EQ(loc.waiting(), 2U);
  // Odometry 1.1 s after the first scan's stamp: that one will not get it; the second does.
  const std::vector<LiveEstimate> e = loc.add_transforms(odometry(truth, 11 * kSecond / 10), false);
  ASSERT_EQ(e.size(), 2U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kNoOdometry);
  EXPECT_EQ(e[0].stamp_ns, kT0);
  EXPECT_NE(e[0].reason.find("odom -> base_link"), std::string::npos) << e[0].reason;
  EXPECT_EQ(e[1].event, LiveEstimate::Event::kLocalized);
  EXPECT_EQ(e[1].result.status, LocalizationStatus::kConverged);
  expect_near(e[1].result.pose, truth, 0.01, 0.005);
}

TEST_F(LiveStream, WithoutAMountingTheScanWaitsThenIsReportedWithTheFramesNotGuessed) {
  LiveLocalizer loc(map, log_settings(), {});
  const Pose2 truth(4.0, 3.0, 0.3);
  loc.set_pose(truth, Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal());
  (void)loc.add_transforms(odometry(truth, 0), false);
  (void)loc.add_scan(render(grid, truth, kSecond / 10));
  // Its odometry is known, its mounting not yet: it waits (a /tf_static may still come).
  EXPECT_TRUE(loc.add_transforms(odometry(truth, kSecond / 5), false).empty());
  EXPECT_EQ(loc.waiting(), 1U);
  // Transforms 1 s newer than the scan, still no mounting: no_transform, the frames named.
  const std::vector<LiveEstimate> e = loc.add_transforms(odometry(truth, 12 * kSecond / 10), false);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kNoTransform);
  EXPECT_STREQ(to_string(e[0].event), "no_transform");
  EXPECT_NE(e[0].reason.find("base_link -> laser"), std::string::npos) << e[0].reason;
  EXPECT_NE(e[0].reason.find("laser_pose"), std::string::npos) << e[0].reason;
}

TEST_F(LiveStream, AScanOlderThanTheFirstMountingTransformIsNoTransformAndTheNextAreLocalized) {
  // A real Neato bag's first scan is older than its first /tf, which carries the mounting.
  LiveLocalizer loc(map, log_settings(), {});
  const Pose2 truth(4.0, 3.0, 0.3);
  loc.set_pose(truth, Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal());
  std::vector<LiveEstimate> e;
  const auto take = [&e](std::vector<LiveEstimate> more) {
    e.insert(e.end(), more.begin(), more.end());
  };
  take(loc.add_scan(render(grid, truth, kSecond / 10)));
  for (int k = 0; k <= 15; ++k) {  // /tf at 10 Hz from 0.15 s on: odometry and the mounting
    const std::int64_t t = kT0 + kSecond / 20 + k * kSecond / 10;
    TfMsg tf = odometry(truth, t - kT0);
    if (k > 0) tf.transforms.push_back(transform("base_link", "laser", kMount, t));
    take(loc.add_transforms(tf, false));
    if (k == 2) take(loc.add_scan(render(grid, truth, 3 * kSecond / 10)));
  }
  ASSERT_EQ(e.size(), 2U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kNoTransform);
  EXPECT_EQ(e[0].stamp_ns, kT0 + kSecond / 10);
  EXPECT_EQ(e[1].event, LiveEstimate::Event::kLocalized);
  EXPECT_EQ(e[1].stamp_ns, kT0 + 3 * kSecond / 10);
  EXPECT_EQ(e[1].result.status, LocalizationStatus::kConverged);
  expect_near(e[1].result.pose, truth, 0.01, 0.005);
  EXPECT_EQ(loc.mount_source(), "TF base_link -> laser");
}

TEST_F(LiveStream, GlobalLocalizationFindsThePoseWithoutAPrior) {
  LiveLocalizer loc(map, log_settings(), {});
  ASSERT_TRUE(loc.add_transforms(mounting(), true).empty());
  // Before any pose: the scans are no_pose.
  Pose2 truth(8.5, 5.0, 2.2);
  (void)loc.add_transforms(odometry(truth, 0), false);
  (void)loc.add_scan(render(grid, truth, kSecond / 10));
  std::vector<LiveEstimate> e = loc.add_transforms(odometry(truth, kSecond / 5), false);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kNoPose);
  // The global_localization service: the next scan is searched for in the whole map.
  loc.set_pose(Pose2(1.0, 1.0, 0.0), Eigen::Matrix3d::Identity());  // a wrong start ...
  loc.start_global();                                               // ... forgotten
  EXPECT_TRUE(loc.global_pending());
  loc.set_map(room());  // a map arriving while the search is pending: searched on the new one
  EXPECT_TRUE(loc.global_pending());
  (void)loc.add_scan(render(grid, truth, 3 * kSecond / 10));
  e = loc.add_transforms(odometry(truth, 4 * kSecond / 10), false);
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kLocalized);
  EXPECT_EQ(e[0].result.status, LocalizationStatus::kConverged) << e[0].result.explained;
  expect_near(e[0].result.pose, truth, 0.02, 0.01);
  EXPECT_FALSE(loc.global_pending());
  expect_near(e[0].map_to_odom, kMapToOdom, 0.02, 0.01);
}

TEST_F(LiveStream, WithOdometryExtrapolationAScanNewerThanTheOdometryIsLocalizedAtOnce) {
  LiveLocalizerOptions o;
  o.odom_extrapolation = 0.2;
  LiveLocalizer loc(map, log_settings(), o);
  ASSERT_TRUE(loc.add_transforms(mounting(), true).empty());
  // The robot drives at 0.5 m/s and 0.2 rad/s; odometry at 20 Hz, the scan 80 ms after the last.
  const auto truth_at = [](double s) { return Pose2(3.0 + 0.5 * s, 3.0, 0.2 * s); };
  loc.set_pose(truth_at(0.0), Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  for (int k = 0; k <= 10; ++k) {
    ASSERT_TRUE(loc.add_transforms(odometry(truth_at(0.05 * k), kSecond / 20 * k), false).empty());
  }
  const std::int64_t t = kSecond / 2 + 80'000'000;
  const std::vector<LiveEstimate> e = loc.add_scan(render(grid, truth_at(0.58), t));
  ASSERT_EQ(e.size(), 1U);
  EXPECT_EQ(e[0].event, LiveEstimate::Event::kLocalized);
  EXPECT_EQ(e[0].result.status, LocalizationStatus::kConverged);
  expect_near(e[0].result.pose, truth_at(0.58), 0.01, 0.005);
  // The odometry carried 80 ms past its last sample: the robot's odom pose at the stamp.
  expect_near(e[0].odometry, between(kMapToOdom, truth_at(0.58)), 0.002, 0.002);
  // Beyond odom_extrapolation the scan waits, as without it.
  EXPECT_TRUE(loc.add_scan(render(grid, truth_at(0.8), kSecond * 8 / 10)).empty());
  EXPECT_EQ(loc.waiting(), 1U);
}

}  // namespace
}  // namespace vdtnav::ros
