// Pan-tilt CSV input: good files (any column order, optional time, comments), exact round trips of
// simulated sweeps, and corrupted files whose errors name the file, the line and what was expected
// (or are skipped and counted with skip_malformed).
#include "vdtnav/point_laser/pan_tilt_csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"
#include "vdtnav/sim/point_laser_simulator.hpp"

namespace vdtnav::point_laser {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  std::filesystem::create_directories(VDTNAV_TEST_TMP);
  const std::string path = std::string(VDTNAV_TEST_TMP) + "/" + name;
  std::ofstream(path) << text;
  return path;
}

/// The FormatError `read_pan_tilt_csv(path, options)` throws (fails the test if none).
FormatError format_error(const std::string& path, const PanTiltCsvOptions& options = {}) {
  try {
    (void)read_pan_tilt_csv(path, options);
  } catch (const FormatError& e) {
    return e;
  }
  ADD_FAILURE() << "no FormatError for " << path;
  return FormatError(path, 0, "none");
}

TEST(PanTiltCsv, ReadsAGoodFileWithTimeCommentsAndBlankLines) {
  const std::string path = write_file("good.csv",
                                      "# pan-tilt sweep\n"
                                      "pan,tilt,range,time\n"
                                      "0.1,-0.2,3.25,0.0\n"
                                      "\n"
                                      "  -1.5 , 0.75 , 12.5 , 0.002  # trailing comment\r\n"
                                      "3.0,0.0,inf,0.004\n");
  const PanTiltCsv csv = read_pan_tilt_csv(path);
  EXPECT_TRUE(csv.has_time);
  EXPECT_EQ(csv.skipped_malformed, 0u);
  ASSERT_EQ(csv.readings.size(), 3u);
  EXPECT_EQ(csv.readings[0].pan, 0.1);
  EXPECT_EQ(csv.readings[0].tilt, -0.2);
  EXPECT_EQ(csv.readings[0].range, 3.25);
  EXPECT_EQ(csv.readings[1].pan, -1.5);
  EXPECT_EQ(csv.readings[1].tilt, 0.75);
  EXPECT_EQ(csv.readings[1].range, 12.5);
  EXPECT_EQ(csv.readings[1].time, 0.002);
  EXPECT_TRUE(std::isinf(csv.readings[2].range));
  EXPECT_EQ(csv.readings[2].time, 0.004);
}

TEST(PanTiltCsv, ColumnsInAnyOrderAndTimeIsOptional) {
  const PanTiltCsv a = read_pan_tilt_csv(write_file("order.csv", "range,tilt,pan\n2,0.5,-1\n"));
  EXPECT_FALSE(a.has_time);
  ASSERT_EQ(a.readings.size(), 1u);
  EXPECT_EQ(a.readings[0].pan, -1.0);
  EXPECT_EQ(a.readings[0].tilt, 0.5);
  EXPECT_EQ(a.readings[0].range, 2.0);
  EXPECT_EQ(a.readings[0].time, 0.0);
  const PanTiltCsv b = read_pan_tilt_csv(write_file("header_only.csv", "pan,tilt,range\n"));
  EXPECT_TRUE(b.readings.empty());
}

TEST(PanTiltCsv, RoundTripsASimulatedSweepExactly) {
  // An empty 4 m cube so that the sweep has both returns and (upwards, open top) no-returns.
  OccupancyGrid<3> grid(Eigen::Vector3i(80, 80, 40),
                        GridFrame<3>(0.05, Eigen::Vector3d(-2.0, -2.0, -0.1)), 0);
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 80; ++i) grid(Eigen::Vector3i(i, j, 0)) = 1;
  sim::PointLaserSimOptions o;
  o.pattern.pan_steps = 20;
  const auto sweep =
      sim::simulate_point_laser_sweep(grid, pose3_from_xyz_rpy(0, 0, 0, 0.03, 0.02, 1.0), o, 2);
  for (bool with_time : {true, false}) {
    const std::string path = std::string(VDTNAV_TEST_TMP) + "/roundtrip.csv";
    std::filesystem::create_directories(VDTNAV_TEST_TMP);
    write_pan_tilt_csv(path, sweep.readings, with_time);
    const PanTiltCsv csv = read_pan_tilt_csv(path);
    EXPECT_EQ(csv.has_time, with_time);
    ASSERT_EQ(csv.readings.size(), sweep.readings.size());
    std::size_t inf = 0;
    for (std::size_t k = 0; k < csv.readings.size(); ++k) {
      EXPECT_EQ(csv.readings[k].pan, sweep.readings[k].pan);
      EXPECT_EQ(csv.readings[k].tilt, sweep.readings[k].tilt);
      EXPECT_EQ(csv.readings[k].range, sweep.readings[k].range);
      EXPECT_EQ(csv.readings[k].time, with_time ? sweep.readings[k].time : 0.0);
      inf += std::isinf(csv.readings[k].range);
    }
    EXPECT_GT(inf, 0u);
    // Through the file or directly: the same observation set.
    const auto direct = point_laser_observations(sweep.readings, o.calibration);
    const auto via_csv = point_laser_observations(csv.readings, o.calibration);
    EXPECT_EQ(via_csv.beam, direct.beam);
    EXPECT_TRUE(via_csv.points == direct.points);
    EXPECT_EQ(via_csv.dropped_not_finite, inf);
  }
}

