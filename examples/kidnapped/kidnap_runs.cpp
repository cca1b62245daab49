// The kidnapped robot on one map: vdt-opt and vdt-ekf, each inside its lost detection and
// recovery, track the map's drive teleported every --every scans (kidnapping.hpp); the kidnap
// table rows and vdt-opt's error figure.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "kidnapped_study.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;

namespace {

/// A drive through the map for the kidnappings: a tour of its rooms at 10 Hz (UTM-30LX, Table 3.2
/// noise), at least `scans` long.
kidnap::Drive simulate_drive(const OccupancyGrid<2>& grid, int scans, std::uint32_t seed) {
  sim::TrajectoryOptions t;
  t.rate_hz = 10.0;
  t.min_steps = scans;
  const std::vector<Eigen::Vector2d> path = sim::plan_tour(grid, 6, 0.5, seed);
  const sim::SimulatedRun run =
      sim::simulate_run(grid, sim::follow_path(path, grid, t), sim::LidarOptions{},
                        sim::NoiseProfile::table_3_2_sigma(), seed);
  kidnap::Drive d;
  for (std::size_t k = 0; k < run.size(); ++k) {
    d.scans.push_back(scan_points(run.scans[k]));
    d.odometry.push_back(run.odometry[k]);
    d.truth.push_back(run.truth[k]);
  }
  return d;
}

void kidnap_figure(const std::string& title, const kidnap::Trace& t, const std::string& path) {
  viz::Figure fig(1400, 500, 1, 1);
  viz::Axes& ax = fig.axes(0, 0);
  std::vector<double> k, e, lk, le;
  for (std::size_t i = 0; i < t.error.size(); ++i) {
    const double err = std::min(t.error[i], 10.0);
    k.push_back(static_cast<double>(i));
    e.push_back(err);
    if (t.status[i] == LocalizationStatus::kLost) {
      lk.push_back(static_cast<double>(i));
      le.push_back(err);
    }
  }
  ax.title(title).xlabel("scan").ylabel("position error, m (clipped at 10)");
  for (int i : t.teleports) {
    ax.vline(i, viz::Style().with_color({150, 150, 150}));
  }
  ax.line(k, e, viz::Style().with_color({0, 114, 178}).with_label("vdt-opt error"));
  if (!lk.empty()) {
    ax.scatter(lk, le,
               viz::Style()
                   .with_color({213, 94, 0})
                   .with_marker(viz::Marker::kCircle, 4)
                   .with_label("status lost"));
  }
  ax.legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

}  // namespace

void kidnap_runs(Case& c, const VdtMap2& map, const kidnap::Options& ko, unsigned seed,
                 const std::string& out, std::ofstream& kcsv, std::ofstream& kmd) {
  if (c.drive.scans.empty()) {
    c.drive = simulate_drive(c.grid, std::max(3000, 2 * ko.every), seed * 104729u + c.id);
  }
  for (const char* method : {"vdt-opt", "vdt-ekf"}) {
    const auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Localizer2D> loc = make_localizer(method, map, c.grid, c.settings);
    kidnap::Trace trace;
    const std::vector<kidnap::Outcome> o = kidnap::run(c.drive, *loc, ko, &trace);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    int within = 0, before = 0, wrong = 0, early = 0, off = 0, lost = 0, searches = 0;
    int ambiguous = 0;  // not recovered in time, refused as ambiguous with the truth among
    std::vector<double> to_recover;
    for (const kidnap::Outcome& x : o) {
      const bool in_time = x.scans_to_recover >= 0 && x.scans_to_recover <= ko.within;
      within += in_time;
      ambiguous += !in_time && x.unrecognizable;
      before += x.scans_to_recover >= 0;
      if (x.scans_to_recover >= 0) to_recover.push_back(x.scans_to_recover);
      wrong += x.wrong_accepted;
      early += x.converged_wrong_early;
      off += x.converged_off;
      lost += x.lost_scans;
      searches += x.global_searches;
    }
    const int n = static_cast<int>(o.size());
    const double pct = 100.0 * within / n, pct_before = 100.0 * before / n;
    const double pct_clear = n > ambiguous ? 100.0 * within / (n - ambiguous) : 0.0;
    const double median = quantile(to_recover, 0.5);
    const eval::ErrorStatistics per_scan = eval::error_statistics(trace.ms);
    char line[512];
    if (std::string(method) == "vdt-opt") {
      std::snprintf(line, sizeof line, "%s,%d,%.1f,%.1f,%d,%.3f,%.3f,%.3f\n", c.map.c_str(), n, pct,
                    median, wrong, per_scan.median, per_scan.p99, per_scan.max);
      kcsv << line;
      kidnap_figure(
          c.map + ": vdt-opt teleported every " + std::to_string(ko.every) + " scans (grey lines)",
          trace, out + "/" + c.map + "_kidnap.png");
    }
    std::snprintf(line, sizeof line,
                  "| %s | %s | %d | %.1f | %d | %.1f | %.1f | %.1f | %d | %d | %d | %d | %d | "
                  "%.1f | %.3f, %.3f (%.3f) |\n",
                  c.map.c_str(), method, n, pct, ambiguous, pct_clear, pct_before, median, wrong,
                  early, off, lost, searches, secs, per_scan.median, per_scan.p99, per_scan.max);
    kmd << line;
    std::printf(
        "  kidnapped %-8s %d teleports: %.1f %% recovered within %d scans (%.1f %% outside "
        "%d ambiguous or featureless places; %.1f %% before the next), median %.1f scans, %d "
        "wrong "
        "accepted, %d lost scans, %d global searches, %.1f s; ms per scan median %.3f, p99 %.3f, "
        "max %.3f\n",
        method, n, pct, ko.within, pct_clear, ambiguous, pct_before, median, wrong, lost, searches,
        secs, per_scan.median, per_scan.p99, per_scan.max);
    std::fflush(stdout);
  }
}

}  // namespace study
