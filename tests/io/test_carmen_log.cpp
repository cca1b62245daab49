#include "vdtnav/io/carmen_log.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_files.hpp"

namespace vdtnav {
namespace {

using test::tmp_dir;
using test::write_file;

namespace fs = std::filesystem;
constexpr double kDeg = kPi / 180.0;

const std::string kIntel = std::string(VDTNAV_DATA_DIR) + "/intel-lab/intel.gfs.log.gz";
const std::string kIntelTable =
    std::string(VDTNAV_DATA_DIR) + "/intel-lab/intel_910_odom_vs_corrected.txt";
const std::string kIntelJson =
    std::string(VDTNAV_DATA_DIR) + "/intel-lab/intel_gfs_rawodom.json.gz";
const std::string kKillian =
    std::string(VDTNAV_DATA_DIR) + "/mit-killian/infinite-corridor-corrected.log.gz";

#define REQUIRE_DATA(path) \
  if (!fs::exists(path)) GTEST_SKIP() << "real data not found at " << (path)

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// gunzip with zlib's gz* API (the loader uses inflate() directly).
std::string gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  EXPECT_NE(f, nullptr) << path;
  std::string text;
  char buf[1 << 16];
  int n = 0;
  while ((n = gzread(f, buf, sizeof(buf))) > 0) text.append(buf, static_cast<std::size_t>(n));
  gzclose(f);
  return text;
}

void gzip(const std::string& path, const std::string& text) {
  gzFile f = gzopen(path.c_str(), "wb1");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, text.data(), static_cast<unsigned>(text.size())),
            static_cast<int>(text.size()));
  gzclose(f);
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

/// A FLASER line with n readings `fill`, the first ones replaced by `first`.
std::string flaser(std::size_t n, const std::vector<std::string>& first = {},
                   const std::string& tail = "1 2 0.5 1 2 0.5 10.25 host 10.5") {
  std::string s = "FLASER " + std::to_string(n);
  for (std::size_t i = 0; i < n; ++i) s += " " + (i < first.size() ? first[i] : "2.5");
  return s + " " + tail;
}

std::string message_of(const std::string& path, const CarmenLogOptions& o = {}) {
  try {
    (void)load_carmen_log(path, o);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

/// Same time, pose, odometry, hostname and ranges (bitwise, NaN equal to NaN).
void expect_same_laser(const CarmenLaser& a, const CarmenLaser& b) {
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.ipc_time, b.ipc_time);
  EXPECT_EQ(a.hostname, b.hostname);
  EXPECT_EQ(a.pose, b.pose);
  EXPECT_EQ(a.odom, b.odom);
  EXPECT_EQ(a.scan.time, b.scan.time);
  EXPECT_EQ(a.scan.angle_min, b.scan.angle_min);
  EXPECT_EQ(a.scan.angle_increment, b.scan.angle_increment);
  ASSERT_EQ(a.scan.ranges.size(), b.scan.ranges.size());
  EXPECT_EQ(std::memcmp(a.scan.ranges.data(), b.scan.ranges.data(),
                        a.scan.ranges.size() * sizeof(double)),
            0);
}

void expect_same_odometry(const CarmenOdometry& a, const CarmenOdometry& b) {
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.ipc_time, b.ipc_time);
  EXPECT_EQ(a.hostname, b.hostname);
  EXPECT_EQ(a.pose, b.pose);
  EXPECT_EQ(a.tv, b.tv);
  EXPECT_EQ(a.rv, b.rv);
  EXPECT_EQ(a.accel, b.accel);
}

// ---------------------------------------------------------------- real logs