TEST(PanTiltCsv, MalformedLinesNameFileLineAndWhatWasExpected) {
  const std::string text =
      "pan,tilt,range\n"    // 1
      "0.1,0.2,3.0\n"       // 2
      "0.1,0.2\n"           // 3: a field missing
      "0.3,0.4,5.0\n"       // 4
      "0.1,0.2,abc\n"       // 5: not a number
      "0.5,0.6,7.0,1.0\n";  // 6: one field too many
  const std::string path = write_file("corrupt.csv", text);
  const FormatError e = format_error(path);
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.line(), 3u);
  EXPECT_EQ(std::string(e.what()), path +
                                       ":3: expected 3 comma-separated numbers as in the header, "
                                       "got 2 fields in '0.1,0.2'");

  const std::string bad_number = write_file("bad_number.csv", "pan,tilt,range\n0.1,0.2,abc\n");
  const FormatError n = format_error(bad_number);
  EXPECT_EQ(n.line(), 2u);
  EXPECT_EQ(std::string(n.what()),
            bad_number + ":2: expected a number for range (metres), got 'abc' in '0.1,0.2,abc'");
  const FormatError empty_field =
      format_error(write_file("empty_field.csv", "time,pan,tilt,range\n0,,0.2,1\n"));
  EXPECT_EQ(empty_field.line(), 2u);
  EXPECT_NE(std::string(empty_field.what()).find("expected a number for pan (radians)"),
            std::string::npos);

  PanTiltCsvOptions skip;
  skip.skip_malformed = true;
  const PanTiltCsv csv = read_pan_tilt_csv(path, skip);
  EXPECT_EQ(csv.skipped_malformed, 3u);
  EXPECT_EQ(csv.skipped_lines, (std::vector<std::size_t>{3, 5, 6}));
  ASSERT_EQ(csv.readings.size(), 2u);
  EXPECT_EQ(csv.readings[0].range, 3.0);
  EXPECT_EQ(csv.readings[1].range, 5.0);
}

TEST(PanTiltCsv, AMissingOrBadHeaderAlwaysThrows) {
  PanTiltCsvOptions skip;
  skip.skip_malformed = true;
  const std::string unknown = write_file("unknown.csv", "# units: degrees\npan,tilt,distance\n");
  const FormatError u = format_error(unknown, skip);
  EXPECT_EQ(u.line(), 2u);
  EXPECT_EQ(std::string(u.what()),
            unknown +
                ":2: expected a header naming the columns pan,tilt,range and optionally time "
                "(each once), got 'pan,tilt,distance'");
  EXPECT_EQ(format_error(write_file("twice.csv", "pan,tilt,range,pan\n"), skip).line(), 1u);
  EXPECT_EQ(format_error(write_file("no_range.csv", "pan,tilt,time\n"), skip).line(), 1u);
  EXPECT_EQ(format_error(write_file("numbers.csv", "\n0.1,0.2,3.0\n"), skip).line(), 2u);
  const std::string empty = write_file("empty.csv", "# nothing\n\n");
  const FormatError none = format_error(empty, skip);
  EXPECT_EQ(none.line(), 0u);
  EXPECT_EQ(std::string(none.what()),
            empty +
                ": expected a header naming the columns pan,tilt,range and optionally time, "
                "found none");
}

TEST(PanTiltCsv, MissingFileIsAnIoError) {
  EXPECT_THROW((void)read_pan_tilt_csv(std::string(VDTNAV_TEST_TMP) + "/does_not_exist.csv"),
               IoError);
  EXPECT_THROW(write_pan_tilt_csv("/nonexistent_dir_vdtnav/x.csv", {}), IoError);
}

}  // namespace
}  // namespace vdtnav::point_laser
