// Active localization with a single rotating range beam (thesis ch. 4): one reading per step,
// the VDT EKF, and where to point the beam next, against keeping it fixed or turning it blindly.
//
//   vdtnav_active_beam --out out/active_beam [--seed 1] [--data ../shared/data]
//
// Dataset 1: a robot driving through rooms and corridors of the Willow Garage map (with --data;
// else the generated floor plan) with Table 4.1's sensor (360 degrees, 0.525 rad/s, 8 segments,
// lambda 1e-5, 0.5-3 m). Dataset 2: Table 4.3's sensor (270 degrees, 0.1745 rad/s, 23 segments,
// 0.5-30 m) on the fetch-office map made by SLAM (with --data; else the generated floor plan),
// a 40 Hz UTM-30LX-like scanner of which one beam per scan is kept, the one in the sensor's
// current direction. Every strategy runs on the same drive, odometry and range noise.
// Writes table.csv, table.md and per dataset trajectory, errors, segments and snapshot PNGs.
//
// The study's machinery is in datasets.cpp, beam_localization.cpp, tables.cpp and figures.cpp
// (active_beam_study.hpp).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "active_beam_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/map/surface_roughness.hpp"

using namespace active_beam_study;

int main(int argc, char** argv) {
  CLI::App app{"Active localization with a single rotating range beam (thesis ch. 4)"};
  std::string out = "out/active_beam", data;
  unsigned seed = 1;
  double minutes = 4.0;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the drive and the noise")->capture_default_str();
  app.add_option("--data", data,
                 "real data folder (e.g. ../shared/data): the Willow Garage and fetch-office maps; "
                 "without it, the generated floor plan");
  app.add_option("--minutes", minutes, "length of each drive, minutes")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 120.0));
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(out);
    std::vector<Dataset> datasets = make_datasets(data, seed, minutes);

    std::ofstream csv(out + "/table.csv");
    std::ofstream md(out + "/table.md");
    write_table_header(csv, md);
    for (std::size_t d = 0; d < datasets.size(); ++d) {
      const Dataset& ds = datasets[d];
      const VdtMap2 map = VdtMap2::build(ds.world);
      const SurfaceRoughness rough = measure_surface_roughness(ds.world);
      datasets[d].map_sigma = rough.floor;
      std::printf("[%s] wall roughness %.4f m over %zu windows: per-reading floor %.4f m\n",
                  ds.name.c_str(), rough.sigma, rough.windows, ds.map_sigma);
      std::mt19937_64 odo_rng(seed * 7919u + d);
      const std::vector<OdometryStep> odo = odometry(ds.drive, odo_rng);
      std::printf(
          "[%s] %zu steps over %.0f s at 40 Hz, %.0f deg at %.4f rad/s, %d segments, "
          "%.1f-%.0f m\n",
          ds.name.c_str(), ds.drive.size(), ds.drive.back().t, ds.beam.rotation_range * 180.0 / kPi,
          ds.beam.angular_velocity, ds.beam.segments, ds.beam.range_min, ds.beam.range_max);
      std::vector<Run> runs;
      for (const BeamStrategy s :
           {BeamStrategy::kActiveTrace, BeamStrategy::kActiveDet, BeamStrategy::kActiveFisher,
            BeamStrategy::kPassiveFixed, BeamStrategy::kPassiveRotate}) {
        runs.push_back(localize(ds, map, s, odo, seed * 104729u + d));
        const Run& r = runs.back();
        std::printf(
            "  %-15s RMSE x %.4f m, y %.4f m, phi %.5f rad; ANEES %.2f [%.2f, %.2f]; "
            "lost %.1f %%; %d selections, %.3f ms each; %d readings refused\n",
            to_string(s), r.rmse_x, r.rmse_y, r.rmse_phi, r.anees.anees, r.anees.interval.lower,
            r.anees.interval.upper, r.lost_pct, r.selections, r.ms_select, r.gated);
        std::fflush(stdout);
        write_table_row(csv, md, ds, d, s, r);
      }
      plots(ds, runs, out + "/" + (d == 0 ? "dataset1" : "dataset2"));
    }
    std::printf("[done] %s/table.csv\n", out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