TEST(CarmenLogIntel, CountsTimesAndGeometry) {
  REQUIRE_DATA(kIntel);
  const CarmenLog log = load_carmen_log(kIntel);
  ASSERT_EQ(log.lasers.size(), 910U);
  EXPECT_EQ(log.odometry.size(), 14541U);
  EXPECT_NEAR(detect_no_return_range(log), 81.83 - 0.01, 1e-9);  // its no-return code
  EXPECT_EQ(log.skipped, (std::map<std::string, std::size_t>{{"NEFF", 910}}));
  EXPECT_EQ(log.comments, 0U);
  EXPECT_TRUE(log.params.empty());
  EXPECT_TRUE(log.malformed_lines.empty());
  // Line numbers and times of the first and last scans (grep -n / awk on the log).
  EXPECT_EQ(log.lasers[0].line, 171U);
  EXPECT_EQ(log.lasers[1].line, 183U);
  EXPECT_EQ(log.lasers[0].time, 32.9068);
  EXPECT_EQ(log.lasers.back().time, 2683.77);
  double lo = 1e300, hi = -1e300;
  std::vector<std::size_t> backwards;
  std::size_t no_return = 0, not_finite = 0;
  double farthest = 0.0;
  for (std::size_t k = 0; k < log.lasers.size(); ++k) {
    const CarmenLaser& l = log.lasers[k];
    lo = std::min(lo, l.time);
    hi = std::max(hi, l.time);
    if (k > 0 && l.time < log.lasers[k - 1].time) backwards.push_back(k);
    EXPECT_EQ(l.ipc_time, l.time);
    EXPECT_EQ(l.hostname, "pippo");
    EXPECT_EQ(l.pose, l.odom);  // corrected log: both are the corrected pose
    ASSERT_EQ(l.scan.ranges.size(), 180U);
    EXPECT_EQ(l.scan.time, l.time);
    EXPECT_EQ(l.scan.range_max, 80.0);
    // 180 beams: 1 degree steps from -90, the last at +89 degrees.
    EXPECT_NEAR(l.scan.angle(0), -kPi / 2.0, 1e-12);
    EXPECT_NEAR(l.scan.angle(179), 89.0 * kDeg, 1e-12);
    const ScanPoints pts = scan_points(l.scan);
    no_return += pts.dropped_out_of_range;
    not_finite += pts.dropped_not_finite;
    for (const double r : pts.ranges) farthest = std::max(farthest, r);
  }
  EXPECT_EQ(lo, 32.9068);
  EXPECT_EQ(hi, 2683.77);
  // gmapping wrote four scans out of time order (by 0.11 .. 0.86 s).
  EXPECT_EQ(backwards, (std::vector<std::size_t>{295, 601, 627, 725}));
  // awk: 4172 readings are 81.83 (no return), none is below 0.1; the farthest return is 25.38.
  EXPECT_EQ(no_return, 4172U);
  EXPECT_EQ(not_finite, 0U);
  EXPECT_EQ(farthest, 25.38);
}

/// The derived table's rows, keyed by gfs_log_timestamp.
struct TableRow {
  std::string abs_text;
  double abs = 0.0;
  Pose2 raw = Pose2::Zero(), corrected = Pose2::Zero();
};

std::map<double, TableRow> read_table(const std::string& path) {
  std::map<double, TableRow> rows;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    TableRow r;
    double gfs = 0.0;
    s >> r.abs_text >> gfs >> r.raw[0] >> r.raw[1] >> r.raw[2] >> r.corrected[0] >>
        r.corrected[1] >> r.corrected[2];
    EXPECT_TRUE(static_cast<bool>(s)) << line;
    r.abs = std::stod(r.abs_text);
    EXPECT_TRUE(rows.emplace(gfs, r).second) << "duplicate gfs time " << gfs;
  }
  return rows;
}

/// `"range": [...]` of the JSON entry keyed by `key`, read with strtod.
std::vector<double> json_ranges(const std::string& json, const std::string& key) {
  std::vector<double> out;
  std::size_t pos = json.find("\"" + key + "\": {");
  EXPECT_NE(pos, std::string::npos) << key;
  if (pos == std::string::npos) return out;
  pos = json.find('[', json.find("\"range\"", pos)) + 1;
  const std::size_t end = json.find(']', pos);
  while (pos < end) {
    char* next = nullptr;
    out.push_back(std::strtod(json.c_str() + pos, &next));
    pos = json.find_first_not_of(" \n\r\t,", static_cast<std::size_t>(next - json.c_str()));
  }
  return out;
}

TEST(CarmenLogIntel, PosesMatchTheDerivedTableAndRangesTheJson) {
  REQUIRE_DATA(kIntel);
  REQUIRE_DATA(kIntelTable);
  REQUIRE_DATA(kIntelJson);
  const CarmenLog log = load_carmen_log(kIntel);
  const std::map<double, TableRow> table = read_table(kIntelTable);
  ASSERT_EQ(table.size(), 910U);
  ASSERT_EQ(log.lasers.size(), 910U);
  const std::string json = gunzip(kIntelJson);
  for (std::size_t k = 0; k < log.lasers.size(); ++k) {
    SCOPED_TRACE("scan " + std::to_string(k));
    const CarmenLaser& l = log.lasers[k];
    const auto row = table.find(l.time);
    ASSERT_NE(row, table.end()) << "no table row at gfs time " << l.time;
    EXPECT_EQ(l.pose, row->second.corrected);
    // README: abs - gfs_log time = 976052857.337 +- 0.005 s.
    EXPECT_NEAR(row->second.abs - l.time, 976052857.337, 0.0055);
    if (k == 0 || k == 1 || k == 294 || k == 295 || k == 455 || k == 909) {
      EXPECT_EQ(l.scan.ranges, json_ranges(json, row->second.abs_text));
    }
  }
  // Spot values read off the log by eye: scan 0's first and last readings.
  EXPECT_EQ(log.lasers[0].scan.ranges.front(), 1.09);
  EXPECT_EQ(log.lasers[0].scan.ranges.back(), 1.23);
  EXPECT_EQ(log.lasers[0].pose, Pose2(0.600266, -0.0320327, -0.354665));
}

