// vdtnav_intel_lab: the Intel Research Lab study (thesis 3.4.2, Dataset 2) on the real log.
//
// The data (../shared/data/intel-lab): the GMapping-corrected log (910 scans of 180 beams), a
// table joining each scan's raw odometry and corrected pose on the absolute time base of the
// Kuemmerle et al. benchmark relations. The thesis built its map from the third loop and
// localized the first two; here:
//   1. join the log and the table (the converter behind `vdtnav join-odometry`);
//   2. build an occupancy map (log-odds ray casting) from the corrected poses of the last third of
//      the scans, and its VDT map (`vdtnav map`);
//   3. localize the first two thirds with the raw odometry and the scans, with every method
//      (`vdtnav localize`), starting at the corrected pose of the first scan;
//   4. evaluate against the relations whose both ends are localized scans (exact stamps)
//      and against the corrected poses: ATE, RPE, lost scans (> 0.5 m), NEES, and the relation
//      NEES of the methods with a covariance (`vdtnav eval --relations R --cov C`); count the
//      scans each method reports lost (status kLost: flagged_lost).
// Writes table.csv, table.md and PNGs (map, trajectories, reprojected scans, errors over time).
//
// The study's machinery is in method_runs.cpp, tables.cpp and figures.cpp (intel_study.hpp).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "intel_study.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

using namespace intel_study;

int main(int argc, char** argv) {
  CLI::App app{"The Intel Research Lab study: map from the last third, localize the first two"};
  std::string data = "../shared/data", out = "out/intel_lab";
  double resolution = 0.05, sigma_range = 0.02;
  std::vector<std::string> methods = localizer_methods();
  app.add_option("--data", data, "Folder with intel-lab/ (read in place)")->capture_default_str();
  app.add_option("--out", out, "Output folder")->capture_default_str();
  app.add_option("--resolution", resolution, "Map resolution, metres")->capture_default_str();
  app.add_option("--sigma-range", sigma_range, "Range noise standard deviation, metres")
      ->capture_default_str();
  app.add_option("--methods", methods, "Methods to run")
      ->check(CLI::IsMember(localizer_methods()))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    const std::string dir = data + "/intel-lab/";
    std::filesystem::create_directories(out);
    std::printf("[intel] joining %sintel.gfs.log.gz with the raw-odometry table\n", dir.c_str());
    const CarmenLog gfs = load_carmen_log(dir + "intel.gfs.log.gz");
    const std::string table_path = dir + "intel_910_odom_vs_corrected.txt";
    const JoinedLogs logs = join_odometry_table(gfs, load_odometry_table(table_path), table_path);
    const std::size_t n = logs.raw.lasers.size();
    const std::size_t split = n - n / 3;  // the last third maps, the first two thirds localize
    save_carmen_log(out + "/intel_raw.log", logs.raw);
    std::vector<StampedPose3> reference_tum;
    for (const auto& l : logs.corrected.lasers)
      reference_tum.push_back({l.time, pose3_from_pose2(l.pose)});
    save_tum_trajectory(out + "/intel_corrected.tum", reference_tum);

    // 2. The map from the corrected poses of scans split..n-1.
    std::vector<Pose2> map_poses;
    std::vector<LaserScan> map_scans;
    for (std::size_t i = split; i < n; ++i) {
      map_poses.push_back(logs.corrected.lasers[i].pose);
      map_scans.push_back(logs.corrected.lasers[i].scan);
    }
    mapping::OccupancyMapperOptions mo;
    mo.resolution = resolution;
    const mapping::OccupancyMap map = mapping::build_occupancy_map(map_poses, map_scans, mo);
    save_ros_map(out + "/intel_map", map.cells);
    const auto tb = Clock::now();
    const VdtMap2 vdt = VdtMap2::build(map.occupancy);
    const double build_s = std::chrono::duration<double>(Clock::now() - tb).count();
    std::printf(
        "[intel] map from scans %zu..%zu (t = %.1f..%.1f): %d x %d cells of %.2f m, VDT "
        "built in %.3f s -> %s/intel_map.yaml\n",
        split, n - 1, logs.raw.lasers[split].time, logs.raw.lasers[n - 1].time,
        map.cells.size().x(), map.cells.size().y(), resolution, build_s, out.c_str());

    // 3. Localize scans 0..split-1 with the raw odometry.
    std::vector<std::size_t> idx(split);
    for (std::size_t i = 0; i < split; ++i) idx[i] = i;
    const LogOdometry odom = log_odometry(logs.raw, idx);
    std::vector<double> times;
    eval::Trajectory2 reference;
    for (std::size_t i : idx) {
      times.push_back(logs.raw.lasers[i].time);
      reference.push_back({logs.raw.lasers[i].time, logs.corrected.lasers[i].pose});
    }
    const std::vector<OdometryStep> steps = odometry_steps(times, odom.poses);
    const std::vector<Relation> relations = load_relations(dir + "intel.relations").relations;
    eval::RelationMetricOptions ro;  // exact stamps only: one scan every ~3 s
    ro.stamp_tolerance = 1e-6;
    ro.interpolate = false;

    std::vector<Row> rows;
    {  // The GMapping-corrected poses themselves, for scale.
      Row r;
      r.method = "gmapping (reference)";
      r.rel = eval::relation_metric(reference, relations, ro);
      r.scans = split;
      rows.push_back(r);
    }
    const Localization in{logs, split, sigma_range, times, reference, steps, relations, ro};
    const LocalizerSettings settings = log_settings();
    const Eigen::Matrix3d p0 = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05).asDiagonal();
    for (const std::string& method : methods) {
      rows.push_back(localize_method(method, vdt, map, settings, p0, in, out));
    }

    // 4. Tables.
    std::ofstream csv(out + "/table.csv");
    std::ofstream md(out + "/table.md");
    write_tables(csv, md, rows, split, n, build_s);

    // 5. Figures.
    write_figures(out, map, in, rows);
    std::printf(
        "[intel] wrote %s/table.csv, table.md, trajectories.png, scans_*.png, errors_*.png\n",
        out.c_str());
    std::ifstream t(out + "/table.md");
    std::printf("%s", std::string(std::istreambuf_iterator<char>(t), {}).c_str());
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "vdtnav_intel_lab: %s\n", e.what());
    return 1;
  }
  return 0;
}
