// vdtnav_turtlebot_lidar: the thesis's Table 3.3 study (Dataset 1, section 3.4.1). A robot with a
// Hokuyo UTM-30LX-like LiDAR (270 degrees, 0.25 degrees, 0.1-30 m) drives through a floor plan;
// five localizers run side by side on the same simulated scans and odometry:
//   vdt-opt  optimization on the VDT (Algorithm 1) with implicit-function covariance
//   vdt-ekf  EKF on the VDT
//   udt-opt  C-LOG-style optimization on the UDT (no covariance)
//   udt-ekf  EKF on the UDT
//   pf       AMCL-style particle filter (likelihood field)
// and their errors against the ground truth, ANEES and timings are tabulated and plotted.
// The machinery (the localizers' runs, their metrics, the table and the figures) is declared in
// turtlebot_study.hpp.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "turtlebot_study.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace {

using namespace vdtnav;
using turtlebot_study::Metrics;
using turtlebot_study::Trace;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Table 3.3 study: VDT and UDT optimization and EKF localizers and a particle filter on a "
      "simulated LiDAR run"};
  std::string out = "out/turtlebot_lidar", map_path, size_text, noise_name = "sigma";
  unsigned seed = 1;
  int repeat = 1, scans = 2000;
  double resolution = 0.05;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the simulated run (and of the generated plan)")
      ->capture_default_str();
  app.add_option("--repeat", repeat, "runs with seeds seed, seed+1, ...: mean +- std over them")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--map", map_path, "floor-plan bitmap (dark = occupied); default: generated plan");
  app.add_option("--size", size_text, "world size of --map as WxH metres, e.g. 40x18");
  app.add_option("--scans", scans, "scans per run (>= 2)")
      ->capture_default_str()
      ->check(CLI::Range(2, 1000000));
  app.add_option("--resolution", resolution, "map cell size, metres")->capture_default_str();
  app.add_option("--noise", noise_name, "Table 3.2 read as 'sigma' (default) or 'variance'")
      ->check(CLI::IsMember({"sigma", "variance"}));
  CLI11_PARSE(app, argc, argv);

  try {
    std::filesystem::create_directories(out);
    // ---------------------------------------------------------------- map and route
    OccupancyGrid<2> occ;
    std::vector<Eigen::Vector2d> path;
    std::string name;
    if (map_path.empty()) {
      sim::FloorPlanOptions o;
      o.seed = seed;
      o.resolution = resolution;
      const auto plan = sim::generate_floor_plan(o);
      occ = plan.occupancy;
      path = plan.tour;
      name = "generated floor plan";
    } else {
      double w = 0, h = 0;
      if (std::sscanf(size_text.c_str(), "%lfx%lf", &w, &h) != 2 || w <= 0 || h <= 0) {
        std::fprintf(stderr, "error: --map needs --size WxH in metres (e.g. 40x18), got '%s'\n",
                     size_text.c_str());
        return 2;
      }
      occ = load_occupancy_image(map_path, Eigen::Vector2d(w, h), resolution);
      std::printf("[map] planning a tour through %s\n", map_path.c_str());
      path = sim::plan_tour(occ, 12, 0.5, seed);
      name = std::filesystem::path(map_path).filename().string();
    }
    std::printf("[map] %s: %d x %d cells of %.3f m\n", name.c_str(), occ.size().x(), occ.size().y(),
                resolution);
    const VdtMap2 vdt = VdtMap2::build(occ);
    const sim::NoiseProfile noise = noise_name == "variance"
                                        ? sim::NoiseProfile::table_3_2_variance()
                                        : sim::NoiseProfile::table_3_2_sigma();
    const std::vector<std::string> methods = {"vdt-opt", "vdt-ekf", "udt-opt", "udt-ekf", "pf"};
    std::vector<std::vector<Metrics>> per_method(methods.size());
    std::vector<Trace> first_traces;
    sim::SimulatedRun first_run;

    for (int r = 0; r < repeat; ++r) {
      const std::uint32_t run_seed = seed + static_cast<std::uint32_t>(r);
      std::printf("[run %d/%d] simulating %d scans (seed %u)\n", r + 1, repeat, scans, run_seed);
      sim::TrajectoryOptions topt;
      topt.min_steps = scans;
      auto trajectory = sim::follow_path(path, occ, topt);
      trajectory.resize(std::min<std::size_t>(trajectory.size(), static_cast<std::size_t>(scans)));
      const sim::SimulatedRun run =
          sim::simulate_run(occ, trajectory, sim::LidarOptions{}, noise, run_seed);
      const std::vector<Trace> traces =
          turtlebot_study::run_localizers(vdt, occ, noise, methods, run, run_seed, per_method);
      if (r == 0) {
        first_traces = traces;
        first_run = run;
      }
    }

    turtlebot_study::write_tables(out, methods, per_method);
    turtlebot_study::draw_figures(out, name, occ, resolution, vdt, methods, first_run,
                                  first_traces);
    std::printf(
        "[done] %s/table.csv, table.md, trajectory.png, errors_vdt_opt.png, errors_vdt_ekf.png, "
        "vcd_landscape.png\n",
        out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
