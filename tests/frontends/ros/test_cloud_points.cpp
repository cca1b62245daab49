// PointCloud2 messages as points and per-point times: clouds laid out here byte by byte (fields
// out of order, FLOAT64, padded rows, organized), the broken ones refused, and the real Luminar
// clouds of the shared lz4 bag (README: 6.9-250 m, time_sec/time_nsec per point).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_points.hpp"

namespace vdtnav::ros {
namespace {

template <typename T>
void put(std::vector<std::uint8_t>& data, std::size_t at, T v) {
  std::memcpy(data.data() + at, &v, sizeof v);
}

/// 2 rows x 3 points, point_step 32 (z at 0, x at 8, y at 16 as FLOAT64; t at 24 as UINT32 ns),
/// row_step 100 (4 bytes of padding per row); point (row 1, col 1) is NaN.
PointCloud2Msg organized_cloud() {
  PointCloud2Msg m;
  m.header.stamp_ns = 5000000000;
  m.height = 2;
  m.width = 3;
  m.point_step = 32;
  m.row_step = 100;
  m.fields = {{"z", 0, 8, 1}, {"x", 8, 8, 1}, {"y", 16, 8, 1}, {"t", 24, 6, 1}};
  m.data.assign(200, 0xAB);
  for (std::uint32_t r = 0; r < 2; ++r) {
    for (std::uint32_t c = 0; c < 3; ++c) {
      const std::size_t at = r * 100 + c * 32;
      const double k = 3.0 * r + c;
      put(m.data, at + 8, 1.0 + k);
      put(m.data, at + 16, -2.0 * k);
      put(m.data, at + 0, r == 1 && c == 1 ? std::numeric_limits<double>::quiet_NaN() : 0.5 * k);
      put(m.data, at + 24, static_cast<std::uint32_t>(1000000 * (k + 1)));  // (k + 1) ms
    }
  }
  return m;
}

TEST(CloudPoints, FieldsAreFoundByNameInAnyLayout) {
  const CloudPoints p = cloud_points(organized_cloud(), "test");
  ASSERT_EQ(p.points.size(), 5U);
  EXPECT_EQ(p.dropped_not_finite, 1U);
  EXPECT_EQ(p.time_field, "t");
  ASSERT_EQ(p.times.size(), 5U);
  std::size_t i = 0;
  for (int k = 0; k < 6; ++k) {
    if (k == 4) continue;  // the NaN point
    EXPECT_EQ(p.points[i], Eigen::Vector3d(1.0 + k, -2.0 * k, 0.5 * k)) << k;
    EXPECT_NEAR(p.times[i], 1e-3 * (k + 1), 1e-12) << k;
    ++i;
  }
}

TEST(CloudPoints, BrokenCloudsAreRefused) {
  PointCloud2Msg big = organized_cloud();
  big.is_bigendian = true;
  EXPECT_THROW((void)cloud_points(big, "test"), FormatError);
  PointCloud2Msg no_z = organized_cloud();
  no_z.fields.erase(no_z.fields.begin());
  EXPECT_THROW((void)cloud_points(no_z, "test"), FormatError);
  PointCloud2Msg short_data = organized_cloud();
  short_data.data.resize(150);  // the second row is cut
  EXPECT_THROW((void)cloud_points(short_data, "test"), FormatError);
  PointCloud2Msg narrow_rows = organized_cloud();
  narrow_rows.row_step = 90;  // < 3 x 32
  EXPECT_THROW((void)cloud_points(narrow_rows, "test"), FormatError);
  PointCloud2Msg past_step = organized_cloud();
  past_step.fields[3].offset = 30;  // a 4-byte field at 30 of a 32-byte point
  EXPECT_THROW((void)cloud_points(past_step, "test"), FormatError);
  PointCloud2Msg int_x = organized_cloud();
  int_x.fields[1].datatype = 5;  // INT32 x
  EXPECT_THROW((void)cloud_points(int_x, "test"), FormatError);
}

TEST(CloudPoints, TheLuminarCloudsOfTheLz4Bag) {
  const std::filesystem::path bag_path =
      std::filesystem::path(VDTNAV_DATA_DIR) / "rosbags/embag-lz4/test.bag";
  if (!std::filesystem::exists(bag_path)) GTEST_SKIP() << "no " << bag_path;
  const auto bag = BagReader::open(bag_path.string());
  int clouds = 0;
  bag->read({"/luminar_pointcloud"}, [&](const BagMessage& m) -> bool {
    const PointCloud2Msg msg = decode_point_cloud2(m);
    const CloudPoints p = cloud_points(msg, m.topic);
    EXPECT_EQ(p.points.size() + p.dropped_not_finite,
              static_cast<std::size_t>(msg.width) * msg.height);
    EXPECT_EQ(p.time_field, "time_sec+time_nsec");
    EXPECT_EQ(p.times.size(), p.points.size());
    if (p.times.size() != p.points.size()) return false;
    double lo = 1e9, hi = -1e9, rmin = 1e9, rmax = 0.0;
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      lo = std::min(lo, p.times[i]);
      hi = std::max(hi, p.times[i]);
      rmin = std::min(rmin, p.points[i].norm());
      rmax = std::max(rmax, p.points[i].norm());
    }
    // One sweep: every point within a tenth of a second of the stamp, ranges as the README says.
    EXPECT_GT(lo, -0.2);
    EXPECT_LT(hi, 0.2);
    EXPECT_LT(hi - lo, 0.2);
    EXPECT_GT(hi - lo, 1e-3);  // the times do vary across the sweep
    EXPECT_GT(rmin, 6.0);
    EXPECT_LT(rmax, 260.0);
    ++clouds;
    return true;
  });
  EXPECT_EQ(clouds, 5);
}

}  // namespace
}  // namespace vdtnav::ros
