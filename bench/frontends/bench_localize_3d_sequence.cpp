// BM_Localize3DSequence: a real 3D sequence tracked as `vdtnav localize3d --odom` tracks it —
// MulRan Riverside 02 (../shared/data/3d/mulran-riverside02, a car's Ouster, 60 keyframes over 245
// m): the odd keyframes at their SLAM poses make a sparse map (0.1 m, as `vdtnav map3d --scans
// --poses --skip-even` builds it), the 30 even ones are localized in order, each predicted by
// FAST-LIO2's increments (the study's --scans --odom run, examples/lidar_3d/real_scans.cpp). Reads
// the data in place; skipped with a message when it is absent. The map (~40 s, ~1 GB) and the
// observations are made once, outside the timing; one pass = a fresh localizer over the 30 scans.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#include "vdtnav/pcl/registered_scans.hpp"

namespace vdtnav {
namespace {

struct Riverside {
  std::string error;  ///< why the benchmark cannot run, empty when it can
  std::unique_ptr<SparseVdtMap3> map;
  std::vector<ObservationSet3> scans;  ///< the even keyframes, voxel-downsampled at 0.1 m
  std::vector<Pose3> reference;        ///< their SLAM poses
  std::vector<OdometryStep3> steps;    ///< FAST-LIO2's increment into each (the first: none)
};

const Riverside& riverside() {
  static const Riverside s = [] {
    Riverside s;
    const std::string dir = std::string(VDTNAV_DATA_DIR) + "/3d/mulran-riverside02/";
    if (!std::filesystem::exists(dir + "odom_poses.txt")) {
      s.error = "MulRan Riverside data not found in " + dir;
      return s;
    }
    try {
      const std::vector<std::string> clouds = point_cloud_files_in(dir + "Scans");
      const std::vector<Pose3> ref =
          poses_of_scans(load_scan_poses(dir + "optimized_poses.txt"), clouds);
      const std::vector<Pose3> odom =
          poses_of_scans(load_scan_poses(dir + "odom_poses.txt"), clouds);
      std::vector<double> times;
      {
        std::ifstream in(dir + "times.txt");
        for (double t; in >> t;) times.push_back(t);
      }
      VDTNAV_CHECK(times.size() == clouds.size(), dir + "times.txt: a stamp per scan expected");
      std::vector<std::string> map_files;
      std::vector<Pose3> map_poses;
      for (const std::size_t k : select_scans(clouds.size(), {1, false, true})) {
        map_files.push_back(clouds[k]);
        map_poses.push_back(ref[k]);
      }
      PointCloudOccupancyOptions mo;
      mo.resolution = 0.1;  // map3d's default
      mo.margin = 1.0;
      s.map = std::make_unique<SparseVdtMap3>(
          sparse_vdt_map_from_point_cloud(merge_scan_files(map_files, map_poses, 0.025), mo));
      const std::vector<std::size_t> even = select_scans(clouds.size(), {1, true, false});
      for (std::size_t i = 0; i < even.size(); ++i) {
        const std::size_t k = even[i], prev = i == 0 ? k : even[i - 1];
        CloudObservationOptions co;
        co.voxel = 0.1;  // localize3d's default: the map's resolution
        s.scans.push_back(observations_from_cloud(read_point_cloud(clouds[k]), co));
        s.reference.push_back(ref[k]);
        OdometryStep3 step;
        step.dt = i == 0 ? 0.1 : std::max(times[k] - times[prev], 1e-3);
        step.delta = odom[prev].inverse() * odom[k];
        s.steps.push_back(step);
      }
    } catch (const Error& e) {
      s.error = e.what();
    }
    return s;
  }();
  return s;
}

/// Counters: ms_per_scan (mean of the updates) and ms_median; iterations_median and
/// iterations_p99 (solver evaluations per scan, every solve of the update); converged_pct,
/// refused_pct, lost_pct; pos_rmse_m and att_max_deg against the SLAM poses; within_pct (scans
/// within 0.10 m and 1 deg of them).
void BM_Localize3DSequence(benchmark::State& state) {
  const Riverside& s = riverside();
  if (!s.error.empty()) {
    state.SkipWithError(s.error.c_str());
    return;
  }
  const VdtLocalizer3Options o = vdt_localizer3_defaults();  // localize3d's
  std::vector<double> ms, iterations;
  int converged = 0, refused = 0, lost = 0, within = 0;
  double se = 0.0, att_max = 0.0;
  for (auto _ : state) {
    RecoveringLocalizer3 loc(*s.map, o);
    ms.clear();
    iterations.clear();
    converged = refused = lost = within = 0;
    se = att_max = 0.0;
    bool tracking = false;
    Pose3 guess = s.reference.front();
    for (std::size_t i = 0; i < s.scans.size(); ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      LocalizationResult3 r;
      if (tracking) {
        r = loc.update(s.steps[i], s.scans[i]);
      } else {
        if (i > 0) guess = guess * s.steps[i].delta;
        r = localize_from_guess(loc.tracker(), s.scans[i], guess);
        if (r.status == LocalizationStatus::kConverged) {
          loc.reset(r.pose, r.covariance);
          tracking = true;
        }
      }
      ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      iterations.push_back(r.iterations);
      converged += r.status == LocalizationStatus::kConverged;
      refused += r.status == LocalizationStatus::kRefused;
      lost += r.status == LocalizationStatus::kLost;
      const double e = (r.pose.translation() - s.reference[i].translation()).norm();
      const double a = attitude_error(r.pose, s.reference[i]) * 180.0 / M_PI;  // degrees
      se += e * e;
      att_max = std::max(att_max, a);
      within += e <= 0.10 && a <= 1.0;
    }
  }
  const double n = static_cast<double>(s.scans.size());
  const eval::ErrorStatistics t = eval::error_statistics(ms);
  const eval::ErrorStatistics it = eval::error_statistics(iterations);
  state.counters["ms_per_scan"] = t.mean;
  state.counters["ms_median"] = t.median;
  state.counters["iterations_median"] = it.median;
  state.counters["iterations_p99"] = it.p99;
  state.counters["converged_pct"] = 100.0 * converged / n;
  state.counters["refused_pct"] = 100.0 * refused / n;
  state.counters["lost_pct"] = 100.0 * lost / n;
  state.counters["pos_rmse_m"] = std::sqrt(se / n);
  state.counters["att_max_deg"] = att_max;
  state.counters["within_pct"] = 100.0 * within / n;
}
BENCHMARK(BM_Localize3DSequence)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace vdtnav
