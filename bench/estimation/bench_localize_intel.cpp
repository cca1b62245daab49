// The whole real-log path: the Intel study's scans (the first two thirds of the Intel Research Lab
// log, raw odometry) through the vdt-opt localizer with the log settings, on the map drawn from
// the last third with the corrected poses (as examples/intel_lab). Reads ../shared/data in place;
// skipped with a message when it is absent.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"

namespace vdtnav {
namespace {

struct IntelStudy {
  std::string error;  ///< why the benchmark cannot run, empty when it can
  OccupancyGrid<2> occupancy;
  MapKnowledge knowledge;  ///< the map's unknown cells (what the last third did not see)
  std::unique_ptr<VdtMap2> vdt;
  std::vector<LaserScan> scans;
  std::vector<OdometryStep> steps;
  Pose2 start = Pose2::Zero();
  eval::Trajectory2 reference;
  std::vector<Relation> relations;
};

const IntelStudy& intel() {
  static const IntelStudy s = [] {
    IntelStudy s;
    const std::string dir = std::string(VDTNAV_DATA_DIR) + "/intel-lab/";
    if (!std::filesystem::exists(dir + "intel.gfs.log.gz")) {
      s.error = "Intel lab data not found in " + dir;
      return s;
    }
    try {
      const CarmenLog gfs = load_carmen_log(dir + "intel.gfs.log.gz");
      const std::string table = dir + "intel_910_odom_vs_corrected.txt";
      const JoinedLogs logs = join_odometry_table(gfs, load_odometry_table(table), table);
      const std::size_t n = logs.raw.lasers.size(), split = n - n / 3;
      std::vector<Pose2> map_poses;
      std::vector<LaserScan> map_scans;
      for (std::size_t i = split; i < n; ++i) {
        map_poses.push_back(logs.corrected.lasers[i].pose);
        map_scans.push_back(logs.corrected.lasers[i].scan);
      }
      const mapping::OccupancyMap map = mapping::build_occupancy_map(map_poses, map_scans, {});
      s.occupancy = map.occupancy;
      s.knowledge = MapKnowledge(map.cells);
      s.vdt = std::make_unique<VdtMap2>(VdtMap2::build(s.occupancy));
      std::vector<std::size_t> idx(split);
      std::vector<double> times;
      for (std::size_t i = 0; i < split; ++i) {
        idx[i] = i;
        times.push_back(logs.raw.lasers[i].time);
        s.scans.push_back(logs.raw.lasers[i].scan);
        s.reference.push_back({logs.raw.lasers[i].time, logs.corrected.lasers[i].pose});
      }
      s.steps = odometry_steps(times, log_odometry(logs.raw, idx).poses);
      s.start = logs.corrected.lasers[0].pose;
      s.relations = load_relations(dir + "intel.relations").relations;
    } catch (const Error& e) {
      s.error = e.what();
    }
    return s;
  }();
  return s;
}

/// BM_LocalizeIntel: one pass = every scan of the study through a fresh localizer (the map built
/// once, outside). Counters: ms_per_scan; the study's accuracy on the relations whose ends are
/// scans (m, deg), scans farther than 0.5 m from the corrected pose; solver iterations and fine
/// solves per scan, the share of scans that ran a coarse-to-fine alignment, a window search or a
/// scan-to-scan match; and the share of scans whose status is each of converged, not converged,
/// refused.
void localize_intel(benchmark::State& state, ScanSolver solver) {
  const IntelStudy& s = intel();
  if (!s.error.empty()) {
    state.SkipWithError(s.error.c_str());
    return;
  }
  LocalizerSettings settings = log_settings();
  settings.vdt_opt.solver = solver;
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05).asDiagonal();
  eval::Trajectory2 estimate;
  std::map<LocalizationStatus, int> statuses;
  double iterations = 0.0, update_s = 0.0;
  LocalizationResult::Work work;
  int lost = 0;
  for (auto _ : state) {
    std::unique_ptr<Localizer2D> loc =
        make_localizer("vdt-opt", *s.vdt, s.occupancy, settings, s.knowledge);
    loc->reset(s.start, p0);
    estimate.clear();
    statuses.clear();
    iterations = 0.0;
    lost = 0;
    work = {};
    for (std::size_t k = 0; k < s.scans.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      const LocalizationResult r = loc->update(s.steps[k], s.scans[k]);
      update_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      estimate.push_back({s.reference[k].t, r.pose});
      ++statuses[r.status];
      iterations += r.iterations;
      work.solves += r.work.solves;
      work.coarse_to_fine += r.work.coarse_to_fine;
      work.window_searches += r.work.window_searches;
      work.bridged += r.work.bridged;
      if ((r.pose.head<2>() - s.reference[k].pose.head<2>()).norm() > 0.5) ++lost;
    }
  }
  const double n = static_cast<double>(s.scans.size());
  // The updates alone (not the localizer's construction, which builds its coarse maps).
  state.counters["ms_per_scan"] = 1e3 * update_s / (n * static_cast<double>(state.iterations()));
  eval::RelationMetricOptions ro;  // exact stamps only, as the study
  ro.stamp_tolerance = 1e-6;
  ro.interpolate = false;
  const eval::RelationMetricResult m = eval::relation_metric(estimate, s.relations, ro);
  state.counters["relations"] = static_cast<double>(m.used);
  state.counters["trans_err_m"] = m.translation.mean;
  state.counters["rot_err_deg"] = m.rotation.mean * 180.0 / M_PI;
  state.counters["lost"] = lost;
  state.counters["iterations_per_scan"] = iterations / n;
  state.counters["solves_per_scan"] = work.solves / n;
  state.counters["coarse_to_fine_pct"] = 100.0 * work.coarse_to_fine / n;
  state.counters["window_search_pct"] = 100.0 * work.window_searches / n;
  state.counters["bridged_pct"] = 100.0 * work.bridged / n;
  state.counters["converged_pct"] = 100.0 * statuses[LocalizationStatus::kConverged] / n;
  state.counters["not_converged_pct"] = 100.0 * statuses[LocalizationStatus::kNotConverged] / n;
  state.counters["refused_pct"] = 100.0 * statuses[LocalizationStatus::kRefused] / n;
}
/// With the log settings as they are (the dense solver) and, for the ratio, Ceres.
void BM_LocalizeIntel(benchmark::State& state) { localize_intel(state, ScanSolver::kDense); }
void BM_LocalizeIntelCeres(benchmark::State& state) { localize_intel(state, ScanSolver::kCeres); }
BENCHMARK(BM_LocalizeIntel)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LocalizeIntelCeres)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
