// IMU CSV (io/imu_table.hpp): written and read back bit for bit, the header optional, comments
// and spaces, rows with NaN or inf dropped and counted, and file:line errors for a bad row, times
// not increasing and an unreadable file.
#include "vdtnav/io/imu_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "test_files.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

std::vector<ImuSample> random_samples(std::size_t n) {
  std::mt19937 rng(4);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<ImuSample> s;
  double t = 1700000000.123456;  // a Unix stamp: the digits a bag's times have
  for (std::size_t i = 0; i < n; ++i) {
    t += 0.005 + 1e-4 * normal(rng);
    s.push_back({t,
                 {0.3 * normal(rng), 0.3 * normal(rng), 1e-7 * normal(rng)},
                 {normal(rng), normal(rng), 9.80665 + 1e5 * normal(rng)}});
  }
  return s;
}

/// The FormatError's message from loading `path`, or "" if none.
std::string format_error(const std::string& path) {
  try {
    (void)load_imu_csv(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return {};
}

TEST(ImuTable, WrittenSamplesReadBackBitForBit) {
  const std::string path = test::tmp_dir("io") + "/imu.csv";
  const std::vector<ImuSample> samples = random_samples(300);
  save_imu_csv(path, samples);
  EXPECT_EQ(test::lines_of(path).front(), "t,wx,wy,wz,ax,ay,az");
  ImuCsvReport report;
  const std::vector<ImuSample> back = load_imu_csv(path, &report);
  EXPECT_TRUE(report.header);
  EXPECT_TRUE(report.non_finite_lines.empty());
  ASSERT_EQ(back.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(back[i].t, samples[i].t) << i;
    EXPECT_EQ(back[i].gyro, samples[i].gyro) << i;
    EXPECT_EQ(back[i].accel, samples[i].accel) << i;
  }
  std::vector<ImuSample> bad = samples;
  bad[3].accel.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(save_imu_csv(path, bad), ConfigError);
  bad = samples;
  bad[3].t = bad[2].t;
  EXPECT_THROW(save_imu_csv(path, bad), ConfigError);
}

TEST(ImuTable, TheHeaderIsOptionalAndCommentsAndSpacesAreAllowed) {
  const std::string dir = test::tmp_dir("io");
  const std::string rows =
      "0.0,0.1,0.2,0.3,0.4,0.5,9.8\n# a comment\n\n 0.005 , -0.1,0,0, 1e-3,+2,9.7\r\n";
  test::write_file(dir + "/bare.csv", rows);
  test::write_file(dir + "/header.csv", "# IMU\n t, wx,wy ,wz,ax,ay,az \n" + rows);
  for (const char* name : {"bare.csv", "header.csv"}) {
    ImuCsvReport report;
    const std::vector<ImuSample> s = load_imu_csv(dir + "/" + name, &report);
    EXPECT_EQ(report.header, std::string(name) == "header.csv");
    ASSERT_EQ(s.size(), 2u) << name;
    EXPECT_EQ(s[1].t, 0.005);
    EXPECT_EQ(s[0].gyro, Eigen::Vector3d(0.1, 0.2, 0.3));
    EXPECT_EQ(s[1].accel, Eigen::Vector3d(1e-3, 2.0, 9.7));
  }
}

TEST(ImuTable, NonFiniteRowsAreDroppedAndCounted) {
  const std::string path = test::tmp_dir("io") + "/nan.csv";
  test::write_file(path,
                   "t,wx,wy,wz,ax,ay,az\n1,0,0,0,0,0,9.8\n2,nan,0,0,0,0,9.8\n3,0,0,0,inf,0,9.8\n"
                   "nan,0,0,0,0,0,9.8\n4,0,0,0,0,0,9.8\n");
  ImuCsvReport report;
  const std::vector<ImuSample> s = load_imu_csv(path, &report);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].t, 4.0);
  EXPECT_EQ(report.non_finite_lines, (std::vector<std::size_t>{3, 4, 5}));
}

TEST(ImuTable, BadRowsAreNamedByFileAndLine) {
  const std::string dir = test::tmp_dir("io");
  const std::string good = "t,wx,wy,wz,ax,ay,az\n0,0,0,0,0,0,9.8\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0.1,0,0,0,0,9.8\n", ":3: expected 7 numbers t,wx,wy,wz,ax,ay,az, got '0.1,0,0,0,0,9.8'"},
      {"0.1,0,0,0,0,0,9.8,1\n", ":3: expected 7 numbers t,wx,wy,wz,ax,ay,az"},
      {"0.1,0,0,x,0,0,9.8\n", ":3: expected 7 numbers t,wx,wy,wz,ax,ay,az"},
      {"0.1 0 0 0 0 0 9.8\n", ":3: expected 7 numbers t,wx,wy,wz,ax,ay,az"},
      {"0.1,0,0,,0,0,9.8\n", ":3: expected 7 numbers t,wx,wy,wz,ax,ay,az"},
      {"0,0,0,0,0,0,9.8\n", ":3: expected times strictly increasing: 0 s after 0 s"},
      {"0.2,0,0,0,0,0,9.8\n0.1,0,0,0,0,0,9.8\n",
       ":4: expected times strictly increasing: 0.1 s after 0.2 s"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string path = dir + "/bad" + std::to_string(i) + ".csv";
    test::write_file(path, good + cases[i].first);
    const std::string what = format_error(path);
    EXPECT_EQ(what.rfind(path + cases[i].second, 0), 0u) << what;
  }
  // A misspelt header is a bad first row, and says so.
  test::write_file(dir + "/header.csv", "time,wx,wy,wz,ax,ay,az\n0,0,0,0,0,0,9.8\n");
  EXPECT_NE(format_error(dir + "/header.csv")
                .find(":1: expected 7 numbers t,wx,wy,wz,ax,ay,az "
                      "(or that header)"),
            std::string::npos);
  test::write_file(dir + "/empty.csv", "t,wx,wy,wz,ax,ay,az\n# nothing\n");
  EXPECT_NE(format_error(dir + "/empty.csv").find("expected at least one finite row"),
            std::string::npos);
  EXPECT_THROW((void)load_imu_csv(dir + "/missing.csv"), IoError);
}

}  // namespace
}  // namespace vdtnav
