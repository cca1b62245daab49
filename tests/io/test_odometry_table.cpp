// The Intel lab converter behind `vdtnav join-odometry`: the table reader (file:line for a bad
// row) and the join on log time: raw and corrected logs stamped with the absolute time, sorted by
// it, scans without a row counted, and a table that belongs to another log refused.
#include "vdtnav/io/odometry_table.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_files.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

CarmenLaser laser(double t, const Pose2& pose, std::size_t line) {
  CarmenLaser l;
  l.time = l.ipc_time = l.scan.time = t;
  l.pose = l.odom = pose;
  l.line = line;
  l.scan.ranges = {1.0, 2.0, 3.0};
  return l;
}

/// Lasers at log times 12, 10, 11 (out of order, as four scans of the Intel log are) and 13.
CarmenLog corrected_log() {
  CarmenLog log;
  log.lasers = {laser(12.0, Pose2(2.0, 0.0, 0.2), 1), laser(10.0, Pose2(0.0, 0.0, 0.0), 2),
                laser(11.0, Pose2(1.0, 0.0, 0.1), 3), laser(13.0, Pose2(3.0, 0.0, 0.3), 4)};
  return log;
}

/// Rows for log times 10, 11, 12 (not 13), 1000 s later, log times off by up to 3 ms.
std::vector<OdometryTableRow> table() {
  return {{1010.0, 10.003, Pose2(0.1, 0.0, 0.0), Pose2(0.0, 0.0, 0.0), 3},
          {1011.0, 10.998, Pose2(1.2, 0.1, 0.15), Pose2(1.0, 0.0, 0.1), 4},
          {1012.0, 12.0, Pose2(2.3, 0.2, 0.25), Pose2(2.0, 0.0, 0.2), 5}};
}

TEST(JoinOdometryTable, StampsBothLogsWithTheAbsoluteTime) {
  const JoinedLogs j = join_odometry_table(corrected_log(), table(), "t.txt");
  EXPECT_EQ(j.unmatched_scans, 1u);  // the scan at 13
  ASSERT_EQ(j.raw.lasers.size(), 3u);
  ASSERT_EQ(j.corrected.lasers.size(), 3u);
  const std::vector<OdometryTableRow> rows = table();
  for (std::size_t k = 0; k < 3; ++k) {  // sorted by absolute time
    for (const CarmenLog* log : {&j.raw, &j.corrected}) {
      const CarmenLaser& l = log->lasers[k];
      EXPECT_EQ(l.time, rows[k].abs_time);
      EXPECT_EQ(l.ipc_time, rows[k].abs_time);
      EXPECT_EQ(l.scan.time, rows[k].abs_time);
      EXPECT_EQ(l.scan.ranges, std::vector<double>({1.0, 2.0, 3.0}));
    }
    EXPECT_EQ(j.raw.lasers[k].pose, rows[k].raw);
    EXPECT_EQ(j.raw.lasers[k].odom, rows[k].raw);
    EXPECT_EQ(j.corrected.lasers[k].pose, rows[k].corrected);
    EXPECT_EQ(j.corrected.lasers[k].odom, rows[k].corrected);
  }
  EXPECT_EQ(j.raw.lasers[0].line, 2u);  // the scan at log time 10 was line 2
}

TEST(JoinOdometryTable, RefusesATableOfAnotherLog) {
  std::vector<OdometryTableRow> rows = table();
  rows[1].corrected[0] += 0.002;  // 2 mm off the log's corrected pose
  try {
    (void)join_odometry_table(corrected_log(), rows, "t.txt");
    FAIL() << "no FormatError";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.file(), "t.txt");
    EXPECT_EQ(e.line(), 4u);
    EXPECT_NE(std::string(e.what()).find("t.txt:4: the corrected pose differs from the log's at "
                                         "line 3"),
              std::string::npos)
        << e.what();
  }
  rows = table();
  for (auto& r : rows) r.log_time += 0.01;  // beyond the 5 ms tolerance: nothing matches
  EXPECT_THROW((void)join_odometry_table(corrected_log(), rows, "t.txt"), ConfigError);
  EXPECT_EQ(join_odometry_table(corrected_log(), rows, "t.txt", 0.02).raw.lasers.size(), 3u);
}

TEST(LoadOdometryTable, ReadsRowsAndNamesTheBadLine) {
  const std::string dir = test::tmp_dir("io");
  test::write_file(dir + "/t.txt",
                   "# abs log raw corrected\n"
                   "1010.5 10.25 0.1 0.2 0.3 1 2 3\n"
                   "\n"
                   "1011 11 0 0 0 0 0 -1.5\n");
  const std::vector<OdometryTableRow> rows = load_odometry_table(dir + "/t.txt");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].abs_time, 1010.5);
  EXPECT_EQ(rows[0].log_time, 10.25);
  EXPECT_EQ(rows[0].raw, Pose2(0.1, 0.2, 0.3));
  EXPECT_EQ(rows[0].corrected, Pose2(1.0, 2.0, 3.0));
  EXPECT_EQ(rows[0].line, 2u);
  EXPECT_EQ(rows[1].line, 4u);

  const auto message = [&](const std::string& text) {
    test::write_file(dir + "/bad.txt", text);
    try {
      (void)load_odometry_table(dir + "/bad.txt");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("1 2 3 4 5 6 7 8\n1 2 3 4 5 6 7\n").find("bad.txt:2: expected 8 numbers"),
            std::string::npos);
  EXPECT_NE(message("1 2 3 4 5 6 7 8 9\n").find("bad.txt:1: expected 8 numbers"),
            std::string::npos);
  EXPECT_NE(message("# only a comment\n").find("expected at least one row"), std::string::npos);
  EXPECT_NE(message("1 2 3 4 5 6 7 x\n").find("bad.txt:1: expected 8 numbers"), std::string::npos);
  EXPECT_THROW((void)load_odometry_table(dir + "/missing.txt"), IoError);
}

}  // namespace
}  // namespace vdtnav
