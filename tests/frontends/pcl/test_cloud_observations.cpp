// observations_from_cloud against the geometry written out by hand (ranges, beam directions,
// robot-frame points), the range limits, and a brute-force voxel downsampling.
#include "vdtnav/pcl/cloud_observations.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

TEST(CloudObservations, BeamsStartAtTheViewpointAndEndInTheRobotFrame) {
  Cloud cloud;
  cloud.push_back(pcl::PointXYZ(4.0f, 1.0f, 1.0f));  // (3, 0, 0) from the viewpoint: range 3
  cloud.push_back(pcl::PointXYZ(1.0f, 5.0f, 1.0f));  // (0, 4, 0) from it: range 4
  cloud.sensor_origin_ = Eigen::Vector4f(1.0f, 1.0f, 1.0f, 0.0f);
  CloudObservationOptions o;
  o.sensor_in_robot = pose3_from_xyz_rpy(0.5, -0.2, 1.5, 0.0, 0.0, M_PI / 2);  // yaw 90 deg
  o.sigma_range = 0.02;
  const ObservationSet3 s = observations_from_cloud(cloud, o);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.beam, (std::vector<std::size_t>{0, 1}));
  EXPECT_NEAR(s.ranges[0], 3.0, 1e-12);
  EXPECT_NEAR(s.ranges[1], 4.0, 1e-12);
  // Yaw 90 deg maps x to y and y to -x; then the translation.
  EXPECT_LT((s.points[0] - Eigen::Vector3d(0.5 - 1.0, -0.2 + 4.0, 2.5)).norm(), 1e-12);
  EXPECT_LT((s.points[1] - Eigen::Vector3d(0.5 - 5.0, -0.2 + 1.0, 2.5)).norm(), 1e-12);
  EXPECT_LT((s.directions[0] - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  EXPECT_LT((s.directions[1] - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
  EXPECT_EQ(s.sigma_range, 0.02);
  // The point's covariance is the range noise along the beam.
  EXPECT_LT((s.point_covariance(1) -
             0.0004 * Eigen::Vector3d(1, 0, 0) * Eigen::Vector3d(1, 0, 0).transpose())
                .norm(),
            1e-15);
}

TEST(CloudObservations, DropsAndCountsInvalidAndOutOfRangeReadings) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Cloud cloud;
  cloud.push_back(pcl::PointXYZ(2.0f, 0.0f, 0.0f));   // 0: range 2, kept
  cloud.push_back(pcl::PointXYZ(nan, 0.0f, 0.0f));    // 1: not finite
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.0f));   // 2: range 0
  cloud.push_back(pcl::PointXYZ(0.5f, 0.0f, 0.0f));   // 3: below range_min
  cloud.push_back(pcl::PointXYZ(0.0f, 10.0f, 0.0f));  // 4: exactly range_max, dropped
  cloud.push_back(pcl::PointXYZ(0.0f, 9.5f, 0.0f));   // 5: kept
  cloud.push_back(pcl::PointXYZ(0.0f, inf, 0.0f));    // 6: not finite
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 80.f));   // 7: beyond
  CloudObservationOptions o;
  o.range_min = 1.0;
  o.range_max = 10.0;
  const ObservationSet3 s = observations_from_cloud(cloud, o);
  EXPECT_EQ(s.beam, (std::vector<std::size_t>{0, 5}));
  EXPECT_EQ(s.dropped_not_finite, 2u);
  EXPECT_EQ(s.dropped_out_of_range, 4u);
  EXPECT_EQ(s.range_max, 10.0);
  // By default nothing finite and non-zero is dropped: no silent range limit.
  const ObservationSet3 all = observations_from_cloud(cloud);
  EXPECT_EQ(all.beam, (std::vector<std::size_t>{0, 3, 4, 5, 7}));
}

TEST(CloudObservations, VoxelDownsamplingKeepsTheReadingNearestEachCubesCentroid) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  Cloud cloud;
  for (int i = 0; i < 4000; ++i) cloud.push_back(pcl::PointXYZ(u(rng), u(rng), 0.3f * u(rng)));
  const double voxel = 0.5;
  CloudObservationOptions o;
  o.voxel = voxel;
  o.sensor_in_robot = pose3_from_xyz_rpy(1, 2, 3, 0.1, 0.2, 0.3);
  const ObservationSet3 s = observations_from_cloud(cloud, o);

  // Oracle: group by cube, centroid, nearest point by exhaustive search.
  using Cube = std::tuple<long, long, long>;
  std::map<Cube, std::vector<std::size_t>> members;
  const auto cube = [&](std::size_t i) {
    const Eigen::Vector3d q = cloud[i].getVector3fMap().cast<double>();
    return Cube(static_cast<long>(std::floor(q.x() / voxel)),
                static_cast<long>(std::floor(q.y() / voxel)),
                static_cast<long>(std::floor(q.z() / voxel)));
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) members[cube(i)].push_back(i);
  ASSERT_EQ(s.size(), members.size());
  std::map<Cube, int> seen;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const std::vector<std::size_t>& m = members.at(cube(s.beam[k]));
    ++seen[cube(s.beam[k])];
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::size_t i : m) centroid += cloud[i].getVector3fMap().cast<double>();
    centroid /= static_cast<double>(m.size());
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i : m)
      best = std::min(best, (cloud[i].getVector3fMap().cast<double>() - centroid).norm());
    const Eigen::Vector3d kept = cloud[s.beam[k]].getVector3fMap().cast<double>();
    EXPECT_NEAR((kept - centroid).norm(), best, 1e-12) << k;
    EXPECT_LT((s.points[k] - o.sensor_in_robot * kept).norm(), 1e-12);
    EXPECT_NEAR(s.ranges[k], kept.norm(), 1e-12);
  }
  for (const auto& [c, n] : seen) EXPECT_EQ(n, 1);
  // In the order the cubes first appear in the cloud.
  for (std::size_t k = 1; k < s.size(); ++k)
    EXPECT_LT(members.at(cube(s.beam[k - 1])).front(), members.at(cube(s.beam[k])).front());
}

TEST(CloudObservations, RefusesOptionsOutOfTheirDomain) {
  Cloud cloud;
  cloud.push_back(pcl::PointXYZ(1.0f, 0.0f, 0.0f));
  const auto refused = [&](auto set) {
    CloudObservationOptions o;
    set(o);
    EXPECT_THROW((void)observations_from_cloud(cloud, o), ConfigError);
  };
  refused([](CloudObservationOptions& o) { o.sigma_range = -0.1; });
  refused([](CloudObservationOptions& o) { o.sigma_range = std::nan(""); });
  refused([](CloudObservationOptions& o) { o.range_min = -1.0; });
  refused([](CloudObservationOptions& o) { o.range_max = 0.0; });
  refused([](CloudObservationOptions& o) { o.voxel = -0.2; });
  refused([](CloudObservationOptions& o) { o.voxel = std::numeric_limits<double>::infinity(); });
}

}  // namespace
}  // namespace vdtnav
