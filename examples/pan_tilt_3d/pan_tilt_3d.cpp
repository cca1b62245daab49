// vdtnav_pan_tilt_3d: the thesis's Table 3.4 / Fig. 3.18 study (Dataset 4, section 3.4.4.2). A
// Turtlebot with a LIDAR-Lite v3 point laser on a pan-tilt unit stands still, rolled and pitched
// by an uneven floor, at 3 locations of a 3D map; a 5700-reading sweep is taken at each and the
// 6-DOF pose is estimated by the VDT optimizer (Algorithm 1 on SE(3)) from the initial guesses
// A-D of Table 3.4, with the sweep kept whole and downsampled by 2, 5, 10 and 100. Every cell of
// the table is repeated over independent range-noise seeds.
//
// The map is the CATEC OctoMap of the DLL data set when it is present (or any .bt/.ot given with
// --map), otherwise a generated 3D room (sim::generate_room3d). Writes table.csv, table.md,
// rmse.png (Fig. 3.18) and slices of the 3D VDT to --out; progress goes to stderr, the table to
// stdout.
//
// The study's machinery is in world.cpp, trials.cpp, tables.cpp and figures.cpp
// (pan_tilt_study.hpp).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "pan_tilt_study.hpp"
#include "vdtnav/core/error.hpp"

