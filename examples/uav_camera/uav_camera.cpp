// UAV downward-camera localization (thesis 3.4.3, Dataset 3; Figs. 3.13-3.14): a simulated flight
// over a figure-of-eight road marked on a runway (MBZIRC 2017 style), or over a real aerial
// photograph laid on the ground (--texture). Every frame is rendered from the true pose (lens
// distortion, sensor noise, motion blur, an exposure change), its edges are projected to the
// ground with the noisy IMU roll/pitch and laser altitude, and three localizers run side by side
// on the same observations: vdt-opt, vdt-ekf and the UDT chamfer baseline udt-opt.
//
//   vdtnav_uav_camera [--out DIR] [--seed N] [--frames N] [--altitude M] [--texture FILE]
//                     [--solver default|dense|ceres] [--verbose]
//
// Writes DIR/table.csv (method,frames,localized_pct,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,
// anees_hi,recovery_s,ms_per_frame,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct:
// the percentage of the frames with a covariance whose NEES is within chi^2_3(0.95)), table.md,
// trajectory.png (Fig. 3.13), errors_vdt_opt.png and errors_vdt_ekf.png (Fig. 3.14), frame.png, and
// the marking map (map.png + map.yaml) it localizes on, read back through the map_server reader as
// a user's map would be.
//
// The machinery (scenario, run, table, figures) is declared in uav_study.hpp.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "uav_study.hpp"

int main(int argc, char** argv) {
  CLI::App app{"UAV downward-camera localization on a VDT map of ground markings (thesis 3.4.3)"};
  std::string out = "out/uav_camera";
  std::uint64_t seed = 1;
  std::size_t frames = 1200;
  double altitude = 15.0;
  std::string texture_path;
  bool verbose = false;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the scene's texture, the flight and all noise")
      ->capture_default_str();
  app.add_option("--frames", frames, "frames at 10 Hz")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{20}, std::size_t{100000}));
  app.add_option("--altitude", altitude,
                 "mean altitude, m; the flight climbs and descends by a third of it")
      ->capture_default_str()
      ->check(CLI::Range(2.0, 200.0));
  app.add_option("--texture", texture_path,
                 "a photograph laid on the ground instead of the runway (its edges are the map)")
      ->check(CLI::ExistingFile);
  std::string solver = "default";
  app.add_option("--solver", solver, "vdt-opt's scan solver: default, dense or ceres")
      ->check(CLI::IsMember({"default", "dense", "ceres"}))
      ->capture_default_str();
  app.add_flag("--verbose", verbose, "one line per frame: points, explained fraction, status");
  CLI11_PARSE(app, argc, argv);

  try {
    std::filesystem::create_directories(out);
    const uav_study::Scenario sc =
        uav_study::make_scenario(out, seed, frames, altitude, texture_path);
    const uav_study::FlightRun run =
        uav_study::localize_flight(sc, altitude, solver, seed, verbose);
    uav_study::write_tables(out, sc, run);
    uav_study::draw_figures(out, sc, altitude, run);
    std::printf(
        "[done] %s/table.csv, table.md, trajectory.png, errors_vdt_opt.png, errors_vdt_ekf.png, "
        "frame.png\n",
        out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vdtnav_uav_camera: %s\n", e.what());
    return 1;
  }
  return 0;
}
