// A mapping run on disk (io/scan_run.hpp): KITTI and TUM pose files read back against the
// poses written, each cloud given its own pose (by order or by the stamp in its name), the scan
// selection map3d's --every/--skip-odd/--skip-even use, and the errors a user needs.
#include "vdtnav/io/scan_run.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.hpp"

namespace vdtnav {
namespace {

using test::tmp_dir;
using test::write_file;

namespace fs = std::filesystem;

/// The KITTI line of a pose, 9 significant digits (as the benchmark's files are written).
std::string kitti_line(const Pose3& p) {
  std::ostringstream s;
  s.precision(9);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) s << (r + c ? " " : "") << p.matrix()(r, c);
  return s.str() + "\n";
}

template <typename Error, typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(ScanRun, KittiPosesReadBackAsWrittenAndMapPointsTheWayTheyDo) {
  const std::string dir = tmp_dir("scan_run");
  const std::vector<Pose3> truth = {pose3_from_xyz_rpy(0, 0, 0, 0, 0, 0),
                                    pose3_from_xyz_rpy(1.5, -2.25, 0.5, 0.1, -0.2, 2.9),
                                    pose3_from_xyz_rpy(-30.0, 12.0, -1.0, -0.4, 0.3, -1.2)};
  std::string text = "# a comment\n\n";
  for (const Pose3& p : truth) text += kitti_line(p);
  write_file(dir + "/poses.txt", text);
  const ScanPoseFile file = load_scan_poses(dir + "/poses.txt");
  EXPECT_EQ(file.format, ScanPoseFormat::kKitti);
  ASSERT_EQ(file.poses.size(), truth.size());
  const Eigen::Vector3d p(2.0, -1.0, 0.7);  // a point of the cloud, in its own frame
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT((file.poses[k].pose * p - truth[k] * p).norm(), 1e-7) << k;
    EXPECT_LT((file.poses[k].pose.linear().transpose() * file.poses[k].pose.linear() -
               Eigen::Matrix3d::Identity())
                  .norm(),
              1e-12);
  }
}

TEST(ScanRun, AKittiLineThatIsNotARotationOrNotTwelveNumbersSaysWhere) {
  const std::string dir = tmp_dir("scan_run");
  write_file(dir + "/scaled.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_poses(dir + "/scaled.txt");
            }).find("scaled.txt:2: expected a rotation"),
            std::string::npos);
  write_file(dir + "/short.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_poses(dir + "/short.txt");
            }).find("short.txt:2: expected 12 fields"),
            std::string::npos);
  write_file(dir + "/neither.txt", "# poses\n1 2 3 4 5\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_poses(dir + "/neither.txt");
            }).find("neither.txt:2: expected a pose: 12 numbers (KITTI"),
            std::string::npos);
}

TEST(ScanRun, ScanTimesReadAsKittisTimesTxtAndSayWhereALineIsWrong) {
  const std::string dir = tmp_dir("scan_run");
  write_file(dir + "/times.txt", "# stamps\n0.000000e+00\n1.038500e-01\n\n2.074000e-01\n");
  const std::vector<double> t = load_scan_times(dir + "/times.txt");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0], 0.0);
  EXPECT_EQ(t[1], 0.10385);
  EXPECT_EQ(t[2], 0.2074);
  write_file(dir + "/two.txt", "0.0\n0.1 0.2\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_times(dir + "/two.txt");
            }).find("two.txt:2: expected 1 fields (t)"),
            std::string::npos);
  write_file(dir + "/back.txt", "0.0\n0.2\n0.1\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_times(dir + "/back.txt");
            }).find("back.txt:3: expected a stamp after the line before's"),
            std::string::npos);
  write_file(dir + "/nan.txt", "0.0\nnan\n");
  EXPECT_NE(error_of<FormatError>([&] {
              (void)load_scan_times(dir + "/nan.txt");
            }).find("nan.txt:2: t: expected a finite number"),
            std::string::npos);
}

