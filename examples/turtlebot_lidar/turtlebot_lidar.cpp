// vdtnav_turtlebot_lidar: the thesis's Table 3.3 study (Dataset 1, section 3.4.1). A robot with a
// Hokuyo UTM-30LX-like LiDAR (270 degrees, 0.25 degrees, 0.1-30 m) drives through a floor plan;
// five localizers run side by side on the same simulated scans and odometry:
//   vdt-opt  optimization on the VDT (Algorithm 1) with implicit-function covariance
//   vdt-ekf  EKF on the VDT
//   udt-opt  C-LOG-style optimization on the UDT (no covariance)
//   udt-ekf  EKF on the UDT
//   pf       AMCL-style particle filter (likelihood field)
// and their errors against the ground truth, ANEES and timings are tabulated and plotted.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "vdtnav/estimation/particle_filter.hpp"
#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"
#include "vdtnav/viz/viz.hpp"

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

struct Trace {  // one method on one run
  std::vector<Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  std::vector<char> has_cov;
  std::vector<double> ms;
};

struct Metrics {
  double pos_mae = 0, pos_mae_std = 0, ori_mae = 0, ori_mae_std = 0;
  double pos_mse = 0, pos_mse_std = 0, ori_mse = 0, ori_mse_std = 0;
  bool has_cov = false;
  double anees = 0, anees_lo = 0, anees_hi = 0, lost_pct = 0, ms_mean = 0, ms_max = 0;
};

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}
double stdev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / (v.size() - 1));
}

Metrics evaluate(const Trace& t, const sim::SimulatedRun& run) {
  Metrics m;
  std::vector<double> pe, oe, pe2, oe2, nees;
  int lost = 0;
  for (std::size_t k = 1; k < run.size(); ++k) {
    const Eigen::Vector3d e = pose_error(t.estimate[k], run.truth[k]);
    const double p = e.head<2>().norm(), o = std::abs(e[2]);
    pe.push_back(p);
    oe.push_back(o);
    pe2.push_back(p * p);
    oe2.push_back(o * o);
    lost += p > 0.5 ? 1 : 0;
    if (t.has_cov[k]) nees.push_back(e.dot(t.covariance[k].ldlt().solve(e)));
  }
  m.pos_mae = mean(pe), m.pos_mae_std = stdev(pe), m.ori_mae = mean(oe), m.ori_mae_std = stdev(oe);
  m.pos_mse = mean(pe2), m.pos_mse_std = stdev(pe2), m.ori_mse = mean(oe2),
  m.ori_mse_std = stdev(oe2);
  m.has_cov = nees.size() == pe.size();
  if (m.has_cov && !nees.empty()) {
    m.anees = mean(nees);
    const eval::ChiSquareInterval bounds = eval::anees_interval(nees.size(), 3, 0.95);
    m.anees_lo = bounds.lower;
    m.anees_hi = bounds.upper;
  }
  m.lost_pct = 100.0 * lost / static_cast<double>(pe.size());
  m.ms_mean = mean(t.ms);
  m.ms_max = t.ms.empty() ? 0.0 : *std::max_element(t.ms.begin(), t.ms.end());
  return m;
}

/// Mean over repeats; with one repeat the stds are over time (as in Table 3.3), with several
/// they are the std of the per-repeat means.
Metrics combine(const std::vector<Metrics>& r) {
  if (r.size() == 1) return r[0];
  Metrics m;
  auto col = [&](double Metrics::*f) {
    std::vector<double> v;
    for (const auto& x : r) v.push_back(x.*f);
    return v;
  };
  m.pos_mae = mean(col(&Metrics::pos_mae)), m.pos_mae_std = stdev(col(&Metrics::pos_mae));
  m.ori_mae = mean(col(&Metrics::ori_mae)), m.ori_mae_std = stdev(col(&Metrics::ori_mae));
  m.pos_mse = mean(col(&Metrics::pos_mse)), m.pos_mse_std = stdev(col(&Metrics::pos_mse));
  m.ori_mse = mean(col(&Metrics::ori_mse)), m.ori_mse_std = stdev(col(&Metrics::ori_mse));
  m.has_cov = r[0].has_cov;
  m.anees = mean(col(&Metrics::anees)), m.anees_lo = mean(col(&Metrics::anees_lo));
  m.anees_hi = mean(col(&Metrics::anees_hi)), m.lost_pct = mean(col(&Metrics::lost_pct));
  m.ms_mean = mean(col(&Metrics::ms_mean));
  const auto mx = col(&Metrics::ms_max);
  m.ms_max = *std::max_element(mx.begin(), mx.end());
  return m;
}

