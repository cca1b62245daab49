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

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/active_beam.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/map/surface_roughness.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"
#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/plot.hpp"

using namespace vdtnav;
using Eigen::Vector2d;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A dataset: the world (also the map: thin walls through its occupied cells' centres), the drive,
/// the sensor.
struct Dataset {
  std::string name;
  OccupancyGrid<2> world;
  std::vector<sim::TimedPose> drive;
  RotatingBeamOptions beam;
  double map_sigma = -1.0;  ///< the EKF's per-reading map floor
};

/// Odometry of the drive with Table 3.2's noise read as sigmas (sim/lidar_simulator.hpp).
std::vector<OdometryStep> odometry(const std::vector<sim::TimedPose>& drive, std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<OdometryStep> out(drive.size());
  for (std::size_t k = 1; k < drive.size(); ++k) {
    OdometryStep& o = out[k];
    o.dt = drive[k].t - drive[k - 1].t;
    o.v = drive[k].v + 0.05 * n01(rng);
    o.w = drive[k].w + 0.01 * n01(rng);
    o.delta = sim::unicycle_increment(o.v, o.w, o.dt);
  }
  return out;
}

struct Run {
  BeamStrategy strategy;
  std::vector<double> t, ex, ey, ephi, sx, sy, sphi, bearing, goal;
  std::vector<Pose2> estimate;
  double rmse_x = 0, rmse_y = 0, rmse_phi = 0, lost_pct = 0, ms_select = 0;
  eval::AneesResult anees;
  int selections = 0;
  int gated = 0;  ///< readings refused by the ray-cast gate
};

Run localize(const Dataset& ds, const VdtMap2& map, BeamStrategy strategy,
             const std::vector<OdometryStep>& odo, std::uint32_t seed) {
  Run run;
  run.strategy = strategy;
  VdtEkfOptions eo;
  eo.min_inliers = 1;                  // one reading per step
  eo.search.enabled = false;           // no window search on one reading
  eo.sensor.map_sigma = ds.map_sigma;  // the map's measured roughness (surface_roughness.hpp)
  const ActiveBeamSelector selector(map, ds.beam, eo.sensor);
  RotatingBeamController beam(ds.beam, strategy);
  VdtEkfLocalizer ekf(map, eo);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
  ekf.reset(ds.drive.front().pose, p0);
  std::mt19937_64 rng(seed);  // the same range noise for every strategy
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<double> nees;
  double se_x = 0, se_y = 0, se_phi = 0, select_ms = 0;
  int lost = 0;
  Eigen::Matrix3d last_cov = p0;
  for (std::size_t k = 0; k < ds.drive.size(); ++k) {
    if (k > 0) beam.advance(odo[k].dt);
    const Pose2& truth = ds.drive[k].pose;
    const double theta = beam.bearing();
    const double eps = n01(rng);
    ScanPoints pts;
    pts.sigma_range = ds.beam.sigma_range;
    pts.range_max = ds.beam.range_max;
    const Vector2d u(std::cos(truth[2] + theta), std::sin(truth[2] + theta));
    const double r0 = sim::cast_ray<2>(ds.world, truth.head<2>(), u, ds.beam.range_max,
                                       sim::RaySurface::kCellCentre);
    bool gated = false;
    if (k > 0 && std::isfinite(r0) && r0 >= ds.beam.range_min) {
      // Data association as ActiveBeamLocalizer does it: against the ray cast from the prediction.
      gated = !selector.consistent(compose(run.estimate.back(), odo[k].delta), last_cov, theta,
                                   r0 + ds.beam.sigma_range * eps);
      run.gated += gated ? 1 : 0;
    }
    if (!gated && std::isfinite(r0) && r0 >= ds.beam.range_min) {
      pts.add(Vector2d::Zero(), Vector2d(std::cos(theta), std::sin(theta)),
              r0 + ds.beam.sigma_range * eps, 0);
    }
    const LocalizationResult res = ekf.update(odo[k], pts);
    last_cov = res.covariance;
    const Eigen::Vector3d e = pose_error(res.pose, truth);
    se_x += e[0] * e[0];
    se_y += e[1] * e[1];
    se_phi += e[2] * e[2];
    if (e.head<2>().norm() > 0.5) ++lost;
    nees.push_back(eval::nees(res.pose, truth, res.covariance));
    run.t.push_back(ds.drive[k].t);
    run.ex.push_back(e[0]);
    run.ey.push_back(e[1]);
    run.ephi.push_back(e[2]);
    run.sx.push_back(std::sqrt(res.covariance(0, 0)));
    run.sy.push_back(std::sqrt(res.covariance(1, 1)));
    run.sphi.push_back(std::sqrt(res.covariance(2, 2)));
    run.bearing.push_back(theta);
    run.estimate.push_back(res.pose);
    if (beam.needs_goal()) {
      const auto t0 = Clock::now();
      const BeamSelection s =
          selector.select(res.pose, res.covariance, selector.segment_of(theta), strategy);
      select_ms += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      ++run.selections;
      beam.set_goal(s.segment, selector);
    }
    run.goal.push_back(beam.goal());
  }
  const double n = static_cast<double>(ds.drive.size());
  run.rmse_x = std::sqrt(se_x / n);
  run.rmse_y = std::sqrt(se_y / n);
  run.rmse_phi = std::sqrt(se_phi / n);
  run.lost_pct = 100.0 * lost / n;
  run.anees = eval::anees(nees, 3);
  run.ms_select = run.selections > 0 ? select_ms / run.selections : 0.0;
  return run;
}

Grid<std::uint8_t, 2> as_bytes(const OccupancyGrid<2>& g) {
  Grid<std::uint8_t, 2> out(g.size(), g.frame(), 0);
  for (int y = 0; y < g.size().y(); ++y) {
    for (int x = 0; x < g.size().x(); ++x) {
      out(Eigen::Vector2i(x, y)) = g(Eigen::Vector2i(x, y)) ? 1 : 0;
    }
  }
  return out;
}

void plots(const Dataset& ds, const std::vector<Run>& runs, const std::string& prefix) {
  const Vector2d lo = ds.world.frame().origin();
  const Vector2d hi = lo + ds.world.size().cast<double>() * ds.world.resolution();
  const viz::RgbImage background = viz::occupancy_image(as_bytes(ds.world));
  const std::vector<viz::Rgb> colours = {
      {213, 94, 0}, {0, 114, 178}, {0, 158, 115}, {204, 121, 167}, {230, 159, 0}};
  {  // Fig. 4.3: trajectories over the map.
    viz::Figure fig(1400, 1100, 1, 1);
    viz::Axes& ax = fig.axes(0, 0);
    ax.title(ds.name + ": trajectories (Fig. 4.3)")
        .image(background, lo.x(), hi.x(), lo.y(), hi.y());
    std::vector<double> tx, ty;
    for (const auto& tp : ds.drive) {
      tx.push_back(tp.pose.x());
      ty.push_back(tp.pose.y());
    }
    ax.line(tx, ty, viz::Style().with_color({0, 0, 0}).with_width(2.0).with_label("truth"));
    for (std::size_t m = 0; m < runs.size(); ++m) {
      std::vector<double> x, y;
      for (const auto& p : runs[m].estimate) {
        x.push_back(p.x());
        y.push_back(p.y());
      }
      ax.line(x, y,
              viz::Style()
                  .with_color(colours[m])
                  .with_width(1.0)
                  .with_label(to_string(runs[m].strategy)));
    }
    ax.equal_aspect().legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_trajectory.png");
  }
  {  // Fig. 4.4: active-trace's errors with +-2 sigma.
    const Run& r = runs.front();
    viz::Figure fig(1600, 1100, 3, 1);
    fig.title(ds.name + ": " + to_string(r.strategy) + " errors and +-2 sigma (Fig. 4.4)");
    const char* labels[3] = {"x error (m)", "y error (m)", "heading error (rad)"};
    for (int a = 0; a < 3; ++a) {
      const auto& e = a == 0 ? r.ex : a == 1 ? r.ey : r.ephi;
      const auto& s = a == 0 ? r.sx : a == 1 ? r.sy : r.sphi;
      std::vector<double> l(s.size()), h(s.size());
      for (std::size_t k = 0; k < s.size(); ++k) {
        l[k] = -2.0 * s[k];
        h[k] = 2.0 * s[k];
      }
      fig.axes(a, 0)
          .ylabel(labels[a])
          .xlabel("time (s)")
          .band(r.t, l, h, viz::Style().with_label("+-2 sigma"))
          .line(r.t, e, viz::Style().with_width(1.0).with_label("error"));
    }
    fig.axes(0, 0).legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_errors.png");
  }
  {  // The chosen segment and the beam's bearing over time.
    const Run& r = runs.front();
    viz::Figure fig(1600, 600, 1, 1);
    std::vector<double> deg(r.bearing.size());
    for (std::size_t k = 0; k < deg.size(); ++k) deg[k] = r.bearing[k] * 180.0 / kPi;
    fig.axes(0, 0)
        .title(ds.name + ": " + to_string(r.strategy) + ", the beam's bearing and goal segment")
        .xlabel("time (s)")
        .ylabel("bearing (deg) / goal segment")
        .line(r.t, deg, viz::Style().with_width(1.0).with_label("bearing (deg)"))
        .line(r.t, r.goal, viz::Style().with_color({213, 94, 0}).with_label("goal segment"))
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_segments.png");
  }
  {  // Figs. 4.5-4.7: a snapshot half way: pose, the sensor's range circle and the beam.
    const Run& r = runs.front();
    const std::size_t k = r.t.size() / 2;
    const Pose2 p = r.estimate[k];
    const double range = std::min(ds.beam.range_max, 6.0);
    viz::Figure fig(1100, 1000, 1, 1);
    viz::Axes& ax = fig.axes(0, 0);
    ax.title(ds.name + ": snapshot at t = " + std::to_string(static_cast<int>(r.t[k])) +
             " s (Figs. 4.5-4.7)")
        .image(background, lo.x(), hi.x(), lo.y(), hi.y());
    std::vector<double> cx, cy;
    for (int a = 0; a <= 90; ++a) {
      cx.push_back(p.x() + ds.beam.range_max * std::cos(a * 2 * kPi / 90));
      cy.push_back(p.y() + ds.beam.range_max * std::sin(a * 2 * kPi / 90));
    }
    const double b = p[2] + r.bearing[k];
    ax.line(cx, cy, viz::Style().with_color({0, 158, 115}).with_label("sensor range"))
        .line({p.x(), p.x() + ds.beam.range_max * std::cos(b)},
              {p.y(), p.y() + ds.beam.range_max * std::sin(b)},
              viz::Style().with_color({213, 94, 0}).with_width(2.0).with_label("beam"))
        .scatter({p.x()}, {p.y()},
                 viz::Style()
                     .with_color({0, 114, 178})
                     .with_marker(viz::Marker::kCircle, 10)
                     .with_label("estimated pose"))
        .xlim(p.x() - range - 1, p.x() + range + 1)
        .ylim(p.y() - range - 1, p.y() + range + 1)
        .equal_aspect()
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_snapshot.png");
  }
}

/// The planner's grid: unknown cells of a SLAM map blocked too (the robot drives where the map
/// saw free space).
OccupancyGrid<2> known_free(const RosMap& m) {
  OccupancyGrid<2> g(m.cells.size(), m.cells.frame(), 0);
  for (int y = 0; y < g.size().y(); ++y) {
    for (int x = 0; x < g.size().x(); ++x) {
      const int v = m.cells(Eigen::Vector2i(x, y));
      g(Eigen::Vector2i(x, y)) = (v < 0 || v >= 65) ? 1 : 0;
    }
  }
  return g;
}

std::vector<sim::TimedPose> drive_through(const OccupancyGrid<2>& plan_grid, int waypoints,
                                          double minutes, std::uint32_t seed) {
  sim::TrajectoryOptions t;
  t.rate_hz = 40.0;
  t.min_steps = static_cast<int>(minutes * 60.0 * t.rate_hz);
  const std::vector<Vector2d> path = sim::plan_tour(plan_grid, waypoints, 0.5, seed);
  std::vector<sim::TimedPose> drive = sim::follow_path(path, plan_grid, t);
  if (drive.size() > static_cast<std::size_t>(t.min_steps)) drive.resize(t.min_steps);
  return drive;
}

}  // namespace

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
    std::vector<Dataset> datasets;
    {
      Dataset d;
      d.beam = RotatingBeamOptions::table_4_1();
      const std::string willow = data + "/ros-maps/willow-garage/willow-full.pgm";
      if (!data.empty() && std::filesystem::exists(willow)) {
        d.name = "dataset1 (Willow Garage)";
        d.world = load_occupancy_image(willow, Vector2d(54.0, 58.7), 0.1);
      } else {
        sim::FloorPlanOptions o;
        o.seed = seed;
        d.name = "dataset1 (generated floor plan)";
        d.world = sim::generate_floor_plan(o).occupancy;
      }
      d.drive = drive_through(d.world, 4, minutes, seed);
      datasets.push_back(std::move(d));
    }
    {
      Dataset d;
      d.beam = RotatingBeamOptions::table_4_3();
      const std::string office = data + "/ros-maps/fetch-office/4_26_15.yaml";
      if (!data.empty() && std::filesystem::exists(office)) {
        const RosMap m = load_ros_map(office);
        d.name = "dataset2 (fetch office)";
        d.world = occupancy(m);
        d.drive = drive_through(known_free(m), 4, minutes, seed + 1);
      } else {
        sim::FloorPlanOptions o;
        o.seed = seed + 1;
        d.name = "dataset2 (generated floor plan)";
        d.world = sim::generate_floor_plan(o).occupancy;
        d.drive = drive_through(d.world, 4, minutes, seed + 1);
      }
      datasets.push_back(std::move(d));
    }

    std::ofstream csv(out + "/table.csv");
    csv << "dataset,strategy,steps,rmse_x_m,rmse_y_m,rmse_phi_rad,anees,anees_lo,anees_hi,"
           "lost_pct,ms_select,anees_left_out\n";
    std::ofstream md(out + "/table.md");
    md << "| dataset | strategy | steps | RMSE x (m) | RMSE y (m) | RMSE phi (rad) | ANEES [95 %] "
          "| "
          "lost % | ms/selection |\n|---|---|---|---|---|---|---|---|---|\n";
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
        const std::string dataset = d == 0 ? "dataset1" : "dataset2";
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%zu,%.5f,%.5f,%.6f,%.3f,%.3f,%.3f,%.2f,%.4f,%zu\n",
                      dataset.c_str(), to_string(s), ds.drive.size(), r.rmse_x, r.rmse_y,
                      r.rmse_phi, r.anees.anees, r.anees.interval.lower, r.anees.interval.upper,
                      r.lost_pct, r.ms_select, ds.drive.size() - r.anees.count);
        const std::string note = eval::left_out_note(r.anees, ds.drive.size());
        csv << line;
        std::snprintf(
            line, sizeof line,
            "| %s | %s | %zu | %.4f | %.4f | %.5f | %.2f [%.2f, %.2f]%s | %.1f | %.3f |\n",
            ds.name.c_str(), to_string(s), ds.drive.size(), r.rmse_x, r.rmse_y, r.rmse_phi,
            r.anees.anees, r.anees.interval.lower, r.anees.interval.upper,
            note.empty() ? "" : (" (" + note + ")").c_str(), r.lost_pct, r.ms_select);
        md << line;
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