TEST(CarmenLogKillian, CountsAndTheNoReturnOption) {
  REQUIRE_DATA(kKillian);
  const CarmenLog log = load_carmen_log(kKillian);
  ASSERT_EQ(log.lasers.size(), 1941U);
  EXPECT_EQ(log.odometry.size(), 18191U);
  EXPECT_EQ(log.skipped, (std::map<std::string, std::size_t>{{"NEFF", 1941}}));
  std::size_t broken_stamps = 0, dropped = 0;
  for (const CarmenLaser& l : log.lasers) {
    ASSERT_EQ(l.scan.ranges.size(), 180U);
    broken_stamps += l.time == 4.29497e+09 ? 1 : 0;
    dropped += scan_points(l.scan).dropped_out_of_range;
  }
  // The first four logger stamps are -0.446 .. -1.82 s, the other 1937 the same 4.29497e+09.
  EXPECT_EQ(log.lasers[0].time, -0.445999);
  EXPECT_EQ(broken_stamps, 1937U);
  // This log marks no return with 51.05..51.16 (awk: 4660 readings >= 51), below the 80 m
  // default: only a lower max_range keeps them from becoming obstacles.
  EXPECT_EQ(dropped, 0U);
  CarmenLogOptions o;
  o.max_range = 51.0;
  const CarmenLog cut = load_carmen_log(kKillian, o);
  dropped = 0;
  for (const CarmenLaser& l : cut.lasers) dropped += scan_points(l.scan).dropped_out_of_range;
  EXPECT_EQ(dropped, 4660U);
  // Found in the readings themselves: the pile 51.05..51.16 (4660 readings within 0.25 m of the
  // maximum, 25 in the metre below).
  const double r = detect_no_return_range(log);
  EXPECT_GT(r, 50.9);
  EXPECT_LE(r, 51.05 - 0.01 + 1e-9);
  dropped = 0;
  for (CarmenLaser l : log.lasers) {
    l.scan.range_max = r;
    dropped += scan_points(l.scan).dropped_out_of_range;
  }
  EXPECT_EQ(dropped, 4660U);
}

TEST(CarmenLog, TheNoReturnCodeIsFoundWhereReadingsPileUpAtTheMaximum) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> real(0.2, 30.0);
  const auto log_with = [&](double code, double code_share) {
    CarmenLog log;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
      CarmenLaser l;
      for (int i = 0; i < 180; ++i) l.scan.ranges.push_back(u(rng) < code_share ? code : real(rng));
      log.lasers.push_back(l);
    }
    return log;
  };
  // A code at 32.76 above real readings up to 30 m: found, just below the code.
  EXPECT_NEAR(detect_no_return_range(log_with(32.76, 0.02)), 32.75, 1e-9);
  // A code inside the readings' reach is no pile (as dense below): none.
  EXPECT_EQ(detect_no_return_range(log_with(30.0, 0.0)), std::numeric_limits<double>::infinity());
  // Too few to be a code (a few far walls at the maximum): none.
  CarmenLog few = log_with(30.0, 0.0);
  for (int i = 0; i < 5; ++i) few.lasers[i].scan.ranges[0] = 45.0;
  EXPECT_EQ(detect_no_return_range(few), std::numeric_limits<double>::infinity());
  EXPECT_EQ(detect_no_return_range(CarmenLog{}), std::numeric_limits<double>::infinity());
}

// ---------------------------------------------------------------- geometry and readings

