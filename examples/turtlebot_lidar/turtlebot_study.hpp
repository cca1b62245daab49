#pragma once
// The machinery of the Table 3.3 study (turtlebot_lidar.cpp): the five localizers' runs
// (localizer_runs.cpp), their metrics (localization_metrics.cpp), the table (study_table.cpp) and
// the figures (study_figures.cpp).
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"

namespace turtlebot_study {

struct Trace {  // one method on one run
  std::vector<vdtnav::Pose2> estimate;
  std::vector<Eigen::Matrix3d> covariance;
  std::vector<char> has_cov;
  std::vector<double> ms;
};

struct Metrics {
  double pos_mae = 0, pos_mae_std = 0, ori_mae = 0, ori_mae_std = 0;
  double pos_mse = 0, pos_mse_std = 0, ori_mse = 0, ori_mse_std = 0;
  bool has_cov = false;  ///< some scan reported a covariance; the ANEES is over those scans
  int without_cov = 0;   ///< scans that reported none (e.g. vdt-opt where its Hessian is not PD)
  double anees = 0, anees_lo = 0, anees_hi = 0, lost_pct = 0;
  double nees_inside_95_pct = 0;  ///< the per-step 95 % bound (eval::AneesResult::inside_95_pct)
  std::vector<double> ms;         ///< every scan's milliseconds (of all runs when combined)
  vdtnav::eval::ErrorStatistics ms_stats;  ///< of ms: mean, median, p99 (nearest rank), max
};

/// Errors, ANEES, lost fraction and timings of one method's trace against the run's truth.
Metrics evaluate(const Trace& t, const vdtnav::sim::SimulatedRun& run);

/// Mean over repeats; with one repeat the stds are over time (as in Table 3.3), with several
/// they are the std of the per-repeat means.
Metrics combine(const std::vector<Metrics>& r);

/// Runs the five localizers (vdt-opt, vdt-ekf, udt-opt, udt-ekf, pf: `methods`, in that order)
/// on `run` from its true start, with a progress bar each; appends each one's metrics to
/// per_method[m] and returns their traces.
std::vector<Trace> run_localizers(const vdtnav::VdtMap2& vdt, const vdtnav::OccupancyGrid<2>& occ,
                                  const vdtnav::sim::NoiseProfile& noise,
                                  const std::vector<std::string>& methods,
                                  const vdtnav::sim::SimulatedRun& run, std::uint32_t run_seed,
                                  std::vector<std::vector<Metrics>>& per_method);

/// Writes out/table.csv and out/table.md (the repeats combined) and prints the table.
void write_tables(const std::string& out, const std::vector<std::string>& methods,
                  const std::vector<std::vector<Metrics>>& per_method);

/// Figs. 3.1-3.5 of the first run: trajectory.png, errors_vdt_opt.png, errors_vdt_ekf.png and
/// vcd_landscape.png in `out`.
void draw_figures(const std::string& out, const std::string& name,
                  const vdtnav::OccupancyGrid<2>& occ, double resolution,
                  const vdtnav::VdtMap2& vdt, const std::vector<std::string>& methods,
                  const vdtnav::sim::SimulatedRun& first_run,
                  const std::vector<Trace>& first_traces);

}  // namespace turtlebot_study
