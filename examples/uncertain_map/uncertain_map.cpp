// Uncertain VDT maps (thesis ch. 5): B-spline distance fields fitted to noisy scans through the
// Eikonal equation, their covariance, and localization on them.
//
//   vdtnav_uncertain_map --out out/uncertain_map [--seed 1] [--runs 3] [--data ../shared/data]
//
// Fig. 5.2: the least-squares B-spline approximation of the true VDT against the spacing.
// Experiment 1: the L-shaped room seen from 3 poses by a 180 degree LiDAR (Table 5.1's noise),
// control points at 0.2 m. Experiment 2: a corridor (the Willow Garage map with --data, else the
// generated floor plan's main corridor) driven with a 270 degree LiDAR (Table 5.2's noise),
// control points at 0.25 m. Localization on the Experiment 2 map, with the constant map floor and
// with the fitted map's covariance. With --data, the Intel lab: the uncertain map from the last
// third's scans, the first two thirds localized on it (intel_study.cpp).
// Writes table.csv, localization.csv, table.md and the figures.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "uncertain_map_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/mapping_run.hpp"
#include "vdtnav/sim/trajectory.hpp"

using namespace vdtnav;

namespace {}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Uncertain VDT maps (thesis ch. 5): Experiments 1 and 2, Figs. 5.2-5.6, "
      "localization on the fitted map, and the Intel lab with --data"};
  std::string out = "out/uncertain_map", data;
  unsigned seed = 1;
  int runs = 3;
  double noise_scale = 1.0;
  study::IntelSettings intel;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the noise (and of the generated plan)")
      ->capture_default_str();
  app.add_option("--runs", runs, "noisy map-building runs per experiment (errors pooled)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--noise-scale", noise_scale,
                 "factor on Tables 5.1 and 5.2's pose and range noise (0: exact poses and ranges)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--data", data,
                 "real data folder (e.g. ../shared/data): the Willow Garage map for Experiment 2 "
                 "and the Intel lab study; without it, the generated floor plan only");
  app.add_option("--intel-pose-sigma", intel.pose_sigma,
                 "Intel: stated sigma of the corrected poses' x and y, metres")
      ->capture_default_str();
  app.add_option("--intel-heading-sigma", intel.heading_sigma,
                 "Intel: stated sigma of the corrected poses' heading, radians")
      ->capture_default_str();
  app.add_option(
         "--intel-spacing", intel.spacing,
         "Intel: control point spacing, metres (0: from the data, as vdtnav map --uncertain)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(out);
    std::vector<study::Row> rows;

    // ------------------------------------------------------------ Fig. 5.2
    const sim::MappingScene room = sim::l_shaped_room(0.01);
    study::approximation(room, out, rows);

    // ------------------------------------------------------------ Experiments 1 and 2
    {
      std::printf("[experiment1] %s, 3 poses, 180 deg LiDAR, Table 5.1 noise, h = 0.2 m, %d runs\n",
                  room.name.c_str(), runs);
      sim::LidarOptions lidar;
      lidar.fov = kPi;
      lidar.angular_resolution = 0.5 * kPi / 180.0;
      lidar.range_max = 10.0;
      study::fit_experiment("experiment1", room, lidar, sim::MappingNoise::table_5_1(), 0.2,
                            nullptr, nullptr, runs, noise_scale, seed, out, rows);
    }

    const sim::MappingScene c2 = study::corridor(data, seed);
    const std::vector<sim::TimedPose> drive = sim::mapping_drive(c2);
    sim::LidarOptions lidar2;  // 270 degrees at 0.25 degrees
    lidar2.range_max = 10.0;
    std::unique_ptr<mapping::UncertainVdtMap> map2;
    sim::MappingRun run2;
    std::printf(
        "[experiment2] %s: %zu key scans over %.1f s, 270 deg LiDAR (0.25 deg, 10 m), "
        "Table 5.2 noise, h = 0.25 m, %d runs\n",
        c2.name.c_str(), c2.poses.size(), drive.back().t, runs);
    study::fit_experiment("experiment2", c2, lidar2, sim::MappingNoise::table_5_2(), 0.25, &map2,
                          &run2, runs, noise_scale, seed, out, rows);

    // ------------------------------------------------------------ localization on map 2
    const std::vector<study::LocalizationRow> loc =
        study::localize_on_fitted_map(*map2, c2.world, drive, lidar2, seed, out);

    // ------------------------------------------------------------ tables
    study::write_tables(out, rows, c2, loc);
    if (!data.empty() && std::filesystem::exists(data + "/intel-lab/intel.relations")) {
      study::intel_uncertain_map(data, out, intel);
    }
    std::printf("[done] %s/table.csv, %s/localization.csv\n", out.c_str(), out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