TEST(CarmenLog, FlaserBeamGeometry) {
  const std::string dir = tmp_dir("carmen_log");
  struct Case {
    std::size_t n;
    double last_deg, step_deg;
  };
  for (const Case c :
       {Case{180, 89.0, 1.0}, Case{181, 90.0, 1.0}, Case{360, 89.5, 0.5}, Case{361, 90.0, 0.5}}) {
    SCOPED_TRACE(c.n);
    const std::string path = dir + "/n" + std::to_string(c.n) + ".log";
    write_file(path, flaser(c.n) + "\n");
    const CarmenLog log = load_carmen_log(path);
    ASSERT_EQ(log.lasers.size(), 1U);
    const LaserScan& s = log.lasers[0].scan;
    ASSERT_EQ(s.ranges.size(), c.n);
    EXPECT_NEAR(s.angle(0), -90.0 * kDeg, 1e-12);
    EXPECT_NEAR(s.angle(c.n - 1), c.last_deg * kDeg, 1e-12);
    EXPECT_NEAR(s.angle(1) - s.angle(0), c.step_deg * kDeg, 1e-12);
    const ScanPoints pts = scan_points(s);  // beam 0 points to -y (right), mount zero
    ASSERT_EQ(pts.size(), c.n);
    EXPECT_NEAR(pts.points[0].x(), 0.0, 1e-12);
    EXPECT_NEAR(pts.points[0].y(), -2.5, 1e-12);
  }
}

TEST(CarmenLog, NoReturnAndNonFiniteReadingsAreDroppedNotMalformed) {
  const std::string dir = tmp_dir("carmen_log");
  const std::string path = dir + "/readings.log";
  write_file(path, flaser(180, {"1.0", "81.83", "80", "79.99", "nan", "inf", "-inf", "0.05",
                                "32.76", "NaN", "+3.25"}) +
                       "\n");
  const CarmenLog log = load_carmen_log(path);
  ASSERT_EQ(log.lasers.size(), 1U);
  const LaserScan& s = log.lasers[0].scan;
  EXPECT_EQ(s.range_max, 80.0);
  EXPECT_EQ(s.range_min, 0.1);
  EXPECT_TRUE(std::isnan(s.ranges[4]));
  EXPECT_EQ(s.ranges[5], std::numeric_limits<double>::infinity());
  EXPECT_EQ(s.ranges[6], -std::numeric_limits<double>::infinity());
  EXPECT_EQ(s.ranges[10], 3.25);
  ScanPoints pts = scan_points(s);
  EXPECT_EQ(pts.dropped_not_finite, 4U);    // nan inf -inf NaN
  EXPECT_EQ(pts.dropped_out_of_range, 3U);  // 81.83, 80 (>= range_max), 0.05 (< range_min)
  EXPECT_EQ(pts.size(), 173U);
  EXPECT_EQ(pts.ranges[1], 79.99);
  EXPECT_EQ(pts.ranges[2], 32.76);

  CarmenLogOptions o;  // a log that marks no return with 32.76
  o.max_range = 32.0;
  o.range_min = 0.0;
  pts = scan_points(load_carmen_log(path, o).lasers[0].scan);
  EXPECT_EQ(pts.dropped_out_of_range, 4U);  // 81.83, 80, 79.99, 32.76
  EXPECT_EQ(pts.ranges[1], 0.05);

  for (const auto& [max_range, range_min] :
       {std::pair{std::nan(""), 0.1}, std::pair{80.0, -1.0}, std::pair{1.0, 1.0},
        std::pair{std::numeric_limits<double>::infinity(), 0.1}}) {
    o.max_range = max_range;
    o.range_min = range_min;
    EXPECT_THROW((void)load_carmen_log(path, o), ConfigError);
  }
}

