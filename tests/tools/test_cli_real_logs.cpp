// Lost detection and recovery on the real logs in ../shared, through `vdtnav` as a user runs it
// with the default settings: the Intel lab (map from the last third, the first two thirds
// localized on the raw odometry) and MIT Killian Court (map from the odd scans, the even scans
// localized). A right track is never flagged lost, and recovery cannot change it: the
// trajectories with and without recovery are the same file, and the Intel relations' figures are
// the study's (0.0295 m / 0.48 deg). Skips when the data is absent.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/map_files/load_map.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::read_all;
using test::run_cli;

fs::path work_dir(const std::string& name) {
  const fs::path d = fs::path(VDTNAV_TEST_TMP) / (name + "_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string fixed(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6f", v);
  return b;
}

/// The value of `"key": number` after `section` in a JSON text.
double json_number(const std::string& js, const std::string& section, const std::string& key) {
  std::size_t p = js.find(section);
  if (p == std::string::npos) return std::nan("");
  p = js.find("\"" + key + "\":", p);
  if (p == std::string::npos) return std::nan("");
  return std::stod(js.substr(p + key.size() + 3));
}

/// Localizes LOG on MAP with and without recovery (method, other flags in `args`), every pose
/// written (--all-poses): both runs complete, no scan is reported lost, and the two trajectories
/// are the same file.
void expect_recovery_changes_nothing(const fs::path& d, const std::string& args,
                                     const std::string& tag) {
  const fs::path on = d / (tag + "_recover.tum"), off = d / (tag + "_norecover.tum");
  ASSERT_EQ(run_cli(args + " --quiet --all-poses --out " + on.string(), d / (tag + "_recover.txt")),
            0)
      << read_all(d / (tag + "_recover.txt"));
  ASSERT_EQ(run_cli(args + " --quiet --all-poses --no-recover --out " + off.string(),
                    d / (tag + "_norecover.txt")),
            0)
      << read_all(d / (tag + "_norecover.txt"));
  for (const char* run : {"_recover.txt", "_norecover.txt"}) {
    const std::string text = read_all(d / (tag + run));
    EXPECT_FALSE(contains(text, "  lost  ")) << tag << run << ":\n" << text;
  }
  EXPECT_EQ(read_all(on), read_all(off)) << tag << ": recovery changed a track nothing lost";
}

/// The README's C++ snippet (load_map, make_localizer with the defaults, reset, update) on MAP
/// and the raw log's scans up to `to`, from `start` with `vdtnav localize`'s --init-sigma and
/// --sigma-range: one TUM line a scan, as `localize --all-poses` writes them.
std::vector<std::string> readme_snippet_poses(const fs::path& map_yaml, const fs::path& raw_log,
                                              double to, const Pose2& start) {
  // As `localize` reads a log: no-return readings dropped, the window, the log's odometry.
  CarmenLogOptions lo;
  lo.max_range = 80.0;
  CarmenLog log = load_carmen_log(raw_log.string(), lo);
  const double no_return = detect_no_return_range(log);
  for (CarmenLaser& l : log.lasers) {
    if (std::isfinite(no_return) && no_return < l.scan.range_max) l.scan.range_max = no_return;
  }
  std::vector<std::size_t> idx;
  std::vector<double> times;
  for (std::size_t i = 0; i < log.lasers.size(); ++i) {
    if (log.lasers[i].time <= to) {
      idx.push_back(i);
      times.push_back(log.lasers[i].time);
    }
  }
  const std::vector<OdometryStep> steps = odometry_steps(times, log_odometry(log, idx).poses);

  // The README's lines (TheReadmeShowsTheseLines below checks that it still does).
  const vdtnav::LoadedMap m = vdtnav::load_map(map_yaml.string());
  const auto loc = vdtnav::make_localizer("vdt-opt", *m.vdt, m.occupancy,  // Algorithm 1
                                          vdtnav::LocalizerSettings{},
                                          vdtnav::MapKnowledge(m.ros.cells));  // vdtnav localize's
  loc->reset(start, Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
  std::vector<std::string> lines;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    LaserScan scan = log.lasers[idx[k]].scan;
    scan.sigma_range = 0.02;
    const LocalizationResult r = loc->update(k == 0 ? OdometryStep{} : steps[k], scan);
    lines.push_back(tum_line(times[k], r.pose));
  }
  return lines;
}

