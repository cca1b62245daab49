// read_point_cloud in every format it accepts, against the points written, and its errors (file,
// line, what was expected); the real libpointmatcher files when the data is there.
#include "vdtnav/pcl/point_cloud_file.hpp"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;

std::string tmp_file(const std::string& name, const std::string& text) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(VDTNAV_TEST_TMP) / "point_cloud_file" / test->name();
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

void expect_points(const pcl::PointCloud<pcl::PointXYZ>& c,
                   const std::vector<Eigen::Vector3f>& expected) {
  ASSERT_EQ(c.size(), expected.size());
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i].getVector3fMap(), expected[i]) << i;
}

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(PointCloudFile, ReadsTextWithAndWithoutAHeader) {
  const std::vector<Eigen::Vector3f> pts = {{1.5f, -2.0f, 0.25f}, {3.0f, 4.0f, -5.0f}};
  // libpointmatcher's car_cloud400.csv: a header, columns with spaces around the commas.
  expect_points(read_point_cloud(tmp_file("a.csv",
                                          "x,y,z,nx,ny,nz\n1.5 , -2 , 0.25 , 0,0,1\n"
                                          "3,4,-5,1,0,0\r\n")),
                pts);
  // The columns named by the header, in any order.
  expect_points(read_point_cloud(tmp_file("b.csv",
                                          "# exported\nintensity;z;y;x\n"
                                          "7;0.25;-2;1.5\n\n9;-5;4;3\n")),
                pts);
  // car_cloud401.csv: no header, blanks.
  expect_points(read_point_cloud(tmp_file("c.xyz", "   1.5e0  -2.0 0.25\n\t3 4 -5 99\n")), pts);
}

TEST(PointCloudFile, ReadsTheLegacyAsciiVtkPointsSection) {
  const std::string vtk =
      "# vtk DataFile Version 3.0\ndata\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n"
      "1.5 -2 0.25\n3 4\n-5\nVERTICES 2 4\n1 0\n1 1\n";
  expect_points(read_point_cloud(tmp_file("a.vtk", vtk)), {{1.5f, -2.0f, 0.25f}, {3, 4, -5}});
}

TEST(PointCloudFile, KeepsAPcdViewpointAsTheSensorOrigin) {
  pcl::PointCloud<pcl::PointXYZ> c;
  c.push_back(pcl::PointXYZ(1, 2, 3));
  c.sensor_origin_ = Eigen::Vector4f(0.5f, -1.0f, 2.0f, 0.0f);
  const std::string path = tmp_file("a.pcd", "");
  ASSERT_EQ(pcl::io::savePCDFileBinary(path, c), 0);
  const pcl::PointCloud<pcl::PointXYZ> r = read_point_cloud(path);
  expect_points(r, {{1, 2, 3}});
  EXPECT_EQ(r.sensor_origin_.head<3>(), Eigen::Vector3f(0.5f, -1.0f, 2.0f));
}

