#include "vdtnav/io/tum_trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.hpp"

namespace vdtnav {
namespace {

using test::lines_of;
using test::tmp_dir;
using test::write_file;

namespace fs = std::filesystem;

const std::string kIntelTable =
    std::string(VDTNAV_DATA_DIR) + "/intel-lab/intel_910_odom_vs_corrected.txt";

std::vector<double> numbers(const std::string& line) {
  std::istringstream s(line);
  return {std::istream_iterator<double>(s), std::istream_iterator<double>()};
}

std::string message_of(const std::string& path) {
  try {
    (void)load_tum_trajectory(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

Pose3 random_pose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  q.normalize();
  Pose3 p = Pose3::Identity();
  p.linear() = q.toRotationMatrix();
  p.translation() = Eigen::Vector3d(100.0 * u(rng), u(rng) * 1e-9, 3.0 * u(rng));
  return p;
}

TEST(TumTrajectory, SaveLoadRoundTrip) {
  const std::string dir = tmp_dir("tum_trajectory");
  std::mt19937_64 rng(5);
  std::vector<StampedPose3> poses;
  for (int k = 0; k < 300; ++k) {
    poses.push_back({1305031102.175304 + 0.0333 * k + 1e-7 * (k % 7), random_pose(rng)});
  }
  poses.push_back({0.0, Pose3::Identity()});
  Pose3 half_turn = Pose3::Identity();  // qw = 0: the sign convention must not break it
  half_turn.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  poses.push_back({1e-9, half_turn});
  const std::string path = dir + "/round.tum";
  save_tum_trajectory(path, poses);
  const TumTrajectory back = load_tum_trajectory(path);
  EXPECT_TRUE(back.malformed_lines.empty());
  ASSERT_EQ(back.poses.size(), poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(back.poses[k].t, poses[k].t);
    EXPECT_EQ(back.poses[k].pose.translation(), poses[k].pose.translation());
    // matrix -> quaternion -> matrix: a few ulps
    EXPECT_LT((back.poses[k].pose.linear() - poses[k].pose.linear()).cwiseAbs().maxCoeff(), 4e-15);
    EXPECT_EQ(back.poses[k].pose.matrix().row(3), Eigen::RowVector4d(0, 0, 0, 1));
  }
  // Independent read of the text: 8 numbers, a unit quaternion with qw >= 0, the exact time.
  const std::vector<std::string> lines = lines_of(path);
  ASSERT_EQ(lines.size(), poses.size());
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::vector<double> v = numbers(lines[k]);
    ASSERT_EQ(v.size(), 8U) << lines[k];
    EXPECT_EQ(v[0], poses[k].t);
    EXPECT_NEAR(std::hypot(std::hypot(v[4], v[5]), std::hypot(v[6], v[7])), 1.0, 1e-15);
    EXPECT_GE(v[7], 0.0);
    const Eigen::Matrix3d r = Eigen::Quaterniond(v[7], v[4], v[5], v[6]).toRotationMatrix();
    EXPECT_LT((r - poses[k].pose.linear()).cwiseAbs().maxCoeff(), 4e-15);
  }
  EXPECT_EQ(lines[0].substr(0, 18), "1305031102.175304 ");
}

TEST(TumTrajectory, PlanarConveniences) {
  for (const double yaw : {0.0, 0.3, -2.0, kPi, 3.0}) {
    SCOPED_TRACE(yaw);
    const Pose2 p(1.25, -3.5, yaw);
    const Pose3 p3 = pose3_from_pose2(p);
    EXPECT_EQ(p3.translation(), Eigen::Vector3d(1.25, -3.5, 0.0));
    // Independent oracle: the rotation about z by yaw, written out.
    Eigen::Matrix3d rz;
    rz << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
    EXPECT_LT((p3.linear() - rz).cwiseAbs().maxCoeff(), 1e-15);
    const Pose2 back = pose2_from_pose3(p3);
    EXPECT_EQ(back.head<2>(), p.head<2>());
    EXPECT_NEAR(wrap_angle(back[2] - yaw), 0.0, 1e-15);
    // The TUM line: z = 0, quaternion (0, 0, sin(yaw/2), cos(yaw/2)) up to the sign (qw >= 0).
    const std::vector<double> v = numbers(tum_line(12.5, p));
    ASSERT_EQ(v.size(), 8U);
    EXPECT_EQ(v[0], 12.5);
    EXPECT_EQ(v[1], 1.25);
    EXPECT_EQ(v[2], -3.5);
    EXPECT_EQ(v[3], 0.0);
    EXPECT_EQ(v[4], 0.0);
    EXPECT_EQ(v[5], 0.0);
    const double s = std::cos(yaw / 2) < 0.0 ? -1.0 : 1.0;
    EXPECT_NEAR(v[6], s * std::sin(yaw / 2), 1e-16);
    EXPECT_NEAR(v[7], s * std::cos(yaw / 2), 1e-16);
    // The 2D line and the 3D line of the same pose read back as the same pose.
    EXPECT_LT(std::abs(wrap_angle(2.0 * std::atan2(v[6], v[7]) - yaw)), 1e-15);
  }
  EXPECT_THROW((void)tum_line(std::nan(""), Pose2::Zero()), ConfigError);
  EXPECT_THROW((void)tum_line(0.0, Pose2(0.0, INFINITY, 0.0)), ConfigError);
}

TEST(TumTrajectory, IntelCorrectedTrajectoryKeepsAbsoluteTimes) {
  if (!fs::exists(kIntelTable)) GTEST_SKIP() << "real data not found at " << kIntelTable;
  const std::string dir = tmp_dir("tum_trajectory");
  std::vector<StampedPose3> poses;
  std::vector<Pose2> planar;
  std::ifstream in(kIntelTable);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::vector<double> v = numbers(line);
    ASSERT_EQ(v.size(), 8U);
    planar.emplace_back(v[5], v[6], v[7]);
    poses.push_back({v[0], pose3_from_pose2(planar.back())});
  }
  ASSERT_EQ(poses.size(), 910U);
  const std::string path = dir + "/intel_corrected.tum";
  save_tum_trajectory(path, poses);
  const TumTrajectory back = load_tum_trajectory(path);
  ASSERT_EQ(back.poses.size(), 910U);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    EXPECT_EQ(back.poses[k].t, poses[k].t);  // 976052890.244111 etc., to the last bit
    const Pose2 p = pose2_from_pose3(back.poses[k].pose);
    EXPECT_EQ(p.head<2>(), planar[k].head<2>());
    EXPECT_NEAR(wrap_angle(p[2] - planar[k][2]), 0.0, 1e-15);
    EXPECT_EQ(back.poses[k].pose.translation().z(), 0.0);
  }
  EXPECT_EQ(lines_of(path)[0].substr(0, 17), "976052890.244111 ");
}

TEST(TumTrajectory, QuaternionNormAndMalformedLines) {
  const std::string dir = tmp_dir("tum_trajectory");
  // |q| = 1.0005: within 1e-3, normalised.
  const std::string ok = dir + "/ok.tum";
  write_file(ok,
             "# timestamp tx ty tz qx qy qz qw\n\n1.5 1 2 3 0 0 0 1.0005\r\n"
             "2.5\t1 2 3 0 0 0.70746 0.70746\n");
  const TumTrajectory t = load_tum_trajectory(ok);
  ASSERT_EQ(t.poses.size(), 2U);
  EXPECT_EQ(t.poses[0].t, 1.5);
  EXPECT_LT((t.poses[0].pose.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  Eigen::Matrix3d rz90;
  rz90 << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((t.poses[1].pose.linear() - rz90).cwiseAbs().maxCoeff(), 1e-15);

  struct Case {
    const char* name;
    const char* line;
    const char* what;
  };
  const Case cases[] = {
      {"long_q", "3 1 2 3 0 0 0 1.0011",
       "expected a unit quaternion qx qy qz qw (norm 1 within 1e-3), got norm 1.0011"},
      {"zero_q", "3 1 2 3 0 0 0 0",
       "expected a unit quaternion qx qy qz qw (norm 1 within 1e-3), "
       "got norm 0"},
      {"few", "3 1 2 3 0 0 1", "expected 8 fields (t x y z qx qy qz qw), found 7"},
      {"many", "3 1 2 3 0 0 0 1 0", "expected 8 fields (t x y z qx qy qz qw), found more than 8"},
      {"word", "3 1 2 3 0 0 0 one", "qw: expected a finite number, got 'one'"},
      {"inf", "inf 1 2 3 0 0 0 1", "t: expected a finite number, got 'inf'"},
  };
  const std::string good = "1.0 0 0 0 0 0 0 1\n";
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".tum";
    write_file(path, "# header\n" + good + good + c.line + "\n" + good);
    EXPECT_EQ(message_of(path), path + ":4: " + c.what);
    TumOptions o;
    o.skip_malformed = true;
    const TumTrajectory file = load_tum_trajectory(path, o);
    EXPECT_EQ(file.malformed_lines, std::vector<std::size_t>{4});
    EXPECT_EQ(file.poses.size(), 3U);
  }
  EXPECT_THROW((void)load_tum_trajectory(dir + "/missing.tum"), IoError);
}

}  // namespace
}  // namespace vdtnav
