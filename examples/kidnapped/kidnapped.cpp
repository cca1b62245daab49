// Global localization from one scan with no prior (estimation/global_localization.hpp): branch
// and bound against LaMa-style random sampling at the same time budget, on the generated floor
// plan (embedded default) and, with --data, the Player/Stage hospital section and the
// fetch-office SLAM map with simulated scans at random free poses, and the Intel lab's real scans
// at random times on a map built from its corrected poses.
//
// Success: accepted (converged) within 0.3 m and 0.1 rad of the true (corrected) pose. A trial
// refused as ambiguous whose candidates include the truth is counted apart as ambiguous (the
// building looks the same from elsewhere); an accepted wrong pose is counted as wrong.
// Writes table.csv (map,scans,method,trials,success_pct,median_s,p95_s), table.md (with the
// ambiguous and wrong counts), per map <map>_success.png (trial poses over the map, by outcome)
// and times.png (the time histogram).
//
// Then the kidnapped robot (kidnapping.hpp): vdt-opt and vdt-ekf, each inside its lost detection
// and recovery (make_localizer's default), track a drive — simulated on the three maps (10 Hz,
// Table 3.2 noise), the Intel log's real scans and raw odometry — teleported every --every scans,
// --kidnappings times. kidnap.csv (map,kidnappings,recovered_pct,scans_to_recover_median,
// wrong_accepted; vdt-opt): recovered_pct is the share recovered within 20 scans (the issue's
// target), the median over those recovered before the next teleport; kidnap.md has both methods,
// and <map>_kidnap.png vdt-opt's position error with the teleports and the lost scans.
//
// With --data, the false alarms of lost detection on the real logs (false_alarms.hpp):
// false_alarms.csv, false_alarms.md, <log>_agreement.png.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "false_alarms.hpp"
#include "kidnapping.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/viz/image.hpp"
#include "vdtnav/viz/plot.hpp"

using namespace vdtnav;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Case {
  std::string map, scans;  ///< map name; "simulated" or "real"
  unsigned id = 0;         ///< the map's place in the full list (seeds do not depend on --maps)
  OccupancyGrid<2> grid;
  std::vector<ScanPoints> observations;
  std::vector<Pose2> truth;
  kidnap::Drive drive;         ///< the drive for the kidnappings (simulated when empty)
  LocalizerSettings settings;  ///< the localizers' settings (log_settings() for real logs)
};

enum class Outcome { kSuccess, kAmbiguous, kRefused, kWrong };

struct Tally {
  std::vector<double> seconds;
  std::vector<Outcome> outcome;
  [[nodiscard]] int count(Outcome o) const {
    return static_cast<int>(std::count(outcome.begin(), outcome.end(), o));
  }
};

using kidnap::right;  // within 0.3 m and 0.1 rad (kidnapping.hpp)

Outcome judge(const GlobalLocalizationResult& r, const Pose2& truth) {
  if (r.result.status == LocalizationStatus::kConverged) {
    return right(r.result.pose, truth) ? Outcome::kSuccess : Outcome::kWrong;
  }
  if (r.ambiguous) {
    bool among = right(r.result.pose, truth);
    for (const Pose2& a : r.alternatives) among = among || right(a, truth);
    if (among) return Outcome::kAmbiguous;
  }
  return Outcome::kRefused;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

/// Random free poses at least `clearance` from the map, scans simulated there (UTM-30LX).
void simulate(Case& c, const VdtMap2& map, int trials, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, c.grid.size().x() - 1), y(0, c.grid.size().y() - 1);
  std::uniform_real_distribution<double> yaw(-kPi, kPi);
  std::vector<sim::TimedPose> poses;
  while (static_cast<int>(poses.size()) < trials) {
    const Eigen::Vector2i i(x(rng), y(rng));
    if (c.grid(i)) continue;
    const Eigen::Vector2d p = c.grid.cell_center(i);
    if (map.value(p).norm() < 0.3) continue;
    sim::TimedPose t;
    t.t = static_cast<double>(poses.size());
    t.pose = Pose2(p.x(), p.y(), yaw(rng));
    poses.push_back(t);
  }
  const sim::SimulatedRun run = sim::simulate_run(c.grid, poses, sim::LidarOptions{},
                                                  sim::NoiseProfile::table_3_2_sigma(), seed);
  for (std::size_t k = 0; k < run.size(); ++k) {
    c.observations.push_back(scan_points(run.scans[k]));
    c.truth.push_back(run.truth[k]);
  }
}

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