TEST(PointCloudFile, ReadsEachPointsTimeAsTheDriversWriteIt) {
  // Ouster: `t`, uint32 nanoseconds after the stamp (binary PCD, the field after x y z).
  const std::string ouster =
      tmp_file("ouster.pcd",
               "VERSION 0.7\nFIELDS x y z t\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 3\n"
               "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 0 0 0\n0 1 0 50000000\n"
               "0 0 1 99999999\n");
  PointTimes t;
  expect_points(read_point_cloud(ouster, &t), {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  EXPECT_EQ(t.field, "t");
  EXPECT_FALSE(t.absolute);
  ASSERT_EQ(t.seconds.size(), 3u);
  EXPECT_DOUBLE_EQ(t.seconds[1], 0.05);
  EXPECT_DOUBLE_EQ(t.seconds[2], 0.099999999);
  // Velodyne as text: a `time` column in seconds (may be negative: before the stamp).
  (void)read_point_cloud(
      tmp_file("velodyne.csv", "x,y,z,intensity,time\n1,2,3,7,-0.0125\n4,5,6,9,0\n"), &t);
  EXPECT_EQ(t.field, "time");
  EXPECT_EQ(t.seconds, (std::vector<double>{-0.0125, 0.0}));
  // Livox: `timestamp`, absolute nanoseconds in a float64.
  (void)read_point_cloud(
      tmp_file("livox.pcd",
               "VERSION 0.7\nFIELDS x y z timestamp\nSIZE 4 4 4 8\nTYPE F F F F\n"
               "COUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n"
               "1 0 0 1700000000000000000\n0 1 0 1700000000050000000\n"),
      &t);
  EXPECT_EQ(t.field, "timestamp");
  EXPECT_TRUE(t.absolute);
  ASSERT_EQ(t.seconds.size(), 2u);
  EXPECT_NEAR(t.seconds[1] - t.seconds[0], 0.05, 1e-6);
  EXPECT_NEAR(t.seconds[0], 1.7e9, 1.0);
  // No time field: empty.
  (void)read_point_cloud(tmp_file("none.xyz", "1 2 3\n"), &t);
  EXPECT_TRUE(t.seconds.empty());
  EXPECT_EQ(t.field, "");
}

TEST(PointCloudFile, SaysWhichFileAndLineAndWhatWasExpected) {
  const std::string bad = tmp_file("bad.csv", "x,y,z\n1,2,3\n4,5\n");
  EXPECT_EQ(error_of([&] { (void)read_point_cloud(bad); }),
            bad +
                ":3: expected the numbers x y z in columns 1, 2, 3 (separated by commas or "
                "blanks)");
  const std::string header = tmp_file("h.csv", "a,b,c\n1,2,3\n");
  EXPECT_NE(
      error_of([&] { (void)read_point_cloud(header); }).find(header + ":1: expected a header"),
      std::string::npos);
  const std::string empty = tmp_file("e.txt", "# nothing\n");
  EXPECT_EQ(error_of([&] { (void)read_point_cloud(empty); }), empty + ": the cloud has no points");
  const std::string cut = tmp_file("cut.vtk",
                                   "# vtk DataFile Version 3.0\nd\nASCII\nDATASET POLYDATA\n"
                                   "POINTS 3 float\n1 2 3\n4 5\n");
  EXPECT_NE(error_of([&] { (void)read_point_cloud(cut); }).find("ends after 5 of the 9"),
            std::string::npos);
  const std::string binary = tmp_file("bin.vtk", "# vtk DataFile Version 3.0\nd\nBINARY\n");
  EXPECT_EQ(error_of([&] { (void)read_point_cloud(binary); }),
            binary + ":3: expected 'ASCII' (binary legacy VTK files are not supported)");
  const std::string unknown = tmp_file("a.las", "x");
  EXPECT_NE(error_of([&] { (void)read_point_cloud(unknown); }).find("unknown point cloud format"),
            std::string::npos);
  EXPECT_THROW((void)read_point_cloud(tmp_file("", "") + "/missing.pcd"), IoError);
}

TEST(PointCloudFile, AHeaderDeclaringMorePointsThanTheFileHoldsAllocatesNothingUpFront) {
  // A fuzzing finding: "POINTS 908204548" in a 140-byte VTK file reserved 22 GB. The input is the
  // fuzz target's (first byte: the format), kept in fuzz/regressions.
  std::ifstream in(std::string(VDTNAV_FUZZ_REGRESSIONS) + "/point_cloud-vtk-huge-count.fuzz",
                   std::ios::binary);
  ASSERT_TRUE(in);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes[0], 2);  // .vtk
  const std::string path = tmp_file("huge.vtk", bytes.substr(1));
  EXPECT_THROW((void)read_point_cloud(path), FormatError);
}

TEST(PointCloudFile, ReadsLibpointmatchersRealScans) {
  const std::string dir = std::string(VDTNAV_DATA_DIR) + "/3d/libpointmatcher/";
  if (!fs::exists(dir + "car_cloud401.csv")) GTEST_SKIP() << "no data at " << dir;
  EXPECT_EQ(read_point_cloud(dir + "car_cloud401.csv").size(), 25193u);  // the README's count
  EXPECT_EQ(read_point_cloud(dir + "cloud.00000.vtk").size(), 24989u);
  EXPECT_EQ(read_point_cloud(dir + "cloud.00002.vtk").size(), 24154u);
  const auto c400 = read_point_cloud(dir + "car_cloud400.csv");
  EXPECT_GT(c400.size(), 20000u);
  EXPECT_NEAR(c400[0].x, -3.5376f, 1e-6f);  // the first data line, after the header
}

}  // namespace
}  // namespace vdtnav