TEST(CarmenLog, MessagesCommentsAndUnknownTypes) {
  const std::string dir = tmp_dir("carmen_log");
  const std::string path = dir + "/mixed.log";
  write_file(path,
             "# CARMEN Logfile\r\n"
             "# file format is one message per line\r\n"
             "PARAM robot_frontlaser_offset 0.05 0.0 nohost 0.0\r\n"
             "PARAM logger_comment two words 0.0 nohost 0.0\r\n"
             "\r\n"
             "   \t\r\n"
             "ODOM 1.5 -2 0.25 0.3 -0.1 0 100.5 robot 100.25\r\n"
             "RAWLASER1 0 -1.57 3.14 0.0174 81.9 0.01 0 2 1 2 0 100.6 robot 100.6\r\n"
             "TRUEPOS 1 2 3 4 5 6 100.7 robot 100.7\r\n"
             "TRUEPOS 1 2 3 4 5 6 100.8 robot 100.8\r\n"
             // laser_type start fov res max_range accuracy remission_mode n r.. m rem..
             "ROBOTLASER1 0 -1.5 3.0 0.5 50.0 0.01 0 5 1.0 2.0 50.0 nan 3.5 2 10 20 "
             // laser pose, robot pose, tv rv fsd ssd turn_axis, stamps
             "1.1 2.2 0.3 1.0 2.0 0.25 0.5 0.1 0.3 0.2 0.0 1000.5 host2 1000.75\r\n"
             "ROBOTLASER1 0 -1.5 3.0 0.5 120 0.01 0 1 7.0 0 "
             "1.1 2.2 0.3 1.0 2.0 0.25 0.5 0.1 0.3 0.2 0.0 1001.5 host2 1001.75\r\n" +
                 flaser(181) + "\r\n");
  const CarmenLog log = load_carmen_log(path);
  EXPECT_EQ(log.comments, 2U);
  EXPECT_EQ(log.params, (std::map<std::string, std::string>{{"robot_frontlaser_offset", "0.05"},
                                                            {"logger_comment", "two words"}}));
  EXPECT_EQ(log.skipped, (std::map<std::string, std::size_t>{{"RAWLASER1", 1}, {"TRUEPOS", 2}}));
  ASSERT_EQ(log.odometry.size(), 1U);
  const CarmenOdometry& odom = log.odometry[0];
  EXPECT_EQ(odom.pose, Pose2(1.5, -2.0, 0.25));
  EXPECT_EQ(odom.tv, 0.3);
  EXPECT_EQ(odom.rv, -0.1);
  EXPECT_EQ(odom.accel, 0.0);
  EXPECT_EQ(odom.ipc_time, 100.5);
  EXPECT_EQ(odom.time, 100.25);
  EXPECT_EQ(odom.hostname, "robot");
  EXPECT_EQ(odom.line, 7U);

  ASSERT_EQ(log.lasers.size(), 3U);
  const CarmenLaser& rl = log.lasers[0];
  EXPECT_EQ(rl.line, 11U);
  EXPECT_EQ(rl.scan.angle_min, -1.5);
  EXPECT_EQ(rl.scan.angle(4), -1.5 + 4 * 0.5);
  EXPECT_EQ(rl.scan.range_max, 50.0);  // the message's max_range, below the option's 80
  EXPECT_EQ(rl.remissions, (std::vector<double>{10.0, 20.0}));
  EXPECT_EQ(rl.pose, Pose2(1.1, 2.2, 0.3));   // laser pose
  EXPECT_EQ(rl.odom, Pose2(1.0, 2.0, 0.25));  // robot pose
  EXPECT_EQ(rl.time, 1000.75);
  EXPECT_EQ(rl.scan.time, 1000.75);
  EXPECT_EQ(rl.ipc_time, 1000.5);
  EXPECT_EQ(rl.hostname, "host2");
  const ScanPoints pts = scan_points(rl.scan);
  EXPECT_EQ(pts.ranges, (std::vector<double>{1.0, 2.0, 3.5}));  // 50 = no return, nan dropped
  EXPECT_EQ(log.lasers[1].scan.range_max, 80.0);  // max_range 120 is capped by the option
  EXPECT_TRUE(log.lasers[1].remissions.empty());
  EXPECT_EQ(log.lasers[2].scan.ranges.size(), 181U);
  EXPECT_EQ(log.lasers[2].line, 13U);
}

// ---------------------------------------------------------------- malformed lines

