// The CLI's text options: 2D poses are three finite numbers with the yaw wrapped; standard
// deviations are three finite non-negative numbers and are never wrapped; a bad text names the
// option, echoes the text and says what was expected. 3D poses: six numbers or a 4x4 file.
#include "parse.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::tools {
namespace {

/// The message of the ConfigError that `f` throws ("" if it throws none).
template <class F>
std::string config_error(F f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ParsePose, ReadsThreeNumbersAndWrapsTheYaw) {
  EXPECT_TRUE(parse_pose("1.5,-2,0.25", "--init").isApprox(Pose2(1.5, -2.0, 0.25)));
  EXPECT_TRUE(parse_pose(" 1 , 2 ,3 ", "--init").isApprox(Pose2(1.0, 2.0, 3.0)));
  EXPECT_NEAR(parse_pose("0,0,7", "--init")[2], 7.0 - 2.0 * kPi, 1e-12);
  EXPECT_NEAR(parse_pose("0,0,-4", "--init")[2], -4.0 + 2.0 * kPi, 1e-12);
}

TEST(ParsePose, RejectsMalformedTextNamingTheOption) {
  for (const std::string bad :
       {"", "1,2", "1,2,3,4", "1;2;3", "1,,3", "a,2,3", "1,2,3x", "1,2,nan", "1,inf,3", "1,2,3,"}) {
    const std::string msg = config_error([&] { (void)parse_pose(bad, "--init"); });
    EXPECT_NE(msg.find("--init: expected x,y,yaw"), std::string::npos)
        << "'" << bad << "': " << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

TEST(ParseSigmas, KeepsTheYawSigmaUnwrapped) {
  // Through parse_pose a yaw sigma of 2 pi became 0 (and 4 a negative number).
  const Eigen::Vector3d s = parse_sigmas("0.1,0.2,6.283185307179586", "--init-sigma");
  EXPECT_DOUBLE_EQ(s[0], 0.1);
  EXPECT_DOUBLE_EQ(s[1], 0.2);
  EXPECT_DOUBLE_EQ(s[2], 2.0 * kPi);
  EXPECT_DOUBLE_EQ(parse_sigmas("0,0,4", "--init-sigma")[2], 4.0);
  EXPECT_TRUE(parse_sigmas("0,0,0", "--init-sigma").isZero(0.0));
}

TEST(ParseSigmas, RejectsNegativeNonFiniteAndMalformed) {
  for (const std::string bad : {"0.1,-0.1,0.05", "-0.1,0.1,0.05", "0.1,0.1,-1e-9", "0.1,0.1,inf",
                                "nan,0.1,0.1", "0.1,0.1", "0.1,0.1,0.1,0.1", "x,0.1,0.1"}) {
    const std::string msg = config_error([&] { (void)parse_sigmas(bad, "--init-sigma"); });
    EXPECT_NE(msg.find("--init-sigma: expected three standard deviations sx,sy,syaw, finite and "
                       ">= 0"),
              std::string::npos)
        << "'" << bad << "': " << msg;
    EXPECT_NE(msg.find("'" + bad + "'"), std::string::npos) << msg;
  }
}

TEST(ParsePose3, ReadsXyzRollPitchYawAsRzRyRx) {
  const Pose3 p = parse_pose3("1,-2,0.5,0.1,-0.2,3", "--init");
  EXPECT_TRUE(p.translation().isApprox(Eigen::Vector3d(1, -2, 0.5)));
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(3, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  EXPECT_LT((p.linear() - r).norm(), 1e-15);
  for (const std::string bad : {"1,2,3,4,5", "1,2,3,4,5,6,7", "1,2,3,4,5,nan", "1,2,3,x,5,6", ""}) {
    const std::string msg = config_error([&] { (void)parse_pose3(bad, "--init"); });
    EXPECT_NE(msg.find("--init: expected x,y,z,roll,pitch,yaw"), std::string::npos) << msg;
  }
}

std::string matrix_file(const std::string& name, const std::string& text) {
  const std::filesystem::path dir = std::filesystem::path(VDTNAV_TEST_TMP) / "parse";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

TEST(ReadPoseMatrix, ReadsSixteenNumbersRowByRow) {
  // libpointmatcher's reference pose of car_cloud401 (carCloudList.csv), with brackets and commas.
  const Pose3 p = read_pose_matrix(
      matrix_file("ok.txt",
                  "# T_map_scan\n[0.981715, 0.169605, -0.0864239, 0.0614127]\n"
                  "-0.152902 0.973034 0.172703 0.191433\n0.113385 -0.15633 0.981175 -0.0338571\n"
                  "0 0 0 1\n"));
  EXPECT_TRUE(p.translation().isApprox(Eigen::Vector3d(0.0614127, 0.191433, -0.0338571)));
  EXPECT_NEAR(p(0, 1), 0.169605, 1e-5);  // made exactly a rotation, within the file's 6 digits
  EXPECT_LT((p.linear().transpose() * p.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

TEST(ReadPoseMatrix, RefusesWhatIsNotARigidTransformNamingTheFile) {
  const auto error_of = [](const std::string& path) {
    try {
      (void)read_pose_matrix(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string few = matrix_file("few.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  EXPECT_EQ(error_of(few), few + ":3: expected 16 numbers (a 4x4 matrix, row by row), found 12");
  const std::string word = matrix_file("word.txt", "1 0 0 0\n0 one 0 0\n");
  EXPECT_NE(error_of(word).find(word + ":2: expected 16 finite numbers"), std::string::npos);
  const std::string scaled = matrix_file("scaled.txt", "2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1");
  EXPECT_NE(error_of(scaled).find("expected a rotation"), std::string::npos);
  const std::string mirror = matrix_file("mirror.txt", "-1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");
  EXPECT_NE(error_of(mirror).find("det R = +1"), std::string::npos);
  const std::string row = matrix_file("row.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1");
  EXPECT_NE(error_of(row).find("last row 0 0 0 1"), std::string::npos);
  EXPECT_THROW((void)read_pose_matrix(matrix_file("", "") + "/missing.txt"), IoError);
}

}  // namespace
}  // namespace vdtnav::tools
