// Point-laser observations from PCL: a cloud of points in the unit's base frame, beams from its
// viewpoint, gives the same observation set as the (pan, tilt, range) readings through the
// calibration; a PCD file written here by hand reads back to the same set.
#include "vdtnav/pcl/point_laser_cloud.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"

namespace vdtnav::point_laser {
namespace {

constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();

/// A unit whose beam origin does not move with pan and tilt: the tilt axis on the pan axis,
/// 0.045 m above the base, and the beam starting on the tilt axis.
PanTiltCalibration fixed_origin_unit() {
  PanTiltCalibration c;
  c.mount = pose3_from_xyz_rpy(-0.05, 0.02, 0.36, 0.01, -0.02, 0.3);
  c.pan_to_tilt = Eigen::Vector3d(0.0, 0.0, 0.045);
  return c;
}

/// Readings over a pan/tilt raster with random ranges, and a few invalid ones.
std::vector<PanTiltReading> readings() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> range(0.2, 30.0);
  std::vector<PanTiltReading> out;
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 10; ++j) out.push_back({-3.0 + 0.25 * i, -0.5 + 0.13 * j, range(rng), 0.0});
  out[5].range = std::numeric_limits<double>::infinity();  // no return
  out[17].range = std::numeric_limits<double>::quiet_NaN();
  out[40].range = 0.02;  // too close
  out[41].range = 45.0;  // too far
  return out;
}

/// The readings as a driver would publish them: points in the unit's base frame (NaN for no
/// return), with the beam origin as the viewpoint.
pcl::PointCloud<pcl::PointXYZ> cloud_of(const std::vector<PanTiltReading>& rs,
                                        const PanTiltCalibration& c) {
  PanTiltCalibration base = c;
  base.mount = Pose3::Identity();
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (const PanTiltReading& z : rs) {
    if (!std::isfinite(z.range)) {
      cloud.push_back(pcl::PointXYZ(kNaNf, kNaNf, kNaNf));
      continue;
    }
    const Eigen::Vector3d q = pan_tilt_point(base, z).point;
    cloud.push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()),
                                  static_cast<float>(q.z())));
  }
  cloud.is_dense = false;
  cloud.sensor_origin_ = Eigen::Vector4f(0.0f, 0.0f, 0.045f, 0.0f);
  return cloud;
}

void expect_same(const ObservationSet3& a, const ObservationSet3& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.beam, b.beam);
  EXPECT_EQ(a.dropped_not_finite, b.dropped_not_finite);
  EXPECT_EQ(a.dropped_out_of_range, b.dropped_out_of_range);
  EXPECT_EQ(a.sigma_range, b.sigma_range);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_LT((a.points[k] - b.points[k]).norm(), tol) << k;
    EXPECT_LT((a.directions[k] - b.directions[k]).norm(), tol) << k;
    EXPECT_NEAR(a.ranges[k], b.ranges[k], tol) << k;
  }
}

TEST(PointLaserPcl, CloudGivesTheObservationsOfTheReadings) {
  const PanTiltCalibration c = fixed_origin_unit();
  const auto rs = readings();
  const ObservationSet3 direct = point_laser_observations(rs, c);
  EXPECT_EQ(direct.size(), rs.size() - 4);
  EXPECT_EQ(direct.dropped_not_finite, 2u);
  EXPECT_EQ(direct.dropped_out_of_range, 2u);
  // Float coordinates: a few micrometres at 30 m.
  expect_same(observations_from_cloud(cloud_of(rs, c), c.mount), direct, 1e-5);
}