TEST(CarmenLog, SyntheticMalformedLinesNameFileLineAndExpectation) {
  const std::string dir = tmp_dir("carmen_log");
  struct Case {
    const char* name;
    std::string line;
    std::string what;
  };
  const std::string tail =
      "x y theta odom_x odom_y odom_theta ipc_timestamp hostname logger_timestamp";
  const Case cases[] = {
      {"no_n", "FLASER", "FLASER: expected the number of readings n after FLASER"},
      {"bad_n", "FLASER 18O 1 2",
       "FLASER: n (number of readings): expected an integer >= 2, "
       "got '18O'"},
      {"one_beam", flaser(1), "FLASER: n (number of readings): expected an integer >= 2"},
      {"too_long", flaser(180) + " extra",
       "FLASER: expected 189 fields after n = 180 (180 ranges, " + tail + "), found 190"},
      {"bad_theta", flaser(180, {}, "1 2 north 1 2 0.5 10.25 host 10.5"),
       "FLASER: theta: expected a finite number, got 'north'"},
      {"nan_pose", flaser(180, {}, "1 2 0.5 nan 2 0.5 10.25 host 10.5"),
       "FLASER: odom_x: expected a finite number, got 'nan'"},
      {"bad_stamp", flaser(180, {}, "1 2 0.5 1 2 0.5 10.25 host 10:5"),
       "FLASER: logger_timestamp: expected a finite number, got '10:5'"},
      {"odom_short", "ODOM 1 2 3 0 0 0 5.0 host",
       "ODOM: expected 9 fields after ODOM (x y theta tv rv accel ipc_timestamp hostname "
       "logger_timestamp), found 8"},
      {"param_short", "PARAM a 1 0.0 host", "PARAM: expected at least 5 fields after PARAM"},
      {"robotlaser_count",
       "ROBOTLASER1 0 -1.5 3.0 0.5 50.0 0.01 0 2 1.0 2.0 3 10 20 "
       "1.1 2.2 0.3 1.0 2.0 0.25 0.5 0.1 0.3 0.2 0.0 1000.5 host2 1000.75",
       "ROBOTLASER1: expected 17 fields after num_remissions = 3 (3 remissions, laser_x"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".log";
    write_file(path, "# header\nODOM 0 0 0 0 0 0 1 h 1\n" + c.line + "\nODOM 0 0 0 0 0 0 2 h 2\n");
    const std::string msg = message_of(path);
    EXPECT_EQ(msg.rfind(path + ":3: " + c.what, 0), 0U) << msg;
    CarmenLogOptions o;
    o.skip_malformed = true;
    const CarmenLog log = load_carmen_log(path, o);
    EXPECT_EQ(log.malformed_lines, std::vector<std::size_t>{3});
    EXPECT_EQ(log.odometry.size(), 2U);
    EXPECT_TRUE(log.lasers.empty());
  }
}

TEST(CarmenLogIntel, CorruptedCopiesNameTheLineAndSkipMalformedKeepsTheRest) {
  REQUIRE_DATA(kIntel);
  const std::string dir = tmp_dir("carmen_log");
  const CarmenLog original = load_carmen_log(kIntel);
  const std::vector<std::string> lines = lines_of(gunzip(kIntel));
  ASSERT_EQ(lines.size(), 16361U);
  ASSERT_EQ(lines[182].rfind("FLASER 180 ", 0), 0U);   // line 183: 2nd scan
  ASSERT_EQ(lines[194].rfind("FLASER 180 ", 0), 0U);   // line 195: 3rd scan
  ASSERT_EQ(lines[2164].rfind("FLASER 180 ", 0), 0U);  // line 2165: 100th scan
  ASSERT_EQ(lines[0].rfind("ODOM ", 0), 0U);

  struct Corruption {
    const char* name;
    std::size_t line;  // 1-based
    std::string text;
    std::string what;
  };
  std::vector<std::string> w = words(lines[182]);
  std::string truncated;  // FLASER 180 and the first 12 ranges
  for (std::size_t k = 0; k < 14; ++k) truncated += (k ? " " : "") + w[k];
  w = words(lines[194]);
  w[2 + 54] = "abc";  // range 55
  std::string non_numeric;
  for (std::size_t k = 0; k < w.size(); ++k) non_numeric += (k ? " " : "") + w[k];
  const std::string wrong_count = "FLASER 181" + lines[2164].substr(10);
  const std::string tail =
      "x y theta odom_x odom_y odom_theta ipc_timestamp hostname logger_timestamp";
  const std::vector<Corruption> corruptions = {
      {"truncated", 183, truncated,
       "FLASER: expected 189 fields after n = 180 (180 ranges, " + tail + "), found 12"},
      {"non_numeric", 195, non_numeric, "FLASER: range 55 of 180: expected a number, got 'abc'"},
      {"wrong_count", 2165, wrong_count,
       "FLASER: expected 190 fields after n = 181 (181 ranges, " + tail + "), found 189"},
      {"odom_word", 1, "ODOM 0 0 zero 0 0 0 0.000246 pippo 0.000246",
       "ODOM: theta: expected a finite number, got 'zero'"},
  };
  std::vector<std::string> all = lines;
  for (const Corruption& c : corruptions) {
    SCOPED_TRACE(c.name);
    std::vector<std::string> copy = lines;
    copy[c.line - 1] = c.text;
    all[c.line - 1] = c.text;
    const std::string expected_suffix = ":" + std::to_string(c.line) + ": " + c.what;
    const std::string plain = dir + "/" + c.name + ".log";
    write_file(plain, join_lines(copy));
    EXPECT_EQ(message_of(plain), plain + expected_suffix);
    const std::string gz = plain + ".gz";  // the same lines through the gzip path
    gzip(gz, join_lines(copy));
    EXPECT_EQ(message_of(gz), gz + expected_suffix);
  }
  const std::string path = dir + "/all.log";
  write_file(path, join_lines(all));
  EXPECT_EQ(message_of(path).rfind(path + ":1: ODOM: theta", 0), 0U);  // the first one throws
  CarmenLogOptions o;
  o.skip_malformed = true;
  const CarmenLog log = load_carmen_log(path, o);
  EXPECT_EQ(log.malformed_lines, (std::vector<std::size_t>{1, 183, 195, 2165}));
  EXPECT_EQ(log.skipped, original.skipped);
  // Every good line is kept, unchanged.
  ASSERT_EQ(log.lasers.size(), 907U);
  ASSERT_EQ(log.odometry.size(), 14540U);
  std::size_t k = 0;
  for (const CarmenLaser& l : original.lasers) {
    if (l.line == 183 || l.line == 195 || l.line == 2165) continue;
    SCOPED_TRACE(l.line);
    ASSERT_EQ(log.lasers[k].line, l.line);
    expect_same_laser(log.lasers[k++], l);
  }
  for (std::size_t j = 1; j < original.odometry.size(); ++j) {
    expect_same_odometry(log.odometry[j - 1], original.odometry[j]);
  }
}

// ---------------------------------------------------------------- files and round trips

TEST(CarmenLogIntel, PlainAndGzipCopiesReadTheSame) {
  REQUIRE_DATA(kIntel);
  const std::string dir = tmp_dir("carmen_log");
  const CarmenLog gz = load_carmen_log(kIntel);
  const std::string plain = dir + "/intel.gfs.log";
  write_file(plain, gunzip(kIntel));
  const CarmenLog text = load_carmen_log(plain);
  ASSERT_EQ(text.lasers.size(), gz.lasers.size());
  for (std::size_t k = 0; k < gz.lasers.size(); ++k)
    expect_same_laser(text.lasers[k], gz.lasers[k]);
  ASSERT_EQ(text.odometry.size(), gz.odometry.size());
  for (std::size_t k = 0; k < gz.odometry.size(); ++k) {
    expect_same_odometry(text.odometry[k], gz.odometry[k]);
  }
  // Two gzip members in one file are read one after the other, as gunzip does.
  const std::vector<std::string> lines = lines_of(read_file(plain));
  const std::string first = join_lines({lines.begin(), lines.begin() + 200});
  const std::string second = join_lines({lines.begin() + 200, lines.end()});
  const std::string a = dir + "/a.gz", b = dir + "/b.gz", ab = dir + "/ab.log.gz";
  gzip(a, first);
  gzip(b, second);
  write_file(ab, read_file(a) + read_file(b));
  EXPECT_EQ(load_carmen_log(ab).lasers.size(), 910U);
  // A gzip file cut short is a FormatError, not a shorter log.
  const std::string bytes = read_file(kIntel);
  const std::string cut = dir + "/cut.log.gz";
  write_file(cut, bytes.substr(0, bytes.size() / 2));
  EXPECT_EQ(message_of(cut),
            cut + ": truncated gzip data: expected the end of the compressed stream");
  std::string garbled = bytes;
  for (std::size_t k = 100; k < 200; ++k) garbled[k] = static_cast<char>(garbled[k] ^ 0x5a);
  write_file(cut, garbled);
  EXPECT_EQ(message_of(cut).rfind(cut + ": corrupt gzip data", 0), 0U) << message_of(cut);
  EXPECT_THROW((void)load_carmen_log(dir + "/missing.log"), IoError);
}

TEST(CarmenLogIntel, SaveLoadRoundTrip) {
  REQUIRE_DATA(kIntel);
  const std::string dir = tmp_dir("carmen_log");
  const CarmenLog log = load_carmen_log(kIntel);
  const std::string path = dir + "/intel.log";
  save_carmen_log(path, log);
  const CarmenLog back = load_carmen_log(path);
  ASSERT_EQ(back.lasers.size(), log.lasers.size());
  for (std::size_t k = 0; k < log.lasers.size(); ++k)
    expect_same_laser(back.lasers[k], log.lasers[k]);
  ASSERT_EQ(back.odometry.size(), log.odometry.size());
  for (std::size_t k = 0; k < log.odometry.size(); ++k) {
    expect_same_odometry(back.odometry[k], log.odometry[k]);
  }
  EXPECT_TRUE(back.skipped.empty());  // NEFF is not written
  EXPECT_TRUE(back.malformed_lines.empty());
}

TEST(CarmenLog, SaveLoadRoundTripKeepsEveryBit) {
  const std::string dir = tmp_dir("carmen_log");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  CarmenLog log;
  log.params = {{"robot_frontlaser_offset", "0.05"}, {"comment", "a b c"}};
  for (int k = 0; k < 20; ++k) {
    CarmenLaser l;
    l.time = 1e9 + u(rng);
    l.ipc_time = u(rng) / 3.0;
    l.hostname = k % 2 ? "robot" : "";
    l.pose = Pose2(u(rng), u(rng) * 1e-7, kPi / 3.0);
    l.odom = Pose2(1.0 / 3.0, -u(rng), std::nextafter(1.0, 2.0));
    l.scan.time = l.time;
    set_flaser_geometry(k % 2 ? 361 : 180, l.scan);
    l.scan.ranges.resize(k % 2 ? 361 : 180);
    for (double& r : l.scan.ranges) r = std::abs(u(rng)) / 7.0;
    l.scan.ranges[3] = std::nan("");
    l.scan.ranges[4] = std::numeric_limits<double>::infinity();
    l.scan.ranges[5] = std::numeric_limits<double>::denorm_min();
    log.lasers.push_back(l);
    CarmenOdometry o;
    o.time = l.time - 0.01 * (k % 3);  // some before, some at the same time as the scan
    o.ipc_time = u(rng);
    o.hostname = "base";
    o.pose = Pose2(u(rng), u(rng), 0.1 + 0.2);
    o.tv = u(rng);
    o.rv = -0.0;
    o.accel = 1e-300;
    log.odometry.push_back(o);
  }
  std::sort(log.lasers.begin(), log.lasers.end(),
            [](const CarmenLaser& a, const CarmenLaser& b) { return a.time < b.time; });
  std::sort(log.odometry.begin(), log.odometry.end(),
            [](const CarmenOdometry& a, const CarmenOdometry& b) { return a.time < b.time; });
  const std::string path = dir + "/synthetic.log";
  save_carmen_log(path, log);
  const CarmenLog back = load_carmen_log(path);
  EXPECT_EQ(back.params, log.params);
  ASSERT_EQ(back.lasers.size(), log.lasers.size());
  for (std::size_t k = 0; k < log.lasers.size(); ++k) {
    CarmenLaser expected = log.lasers[k];
    if (expected.hostname.empty()) expected.hostname = "vdtnav";
    expect_same_laser(back.lasers[k], expected);
  }
  ASSERT_EQ(back.odometry.size(), log.odometry.size());
  for (std::size_t k = 0; k < log.odometry.size(); ++k) {
    expect_same_odometry(back.odometry[k], log.odometry[k]);
    EXPECT_TRUE(std::signbit(back.odometry[k].rv));
  }
  // Lines are in time order, an ODOM before a scan of the same time.
  const std::vector<std::string> lines = lines_of(read_file(path));
  double last = -1e300;
  for (const std::string& line : lines) {
    if (line.rfind("PARAM", 0) == 0) continue;
    const double t = std::stod(words(line).back());
    EXPECT_LE(last, t);
    last = t;
  }
}

TEST(CarmenLog, SaveRejectsWhatFlaserCannotHold) {
  const std::string path = tmp_dir("carmen_log") + "/bad.log";
  const auto rejects = [&](auto&& edit) {
    CarmenLog log;
    log.lasers.resize(1);
    set_flaser_geometry(180, log.lasers[0].scan);
    log.lasers[0].scan.ranges.assign(180, 1.0);
    edit(log);
    EXPECT_THROW(save_carmen_log(path, log), ConfigError);
  };
  rejects([](CarmenLog& log) { log.lasers[0].scan.angle_increment = 0.5 * kDeg; });
  rejects([](CarmenLog& log) { log.lasers[0].scan.angle_min = -kPi; });
  rejects([](CarmenLog& log) { log.lasers[0].scan.angles.assign(180, 0.0); });
  rejects([](CarmenLog& log) { log.lasers[0].scan.mount = Pose2(0.1, 0.0, 0.0); });
  rejects([](CarmenLog& log) { log.lasers[0].scan.ranges.resize(1); });
  rejects([](CarmenLog& log) { log.lasers[0].hostname = "two words"; });
  rejects([](CarmenLog& log) { log.params["a b"] = "1"; });
  rejects([](CarmenLog& log) { log.params["a"] = ""; });
  rejects([](CarmenLog& log) { log.params["a"] = "x  y"; });
  EXPECT_THROW(save_carmen_log(tmp_dir("carmen_log") + "/no/such/dir/x.log", CarmenLog{}), IoError);
}

}  // namespace
}  // namespace vdtnav