TEST(ScanRun, KittiPosesGoToTheCloudsInNameOrderAndMustCountThem) {
  const std::string dir = tmp_dir("scan_run");
  fs::create_directories(dir + "/run");
  for (const char* name : {"000002.pcd", "000000.pcd", "000001.pcd", "notes.md"})
    write_file(dir + "/run/" + name, "");
  const std::vector<std::string> clouds = point_cloud_files_in(dir + "/run");
  ASSERT_EQ(clouds.size(), 3u);  // notes.md is not a cloud
  EXPECT_EQ(fs::path(clouds[0]).filename(), "000000.pcd");
  EXPECT_EQ(fs::path(clouds[2]).filename(), "000002.pcd");
  std::string text;
  for (int k = 0; k < 3; ++k) text += kitti_line(pose3_from_xyz_rpy(k, 0, 0, 0, 0, 0));
  write_file(dir + "/poses.txt", text);
  const std::vector<Pose3> poses = poses_of_scans(load_scan_poses(dir + "/poses.txt"), clouds);
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(poses[k].translation().x(), k);
  write_file(dir + "/two.txt", text.substr(0, text.rfind('\n', text.size() - 2) + 1));
  EXPECT_NE(error_of<ConfigError>([&] {
              (void)poses_of_scans(load_scan_poses(dir + "/two.txt"), clouds);
            }).find("2 KITTI poses for 3 clouds"),
            std::string::npos);
}

TEST(ScanRun, TumPosesGoToTheCloudWhoseNameIsTheNearestStampWithinTheTolerance) {
  const std::string dir = tmp_dir("scan_run");
  // Poses every 0.1 s, out of order in the file; clouds stamped a few ms off them.
  write_file(dir + "/poses.tum",
             "100.2 2 0 0 0 0 0 1\n100.0 0 0 0 0 0 0 1\n100.1 1 0 0 0 0 0 1\n"
             "100.3 3 0 0 0 0 0 1\n");
  const ScanPoseFile file = load_scan_poses(dir + "/poses.tum");
  EXPECT_EQ(file.format, ScanPoseFormat::kTum);
  const std::vector<std::string> clouds = {dir + "/100.004.pcd", dir + "/100.196.pcd",
                                           dir + "/100.302.pcd"};
  const std::vector<Pose3> poses = poses_of_scans(file, clouds, 0.01);
  EXPECT_DOUBLE_EQ(poses[0].translation().x(), 0.0);
  EXPECT_DOUBLE_EQ(poses[1].translation().x(), 2.0);
  EXPECT_DOUBLE_EQ(poses[2].translation().x(), 3.0);
  // 100.15 is 0.05 s from both neighbours: refused at 10 ms, with the offset said.
  const std::string far =
      error_of<ConfigError>([&] { (void)poses_of_scans(file, {dir + "/100.15.pcd"}, 0.01); });
  EXPECT_NE(far.find("100.15.pcd: no pose of"), std::string::npos) << far;
  EXPECT_NE(far.find("0.05"), std::string::npos) << far;
  EXPECT_NE(error_of<ConfigError>([&] {
              (void)poses_of_scans(file, {dir + "/scan_a.pcd"});
            }).find("this name is not a number"),
            std::string::npos);
}

TEST(ScanRun, TheSelectionKeepsEveryNthAndOneParityCountedFromZero) {
  using V = std::vector<std::size_t>;
  EXPECT_EQ(select_scans(7, {}), (V{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(select_scans(7, {3, false, false}), (V{0, 3, 6}));
  EXPECT_EQ(select_scans(7, {1, true, false}), (V{0, 2, 4, 6}));
  EXPECT_EQ(select_scans(7, {1, false, true}), (V{1, 3, 5}));
  EXPECT_EQ(select_scans(7, {3, false, true}), (V{3}));
  EXPECT_THROW((void)select_scans(7, {2, false, true}), ConfigError);  // odd multiples of 2: none
  EXPECT_THROW((void)select_scans(7, {1, true, true}), ConfigError);
  EXPECT_THROW((void)select_scans(7, {0, false, false}), ConfigError);
}

TEST(ScanRun, ANameIsAStampOnlyWhenItsWholeStemIsANumber) {
  EXPECT_DOUBLE_EQ(stamp_of_name("/a/1317357625.557814.pcd").value(), 1317357625.557814);
  EXPECT_DOUBLE_EQ(stamp_of_name("000042.bin.pcd").value_or(-1), -1);  // stem "000042.bin"
  EXPECT_DOUBLE_EQ(stamp_of_name("000042.pcd").value(), 42.0);
  EXPECT_FALSE(stamp_of_name("scan_7.pcd").has_value());
  EXPECT_FALSE(stamp_of_name("nan.pcd").has_value());
}

}  // namespace
}  // namespace vdtnav