Grid<std::uint8_t, 2> as_bytes(const OccupancyGrid<2>& g) {
  Grid<std::uint8_t, 2> out(g.size(), g.frame(), 0);
  for (std::size_t k = 0; k < g.num_cells(); ++k) out[k] = g[k] ? 1 : 0;
  return out;
}

void success_map(const Case& c, const Tally& t, const std::string& path) {
  const Eigen::Vector2d lo = c.grid.frame().origin();
  const Eigen::Vector2d hi =
      lo + c.grid.size().cast<double>() * c.grid.resolution();  // axis-aligned maps here
  viz::Figure fig(1400, 1000, 1, 1);
  viz::Axes& ax = fig.axes(0, 0);
  ax.title(c.map + ": branch and bound from one scan, by outcome")
      .image(viz::occupancy_image(as_bytes(c.grid)), lo.x(), hi.x(), lo.y(), hi.y());
  const struct {
    Outcome o;
    const char* label;
    viz::Rgb colour;
  } kinds[] = {{Outcome::kSuccess, "success", {0, 158, 115}},
               {Outcome::kAmbiguous, "ambiguous (refused)", {230, 159, 0}},
               {Outcome::kRefused, "refused", {86, 180, 233}},
               {Outcome::kWrong, "wrong pose accepted", {213, 94, 0}}};
  for (const auto& k : kinds) {
    std::vector<double> xs, ys;
    for (std::size_t i = 0; i < t.outcome.size(); ++i) {
      if (t.outcome[i] != k.o) continue;
      xs.push_back(c.truth[i].x());
      ys.push_back(c.truth[i].y());
    }
    if (xs.empty()) continue;
    ax.scatter(
        xs, ys,
        viz::Style().with_color(k.colour).with_marker(viz::Marker::kCircle, 7).with_label(k.label));
  }
  ax.equal_aspect().legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Global localization from one scan: branch and bound against random sampling"};
  std::string out = "out/kidnapped", data;
  unsigned seed = 1;
  int trials = 40;
  kidnap::Options ko;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the poses and the noise")->capture_default_str();
  app.add_option("--data", data,
                 "real data folder (e.g. ../shared/data): the hospital section, fetch-office and "
                 "Intel lab; without it, the generated floor plan only");
  std::vector<std::string> only;
  app.add_option("--maps", only,
                 "run these maps only (generated, hospital-section, fetch-office, intel; "
                 "false-alarms: lost detection on the real logs)");
  app.add_option("--trials", trials, "scans per map")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--kidnappings", ko.kidnappings, "teleports per map (0: no kidnapping runs)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  app.add_option("--every", ko.every, "scans between teleports")
      ->capture_default_str()
      ->check(CLI::Range(ko.window + 1, 100000));
  CLI11_PARSE(app, argc, argv);
  ko.seed = seed;
  try {
    std::filesystem::create_directories(out);
    std::vector<Case> cases;
    {
      Case c;
      c.map = "generated";
      c.scans = "simulated";
      sim::FloorPlanOptions o;
      o.seed = seed;
      c.grid = sim::generate_floor_plan(o).occupancy;
      cases.push_back(std::move(c));
    }
    const std::string hospital = data + "/stage_maps/hospital_section.png";
    if (!data.empty() && std::filesystem::exists(hospital)) {
      Case c;
      c.map = "hospital-section";
      c.scans = "simulated";
      c.grid = load_occupancy_image(hospital, Eigen::Vector2d(40.0, 18.0), 0.05);
      cases.push_back(std::move(c));
    }
    const std::string office = data + "/ros-maps/fetch-office/4_26_15.yaml";
    if (!data.empty() && std::filesystem::exists(office)) {
      Case c;
      c.map = "fetch-office";
      c.scans = "simulated";
      c.grid = occupancy(load_ros_map(office));
      cases.push_back(std::move(c));
    }
    const std::string intel = data + "/intel-lab/intel.gfs.log.gz";
    if (!data.empty() && std::filesystem::exists(intel)) {
      // The map from every corrected scan; trials: scans at random times, truth the corrected pose.
      const CarmenLog log = load_carmen_log(intel);
      std::vector<Pose2> poses;
      std::vector<LaserScan> scans;
      for (const auto& l : log.lasers) {
        poses.push_back(l.pose);
        scans.push_back(l.scan);
      }
      Case c;
      c.map = "intel";
      c.scans = "real";
      c.grid = mapping::build_occupancy_map(poses, scans, {}).occupancy;
      c.settings = log_settings();
      // The drive: the log's scans with the raw odometry of the table joined to it.
      const std::string table = data + "/intel-lab/intel_910_odom_vs_corrected.txt";
      const JoinedLogs logs = join_odometry_table(log, load_odometry_table(table), table);
      std::vector<std::size_t> all(logs.raw.lasers.size());
      std::vector<double> times;
      for (std::size_t i = 0; i < all.size(); ++i) {
        all[i] = i;
        times.push_back(logs.raw.lasers[i].time);
      }
      c.drive.odometry = odometry_steps(times, log_odometry(logs.raw, all).poses);
      for (std::size_t i = 0; i < all.size(); ++i) {
        LaserScan scan = logs.raw.lasers[i].scan;
        scan.sigma_range = 0.02;  // as the Intel study and `vdtnav localize`
        c.drive.scans.push_back(scan_points(scan));
        c.drive.truth.push_back(logs.corrected.lasers[i].pose);
      }
      std::mt19937 rng(seed);
      std::uniform_int_distribution<std::size_t> pick(0, log.lasers.size() - 1);
      for (int k = 0; k < trials; ++k) {
        const std::size_t i = pick(rng);
        c.observations.push_back(scan_points(log.lasers[i].scan));
        c.truth.push_back(log.lasers[i].pose);
      }
      cases.push_back(std::move(c));
    }

    for (std::size_t i = 0; i < cases.size(); ++i) cases[i].id = static_cast<unsigned>(i);
    if (!only.empty()) {
      cases.erase(std::remove_if(cases.begin(), cases.end(),
                                 [&](const Case& c) {
                                   return std::find(only.begin(), only.end(), c.map) == only.end();
                                 }),
                  cases.end());
    }
    std::ofstream csv(out + "/table.csv");
    csv << "map,scans,method,trials,success_pct,median_s,p95_s\n";
    std::ofstream md(out + "/table.md");
    md << "| map | scans | method | trials | success % | ambiguous | refused | wrong accepted | "
          "success % outside ambiguous | median s | p95 s |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::ofstream kcsv(out + "/kidnap.csv");
    kcsv << "map,kidnappings,recovered_pct,scans_to_recover_median,wrong_accepted\n";
    std::ofstream kmd(out + "/kidnap.md");
    kmd << "| map | method | kidnappings | recovered within " << ko.within
        << " scans % | in ambiguous or featureless places | recovered within " << ko.within
        << " outside them % | recovered before the next % | scans to recover (median) | wrong "
           "accepted | "
           "converged elsewhere before the window (scans) | converged off 0.3 m / 0.1 rad after "
           "recovery (scans) | lost scans | global searches | s |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    const int rows = std::max(1, static_cast<int>(cases.size()));
    viz::Figure hist(1400, 500 * rows, rows, 1);
    for (std::size_t m = 0; m < cases.size(); ++m) {
      Case& c = cases[m];
      const VdtMap2 map = VdtMap2::build(c.grid);
      if (c.observations.empty()) simulate(c, map, trials, seed * 7919u + c.id);
      const GlobalLocalizer loc(map, c.grid);
      std::printf("[%s] %zu x %zu cells of %.3f m, %zu %s scans\n", c.map.c_str(),
                  static_cast<std::size_t>(c.grid.size().x()),
                  static_cast<std::size_t>(c.grid.size().y()), c.grid.resolution(),
                  c.observations.size(), c.scans.c_str());
      std::fflush(stdout);
      Tally bb, rs;
      for (std::size_t k = 0; k < c.observations.size(); ++k) {
        const GlobalLocalizationResult a = loc.localize(c.observations[k]);
        bb.seconds.push_back(a.seconds);
        bb.outcome.push_back(judge(a, c.truth[k]));
        // Random sampling with the time branch and bound took on this scan.
        const GlobalLocalizationResult b =
            loc.localize_random(c.observations[k], a.seconds, seed + static_cast<unsigned>(k));
        rs.seconds.push_back(b.seconds);
        rs.outcome.push_back(judge(b, c.truth[k]));
      }
      for (const auto& [name, t] : {std::pair<const char*, const Tally&>{"branch-and-bound", bb},
                                    std::pair<const char*, const Tally&>{"random-sampling", rs}}) {
        const int n = static_cast<int>(t.outcome.size());
        const int ok = t.count(Outcome::kSuccess), amb = t.count(Outcome::kAmbiguous);
        const double pct = 100.0 * ok / n;
        const double pct_clear = n > amb ? 100.0 * ok / (n - amb) : 0.0;
        char line[512];
        std::snprintf(line, sizeof line, "%s,%s,%s,%d,%.1f,%.4f,%.4f\n", c.map.c_str(),
                      c.scans.c_str(), name, n, pct, quantile(t.seconds, 0.5),
                      quantile(t.seconds, 0.95));
        csv << line;
        std::snprintf(line, sizeof line,
                      "| %s | %s | %s | %d | %.1f | %d | %d | %d | %.1f | %.3f | %.3f |\n",
                      c.map.c_str(), c.scans.c_str(), name, n, pct, amb, t.count(Outcome::kRefused),
                      t.count(Outcome::kWrong), pct_clear, quantile(t.seconds, 0.5),
                      quantile(t.seconds, 0.95));
        md << line;
        std::printf(
            "  %-16s success %.1f %% (%.1f %% outside %d ambiguous), %d refused, %d wrong "
            "accepted; median %.3f s, p95 %.3f s\n",
            name, pct, pct_clear, amb, t.count(Outcome::kRefused), t.count(Outcome::kWrong),
            quantile(t.seconds, 0.5), quantile(t.seconds, 0.95));
        std::fflush(stdout);
      }
      success_map(c, bb, out + "/" + c.map + "_success.png");
      std::vector<double> centres, counts;
      const double top = std::max(quantile(bb.seconds, 1.0), 1e-3);
      const int bins = 20;
      for (int b = 0; b < bins; ++b) {
        centres.push_back((b + 0.5) * top / bins);
        counts.push_back(0.0);
      }
      for (double s : bb.seconds) {
        counts[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(s / top * bins)))] += 1;
      }
      if (ko.kidnappings > 0) {
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
          char line[512];
          if (std::string(method) == "vdt-opt") {
            std::snprintf(line, sizeof line, "%s,%d,%.1f,%.1f,%d\n", c.map.c_str(), n, pct, median,
                          wrong);
            kcsv << line;
            kidnap_figure(c.map + ": vdt-opt teleported every " + std::to_string(ko.every) +
                              " scans (grey lines)",
                          trace, out + "/" + c.map + "_kidnap.png");
          }
          std::snprintf(
              line, sizeof line,
              "| %s | %s | %d | %.1f | %d | %.1f | %.1f | %.1f | %d | %d | %d | %d | %d | "
              "%.1f |\n",
              c.map.c_str(), method, n, pct, ambiguous, pct_clear, pct_before, median, wrong, early,
              off, lost, searches, secs);
          kmd << line;
          std::printf(
              "  kidnapped %-8s %d teleports: %.1f %% recovered within %d scans (%.1f %% outside "
              "%d ambiguous or featureless places; %.1f %% before the next), median %.1f scans, %d "
              "wrong "
              "accepted, %d lost scans, %d global searches, %.1f s\n",
              method, n, pct, ko.within, pct_clear, ambiguous, pct_before, median, wrong, lost,
              searches, secs);
          std::fflush(stdout);
        }
      }
      hist.axes(static_cast<int>(m), 0)
          .title(c.map + ": branch-and-bound time per scan")
          .xlabel("seconds")
          .ylabel("scans")
          .line(centres, counts,
                viz::Style().with_marker(viz::Marker::kCircle, 6).with_label("branch-and-bound"));
    }
    if (!cases.empty()) hist.save_png(out + "/times.png");
    if (!data.empty() && (only.empty() || std::count(only.begin(), only.end(), "false-alarms"))) {
      std::printf("[false alarms] lost detection on the real logs (vdtnav localize's defaults)\n");
      if (false_alarms::run(data, out) > 0) {
        std::printf("[done] %s/false_alarms.csv, false_alarms.md, *_agreement.png\n", out.c_str());
      }
    }
    std::printf("[done] %s/table.csv\n", out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