/// The pose lines of a TUM file (comments left out).
std::vector<std::string> tum_lines(const fs::path& path) {
  std::vector<std::string> out;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') out.push_back(line);
  }
  return out;
}

TEST(CliRealLogs, TheReadmeShowsTheseLines) {
  const std::string readme = read_all(fs::path(VDTNAV_SOURCE_DIR) / "README.md");
  for (const char* line :
       {"const vdtnav::LoadedMap m = vdtnav::load_map(",
        "const auto loc = vdtnav::make_localizer(\"vdt-opt\", *m.vdt, m.occupancy,  // Algorithm 1",
        "    vdtnav::LocalizerSettings{}, vdtnav::MapKnowledge(m.ros.cells));"}) {
    EXPECT_TRUE(contains(readme, line)) << "README.md no longer shows: " << line;
  }
}

TEST(CliRealLogs, IntelStudyNothingLostAndRecoveryChangesNothing) {
  const fs::path data = fs::path(VDTNAV_DATA_DIR) / "intel-lab";
  if (!fs::exists(data / "intel.relations")) GTEST_SKIP() << "no Intel lab data in " << data;
  const fs::path d = work_dir("intel");
  ASSERT_EQ(
      run_cli("join-odometry --log " + (data / "intel.gfs.log.gz").string() + " --table " +
                  (data / "intel_910_odom_vs_corrected.txt").string() + " --out-raw " +
                  (d / "raw.log").string() + " --out-corrected " + (d / "corrected.log").string() +
                  " --out-reference " + (d / "reference.tum").string(),
              d / "join.txt"),
      0)
      << read_all(d / "join.txt");
  // The study's split: the last third maps, the first two thirds are localized.
  const CarmenLog corrected = load_carmen_log((d / "corrected.log").string());
  const std::size_t n = corrected.lasers.size(), split = n - n / 3;
  ASSERT_EQ(n, 910U);
  ASSERT_EQ(run_cli("map --quiet --log " + (d / "corrected.log").string() + " --from " +
                        fixed(corrected.lasers[split].time - 1e-4) + " --resolution 0.05 --out " +
                        (d / "map").string(),
                    d / "map.txt"),
            0)
      << read_all(d / "map.txt");
  const Pose2 p0 = corrected.lasers[0].pose;
  const std::string common = "localize --map " + (d / "map.yaml").string() + " --log " +
                             (d / "raw.log").string() + " --to " +
                             fixed(corrected.lasers[split - 1].time + 1e-4) + " --init " +
                             fixed(p0[0]) + "," + fixed(p0[1]) + "," + fixed(p0[2]);
  for (const char* method : {"vdt-opt", "vdt-ekf"}) {
    expect_recovery_changes_nothing(d, common + " --method " + method, method);
  }
  // The README's C++ snippet with the library's defaults is the CLI's run, pose for pose (issue
  // 58: one set of defaults): the Intel table's vdt-opt row. Within 1e-6 m and rad (the poses
  // go through the text of a TUM file); another setting anywhere moves them by millimetres, and
  // a start 1e-7 m off moved 27 of them by up to 9 cm.
  {
    const std::vector<std::string> cli = tum_lines(d / "vdt-opt_recover.tum");
    // The start as --init gave it to the CLI (6 decimals).
    const Pose2 init(std::stod(fixed(p0[0])), std::stod(fixed(p0[1])), std::stod(fixed(p0[2])));
    const std::vector<std::string> lib = readme_snippet_poses(
        d / "map.yaml", d / "raw.log", corrected.lasers[split - 1].time + 1e-4, init);
    ASSERT_EQ(lib.size(), cli.size());
    std::size_t differ = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < lib.size(); ++k) {
      // t x y z qx qy qz qw, a planar pose: z, qx, qy are 0.
      double a[8], b[8];
      std::istringstream la(lib[k]), lb(cli[k]);
      for (int i = 0; i < 8; ++i) la >> a[i], lb >> b[i];
      const double dyaw = 2.0 * std::abs(std::atan2(a[6], a[7]) - std::atan2(b[6], b[7]));
      const double e = std::max({std::abs(a[1] - b[1]), std::abs(a[2] - b[2]), dyaw});
      worst = std::max(worst, e);
      differ += a[0] != b[0] || e > 1e-6;
    }
    EXPECT_EQ(differ, 0U) << "of " << lib.size() << " poses (worst " << worst << "); the first: "
                          << (lib.empty() ? "" : lib.front() + " against " + cli.front());
  }
  // The relations' figures of vdt-opt on every pose (the README's and the study's: 58 relations).
  ASSERT_EQ(run_cli("eval --traj " + (d / "vdt-opt_recover.tum").string() + " --relations " +
                        (data / "intel.relations").string() + " --max-gap 0 --json",
                    d / "eval.txt"),
            0);
  const std::string js = read_all(d / "eval.txt");
  EXPECT_EQ(json_number(js, "\"relations\"", "used"), 58.0) << js;
  EXPECT_LE(json_number(js, "\"relations\"", "trans_mean_m"), 0.035) << js;
  EXPECT_LE(json_number(js, "\"relations\"", "rot_mean_deg"), 0.5) << js;
  // Without --all-poses the trajectory holds the converged and bridged scans only
  // (published_by_default()), as the pose table counts them; the relations between them are as
  // accurate.
  ASSERT_EQ(run_cli(common + " --method vdt-opt --quiet --out " + (d / "usable.tum").string() +
                        " --cov " + (d / "usable.csv").string(),
                    d / "usable.txt"),
            0)
      << read_all(d / "usable.txt");
  std::size_t converged = 0, published = 0;
  {
    std::ifstream table(d / "usable.csv");
    for (std::string row; std::getline(table, row);) {
      converged += contains(row, ",converged,");
      published += contains(row, ",converged,") || contains(row, ",bridged,");
    }
  }
  EXPECT_EQ(load_tum_trajectory((d / "usable.tum").string()).poses.size(), published);
  EXPECT_GT(converged, 400U);  // of 607
  EXPECT_GT(published, 575U);  // the correct scans but those in doubt (issue 57: 583)
  ASSERT_EQ(run_cli("eval --traj " + (d / "usable.tum").string() + " --relations " +
                        (data / "intel.relations").string() + " --max-gap 0 --json",
                    d / "eval_usable.txt"),
            0);
  const std::string ju = read_all(d / "eval_usable.txt");
  EXPECT_GE(json_number(ju, "\"relations\"", "used"), 30.0) << ju;
  EXPECT_LE(json_number(ju, "\"relations\"", "trans_mean_m"), 0.035) << ju;
  EXPECT_LE(json_number(ju, "\"relations\"", "rot_mean_deg"), 0.6) << ju;
}