TEST(PointLaserPcl, BeamsStartAtTheViewpoint) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(3.0f, 4.0f, 0.0f));
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.0f));  // at the sensor: range 0, dropped
  const Pose3 sensor = pose3_from_xyz_rpy(1.0, 2.0, 0.5, 0.0, 0.0, 3.14159265358979323846 / 2);
  const ObservationSet3 at_origin = observations_from_cloud(cloud, sensor);
  ASSERT_EQ(at_origin.size(), 1u);
  EXPECT_EQ(at_origin.dropped_out_of_range, 1u);
  EXPECT_NEAR(at_origin.ranges[0], 5.0, 1e-12);
  // Yaw 90 deg: sensor x is robot y, sensor y is robot -x.
  EXPECT_LT((at_origin.points[0] - Eigen::Vector3d(1.0 - 4.0, 2.0 + 3.0, 0.5)).norm(), 1e-12);
  EXPECT_LT((at_origin.directions[0] - Eigen::Vector3d(-0.8, 0.6, 0.0)).norm(), 1e-12);
  cloud.sensor_origin_ = Eigen::Vector4f(3.0f, 0.0f, 0.0f, 0.0f);
  const ObservationSet3 shifted = observations_from_cloud(cloud, sensor);
  ASSERT_EQ(shifted.size(), 2u);
  EXPECT_NEAR(shifted.ranges[0], 4.0, 1e-12);
  EXPECT_LT((shifted.directions[0] - Eigen::Vector3d(-1.0, 0.0, 0.0)).norm(), 1e-12);
  EXPECT_NEAR(shifted.ranges[1], 3.0, 1e-12);
}

TEST(PointLaserPcl, PcdFileReadsBackToTheSameObservations) {
  const PanTiltCalibration c = fixed_origin_unit();
  const auto cloud = cloud_of(readings(), c);
  // An ASCII PCD written by hand (the format, not PCL's writer), viewpoint = beam origin.
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  const std::string path = std::string(VDTNAV_TEST_TMP) + "/sweep.pcd";
  {
    std::ofstream out(path);
    out << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\n"
        << "SIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << cloud.size() << "\nHEIGHT 1\n"
        << "VIEWPOINT 0 0 0.045 1 0 0 0\nPOINTS " << cloud.size() << "\nDATA ascii\n";
    char line[128];
    for (const auto& p : cloud) {
      if (!std::isfinite(p.x)) {
        out << "nan nan nan\n";
        continue;
      }
      std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", p.x, p.y, p.z);
      out << line;
    }
  }
  const ObservationSet3 from_file = read_point_laser_pcd(path, c.mount);
  expect_same(from_file, observations_from_cloud(cloud, c.mount), 0.0 + 1e-15);
  expect_same(from_file, point_laser_observations(readings(), c), 1e-5);

  const pcl::PointCloud<pcl::PointXYZ> robot_frame = to_cloud(from_file);
  ASSERT_EQ(robot_frame.size(), from_file.size());
  EXPECT_EQ(robot_frame.height, 1u);
  for (std::size_t k = 0; k < from_file.size(); ++k)
    EXPECT_EQ(robot_frame[k].z, static_cast<float>(from_file.points[k].z()));
}

TEST(PointLaserPcl, MissingOrMalformedPcdThrows) {
  EXPECT_THROW(
      (void)read_point_laser_pcd(std::string(VDTNAV_TEST_TMP) + "/missing.pcd", Pose3::Identity()),
      IoError);
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  const std::string path = std::string(VDTNAV_TEST_TMP) + "/garbage.pcd";
  std::ofstream(path) << "this is not a point cloud\n";
  EXPECT_THROW((void)read_point_laser_pcd(path, Pose3::Identity()), FormatError);
  const std::string no_z = std::string(VDTNAV_TEST_TMP) + "/no_z.pcd";
  std::ofstream(no_z) << "VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\n"
                         "HEIGHT 1\nPOINTS 1\nDATA ascii\n1 2\n";
  try {
    (void)read_point_laser_pcd(no_z, Pose3::Identity());
    ADD_FAILURE() << "no FormatError";
  } catch (const FormatError& e) {
    EXPECT_EQ(std::string(e.what()),
              no_z + ": the cloud has no 'z' field; expected x, y, z coordinates");
  }
}

}  // namespace
}  // namespace vdtnav::point_laser