namespace {

using namespace pan_tilt_study;

/// Where the issue puts the CATEC map, relative to the working directory (the repository root).
const char* const kCatecPath = "../shared/data/3d/dll-catec/catec.bt";

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Table 3.4 / Fig. 3.18 study: 6-DOF VDT localization of a pan-tilt point laser sweep from "
      "the initial guesses A-D, with the sweep downsampled by 1, 2, 5, 10 and 100"};
  std::string out = "out/pan_tilt_3d", map_path;
  bool room = false;
  int seeds = 20, dof = 6, threads = 2;
  bool verbose = false;
  unsigned seed = 1;
  double resolution = 0.0;
  VdtOptimizerOptions opt;
  // An offline study can afford more iterations than the optimizer's default (25, sized for
  // tracking): on a sparse real octree (the CATEC floor is rings of LiDAR returns) LM takes 30 to
  // 80 steps to converge from guesses B and C, and stopping early reports "not converged".
  opt.max_iterations = 100;
  std::string loss = "none";
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--map", map_path,
                 std::string("OctoMap (.bt/.ot) to run in; default: ") + kCatecPath +
                     " when it exists, else the generated 3D room");
  app.add_flag("--room", room, "use the generated 3D room even when the CATEC map is present");
  app.add_option("--seeds", seeds, "range-noise seeds per location (trials = 3 x seeds per cell)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--resolution", resolution,
                 "voxel size in metres (0: the map's own, 0.05 m; an OctoMap accepts whole "
                 "multiples of its resolution)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--dof", dof, "6: full 6-DOF; 4: x, y, z, yaw with roll/pitch held at the IMU's")
      ->capture_default_str()
      ->check(CLI::IsMember({4, 6}));
  app.add_option("--seed", seed, "seed of the room, the locations and the noise")
      ->capture_default_str();
  app.add_option("--gate", opt.sensor.gate, "optimizer gate alpha (3.3), metres")
      ->capture_default_str();
  app.add_option("--pyramid", opt.pyramid_levels,
                 "optimizer coarse-to-fine levels (< 0: the optimizer's default)")
      ->capture_default_str();
  app.add_option("--loss", loss, "optimizer robust loss")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  app.add_option("--loss-scale", opt.loss_scale, "robust loss scale, metres")
      ->capture_default_str();
  app.add_option("--max-iterations", opt.max_iterations, "optimizer iterations per Ceres solve")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  MultiStartOptions multi_start;
  bool single_start = false;
  app.add_flag("--single-start", single_start,
               "one solve from the guess, as the thesis (default: more starts when the solution "
               "leaves readings unexplained, see estimation/multi_start.hpp)");
  app.add_flag("--verbose", verbose, "list every unsuccessful trial on stderr");
  app.add_option("--threads", threads, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  CLI11_PARSE(app, argc, argv);

  try {
    const auto t_start = Clock::now();
    const auto seconds = [&] {
      return std::chrono::duration<double>(Clock::now() - t_start).count();
    };
    std::filesystem::create_directories(out);
    const bool four_dof = dof == 4;
    // LIDAR-Lite v3 (0.05-40 m, sigma 0.025 m) on the Turtlebot-like unit; the default sweep is
    // 100 pans x 57 tilts = 5700 readings, a tilt count coprime to every factor, so every k-th
    // reading still visits all tilts.
    const sim::PointLaserSimOptions sim_options;
    const PanTiltCalibration& cal = sim_options.calibration;

    // ---------------------------------------------------------------- world
    if (map_path.empty() && !room) {
#ifdef VDTNAV_HAVE_OCTOMAP
      if (std::filesystem::exists(kCatecPath)) map_path = kCatecPath;
#else
      if (std::filesystem::exists(kCatecPath))
        std::fprintf(stderr, "[map] %s is present, but this build has no OctoMap front end\n",
                     kCatecPath);
#endif
    }
    World world;
    std::unique_ptr<VdtMap3> vdt;
    if (!build_world(map_path, seed, resolution, world, vdt)) return 2;
    const Eigen::Vector3i size = world.occupancy.size();
    std::printf("map: %s, %d x %d x %d voxels of %.3f m, VDT %.0f MB (%.1f s)\n",
                world.name.c_str(), size.x(), size.y(), size.z(), world.occupancy.resolution(),
                vdt->memory_bytes() / 1e6, seconds());
    std::printf("robot locations (%s):\n", world.how_located.c_str());
    for (std::size_t k = 0; k < world.locations.size(); ++k) {
      const Pose3& p = world.locations[k];
      const Eigen::Vector3d rpy = rpy_of(p.linear());
      std::printf(
          "  L%zu  x %.3f  y %.3f  z %.3f m  roll %+.2f  pitch %+.2f  yaw %+.1f deg  (sensor at "
          "z %.2f m)\n",
          k + 1, p.translation().x(), p.translation().y(), p.translation().z(), rpy[0] * 180 / kPi,
          rpy[1] * 180 / kPi, rpy[2] * 180 / kPi, sensor_z(p, cal));
    }
    std::fflush(stdout);

    // ---------------------------------------------------------------- trials
    multi_start.enabled = !single_start;
    opt.four_dof = four_dof;
    opt.loss = loss == "huber"    ? RobustLoss::kHuber
               : loss == "cauchy" ? RobustLoss::kCauchy
                                  : RobustLoss::kNone;
    const VdtOptimizer3 optimizer(*vdt, opt);
    const TrialRuns runs = run_trials(world, optimizer, sim_options, multi_start, seed, seeds,
                                      four_dof, verbose, threads);
    const std::size_t n_jobs = runs.trials.size();
    const double trials_s = runs.seconds;

    // ---------------------------------------------------------------- table
    const std::vector<std::vector<Cell>> cells = tabulate(runs.trials, seeds, verbose);
    write_tables(out, world, sim_options, cells, runs.sweep_returns, seeds, four_dof);

    // ---------------------------------------------------------------- figures
    std::fprintf(stderr, "[figures] writing PNGs to %s\n", out.c_str());
    write_rmse_figure(cells,
                      "Fig. 3.18: " + std::string(four_dof ? "4" : "6") + "-DOF RMSE, " +
                          world.name + ", " + std::to_string(n_jobs) + " trials per point",
                      out + "/rmse.png");
    write_vdt_slices(world, *vdt, cal, out);
    std::printf(
        "\n%.1f s in all (trials %.1f s on %d threads); wrote %s/table.csv, table.md, "
        "rmse.png, vdt_slice_horizontal.png, vdt_slice_vertical.png\n",
        seconds(), trials_s, threads, out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