TEST(CliRealLogs, MitKillianOddScansMapEvenScansLocalizeNothingLost) {
  const fs::path log = fs::path(VDTNAV_DATA_DIR) / "mit-killian/infinite-corridor-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "no MIT Killian Court log at " << log;
  const fs::path d = work_dir("mit");
  const CarmenLog all = load_carmen_log(log.string());
  CarmenLog odd, even;
  for (std::size_t k = 0; k < all.lasers.size(); ++k) {
    (k % 2 == 0 ? odd : even).lasers.push_back(all.lasers[k]);
  }
  save_carmen_log((d / "odd.log").string(), odd);
  save_carmen_log((d / "even.log").string(), even);
  ASSERT_EQ(run_cli("map --quiet --log " + (d / "odd.log").string() + " --resolution 0.05 --out " +
                        (d / "map").string(),
                    d / "map.txt"),
            0)
      << read_all(d / "map.txt");
  const std::string common =
      "localize --map " + (d / "map.yaml").string() + " --log " + (d / "even.log").string();
  expect_recovery_changes_nothing(d, common, "vdt-opt");
  // The track is right: every scan within 0.5 m of the log's corrected pose but one. Known short
  // since issue 57 (expected.yaml, kidnapped_real off_0.5m): one of the 970 scans, 438, jumps
  // 0.51 m along the corridor (its neighbours 0.09 and 0.05 m off) where the converged Newton
  // solve slides; the acceptance of such a jump is issue 57's open item 3.
  const std::vector<StampedPose3> est =
      load_tum_trajectory((d / "vdt-opt_recover.tum").string()).poses;
  ASSERT_EQ(est.size(), even.lasers.size());
  int off = 0;
  for (std::size_t k = 0; k < est.size(); ++k) {
    off += (est[k].pose.translation().head<2>() - even.lasers[k].pose.head<2>()).norm() > 0.5;
  }
  EXPECT_LE(off, 1);
}

}  // namespace
}  // namespace vdtnav