void progress(const std::string& what, std::size_t done, std::size_t total) {
  const int width = 30, filled = static_cast<int>(width * done / std::max<std::size_t>(total, 1));
  std::printf("\r  %-8s [%s%s] %3zu%%", what.c_str(), std::string(filled, '#').c_str(),
              std::string(width - filled, '.').c_str(),
              100 * done / std::max<std::size_t>(total, 1));
  std::fflush(stdout);
}

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

      const Eigen::Matrix3d p0 =
          Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
      std::vector<std::unique_ptr<Localizer2D>> locs;
      VdtEkfOptions eo;
      eo.noise.sigma_v = noise.sigma_v;
      eo.noise.sigma_w = noise.sigma_w;
      UdtOptions uo;
      uo.noise = eo.noise;
      ParticleFilterOptions po;
      po.seed = run_seed;
      locs.push_back(std::make_unique<VdtOptimizationLocalizer>(vdt));
      locs.push_back(std::make_unique<VdtEkfLocalizer>(vdt, eo));
      locs.push_back(std::make_unique<UdtOptimizationLocalizer>(occ, uo));
      locs.push_back(std::make_unique<UdtEkfLocalizer>(occ, uo));
      locs.push_back(std::make_unique<ParticleFilterLocalizer>(occ, po));
      std::vector<Trace> traces(methods.size());
      for (std::size_t m = 0; m < locs.size(); ++m) {
        Trace& t = traces[m];
        locs[m]->reset(run.truth[0], p0);
        t.estimate.assign(1, run.truth[0]);
        t.covariance.assign(1, p0);
        t.has_cov.assign(1, 1);
        for (std::size_t k = 1; k < run.size(); ++k) {
          const auto t0 = Clock::now();
          const LocalizationResult res = locs[m]->update(run.odometry[k], run.scans[k]);
          t.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
          t.estimate.push_back(res.pose);
          t.covariance.push_back(res.covariance);
          t.has_cov.push_back(res.has_covariance ? 1 : 0);
          if (k % 50 == 0 || k + 1 == run.size()) progress(methods[m], k + 1, run.size());
        }
        std::printf("\n");
        per_method[m].push_back(evaluate(t, run));
      }
      if (r == 0) {
        first_traces = traces;
        first_run = run;
      }
    }

    // ---------------------------------------------------------------- table
    std::ofstream csv(out + "/table.csv");
    csv << "method,pos_mae_m,pos_mae_std_m,ori_mae_rad,ori_mae_std_rad,pos_mse_m2,pos_mse_std_m2,"
           "ori_mse_rad2,"
           "ori_mse_std_rad2,has_cov,anees,anees_lo,anees_hi,lost_pct,ms_mean,ms_max\n";
    std::ofstream md(out + "/table.md");
    md << "| method | position MAE (m) | orientation MAE (rad) | position MSE (m^2 x 1e-3) | "
          "orientation MSE "
          "(rad^2 x 1e-3) | P_k | ANEES [95 % interval] | lost % | ms mean | ms max |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    std::printf("\n%-8s %18s %18s %8s %22s %7s %8s %8s\n", "method", "pos MAE (m)", "ori MAE (rad)",
                "P_k", "ANEES [95%]", "lost%", "ms mean", "ms max");
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const Metrics x = combine(per_method[m]);
      char line[512];
      std::snprintf(line, sizeof line,
                    "%s,%.6f,%.6f,%.6f,%.6f,%.8f,%.8f,%.8f,%.8f,%d,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f\n",
                    methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std,
                    x.pos_mse, x.pos_mse_std, x.ori_mse, x.ori_mse_std, x.has_cov ? 1 : 0, x.anees,
                    x.anees_lo, x.anees_hi, x.lost_pct, x.ms_mean, x.ms_max);
      csv << line;
      std::snprintf(line, sizeof line,
                    "| %s | %.4f ± %.4f | %.4f ± %.4f | %.4f ± %.4f | %.4f ± %.4f | %s | %s | %.2f "
                    "| %.3f | %.3f |\n",
                    methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std,
                    1e3 * x.pos_mse, 1e3 * x.pos_mse_std, 1e3 * x.ori_mse, 1e3 * x.ori_mse_std,
                    x.has_cov ? "✓" : "✗",
                    x.has_cov ? (std::to_string(x.anees).substr(0, 5) + " [" +
                                 std::to_string(x.anees_lo).substr(0, 4) + ", " +
                                 std::to_string(x.anees_hi).substr(0, 4) + "]")
                                    .c_str()
                              : "—",
                    x.lost_pct, x.ms_mean, x.ms_max);
      md << line;
      std::printf("%-8s %8.4f ± %7.4f %8.4f ± %7.4f %8s %8.3f [%.2f,%.2f] %7.2f %8.3f %8.3f\n",
                  methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std,
                  x.has_cov ? "yes" : "no", x.anees, x.anees_lo, x.anees_hi, x.lost_pct, x.ms_mean,
                  x.ms_max);
    }

    // ---------------------------------------------------------------- figures
    std::printf("\n[figures] writing PNGs to %s\n", out.c_str());
    const double w_m = occ.size().x() * resolution, h_m = occ.size().y() * resolution;
    const auto& run = first_run;
    {  // Fig. 3.3: trajectory with every 15th estimate
      viz::Figure fig(1600,
                      static_cast<int>(std::clamp(1600.0 * h_m / w_m, 500.0, 1400.0)) * 2 / 2 + 100,
                      1, 1);
      fig.title("Trajectory (" + name + "): ground truth and every 15th estimate");
      auto& ax = fig.axes();
      ax.image(viz::occupancy_image(occ), 0, w_m, 0, h_m)
          .equal_aspect()
          .xlabel("x [m]")
          .ylabel("y [m]");
      std::vector<double> tx, ty;
      for (const auto& p : run.truth) tx.push_back(p[0]), ty.push_back(p[1]);
      ax.line(tx, ty,
              viz::Style().with_color({0, 0, 0}).with_width(1.5).with_label("ground truth"));
      for (int m : {0, 1}) {
        std::vector<double> ex, ey;
        for (std::size_t k = 0; k < first_traces[m].estimate.size(); k += 15)
          ex.push_back(first_traces[m].estimate[k][0]),
              ey.push_back(first_traces[m].estimate[k][1]);
        ax.scatter(ex, ey,
                   viz::Style()
                       .with_color(viz::kColorCycle[m == 0 ? 0 : 1])
                       .with_marker(m == 0 ? viz::Marker::kCircle : viz::Marker::kCross, 6)
                       .with_label(methods[m]));
      }
      fig.save_png(out + "/trajectory.png");
    }
    for (int m : {0, 1}) {  // Figs. 3.4 / 3.5: errors with +-2 sigma
      viz::Figure fig(1600, 1000, 3, 1);
      fig.title(methods[m] + ": error of each pose component with its 2-sigma band");
      const char* comp[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
      for (int c = 0; c < 3; ++c) {
        std::vector<double> t, e, lo, hi;
        for (std::size_t k = 1; k < run.size(); ++k) {
          const Eigen::Vector3d err = pose_error(first_traces[m].estimate[k], run.truth[k]);
          const double s = first_traces[m].has_cov[k]
                               ? 2.0 * std::sqrt(std::max(0.0, first_traces[m].covariance[k](c, c)))
                               : 0.0;
          t.push_back(run.times[k]);
          e.push_back(err[c]);
          lo.push_back(-s);
          hi.push_back(s);
        }
        auto& ax = fig.axes(c, 0);
        ax.band(t, lo, hi, viz::Style().with_label("+-2 sigma"))
            .line(t, e, viz::Style().with_width(1.2).with_label("error"))
            .ylabel(comp[c]);
        if (c == 2) ax.xlabel("time [s]");
      }
      fig.save_png(out + "/errors_" + std::string(m == 0 ? "vdt_opt" : "vdt_ekf") + ".png");
    }
    {  // Figs. 3.1 / 3.2: d_VCD around the true pose
      const std::size_t k = run.size() / 3;
      const Pose2 truth = run.truth[k];
      const ScanPoints pts = scan_points(run.scans[k]);
      VdtSensorModelOptions so;
      so.gate_mode = GateMode::kNone;
      const VdtSensorModel model(vdt, so);
      const int n = 61;
      const double span = 0.3;
      Grid<float, 2> land(Eigen::Vector2i(n, n),
                          GridFrame<2>(2 * span / n, Eigen::Vector2d(-span, -span)));
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Eigen::Vector2d d = land.cell_center(Eigen::Vector2i(i, j));
          land(Eigen::Vector2i(i, j)) = static_cast<float>(
              model.vector_chamfer_distance(truth + Pose2(d.x(), d.y(), 0.0), pts));
        }
      std::vector<double> a, v;
      for (int i = -60; i <= 60; ++i) {
        a.push_back(i * 0.002);
        v.push_back(model.vector_chamfer_distance(truth + Pose2(0.0, 0.0, i * 0.002), pts));
      }
      const auto range = viz::finite_range(land);
      viz::Figure fig(1600, 700, 1, 2);
      fig.font_scale(2);
      fig.title("d_VCD around the true pose (scan " + std::to_string(k) + ")");
      fig.axes(0, 0)
          .image(viz::heatmap(land, viz::Colormap::kViridis, range.first, range.second), -span,
                 span, -span, span)
          .equal_aspect()
          .colorbar(viz::Colormap::kViridis, range.first, range.second, "d_VCD [m^2]")
          .title("position offset, yaw at truth (Fig. 3.1)")
          .xlabel("dx [m]")
          .ylabel("dy [m]");
      fig.axes(0, 1)
          .line(a, v, viz::Style().with_width(2))
          .title("yaw offset, position at truth (Fig. 3.2)")
          .xlabel("dyaw [rad]")
          .ylabel("d_VCD [m^2]");
      fig.save_png(out + "/vcd_landscape.png");
    }
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
