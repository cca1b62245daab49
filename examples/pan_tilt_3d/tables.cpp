// vdtnav_pan_tilt_3d: Table 3.4 x factors, the cells from the trials and table.csv, table.md and
// the table on stdout (pan_tilt_study.hpp).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "pan_tilt_study.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace pan_tilt_study {
namespace {

std::string format_number(double v, const char* fmt) {
  if (!std::isfinite(v)) return "nan";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

std::vector<std::vector<Cell>> tabulate(const std::vector<std::vector<Trial>>& trials, int seeds,
                                        bool verbose) {
  const std::size_t n_seeds = static_cast<std::size_t>(seeds);
  const std::size_t n_jobs = trials.size();
  std::vector<std::vector<Cell>> cells(kScenarios.size(), std::vector<Cell>(kFactors.size()));
  for (std::size_t job = 0; job < n_jobs; ++job)
    for (std::size_t c = 0; c < kScenarios.size(); ++c)
      for (std::size_t f = 0; f < kFactors.size(); ++f) {
        const Trial& t = trials[job][c * kFactors.size() + f];
        Cell& cell = cells[c][f];
        ++cell.trials;
        cell.ms += t.ms;
        cell.solve_ms.push_back(t.ms);
        cell.observations += t.observations;
        const bool ok = t.status == LocalizationStatus::kConverged &&
                        t.position_error < kSuccessPosition && t.attitude_error < kSuccessAttitude;
        if (verbose && !ok)
          std::fprintf(stderr,
                       "  unsuccessful: L%zu seed %zu scenario %s factor %d: %s, %.3f m, "
                       "%.3f rad, %d inliers of %d readings, d_VCD %.4f m^2, truncated VCD "
                       "%.4f (truth %.4f)\n",
                       job / n_seeds + 1, job % n_seeds, kScenarios[c].name, kFactors[f],
                       to_string(t.status), t.position_error, t.attitude_error, t.inliers,
                       t.observations, t.final_cost, t.tvcd_estimate, t.tvcd_truth);
        const bool estimated = t.status == LocalizationStatus::kConverged ||
                               t.status == LocalizationStatus::kNotConverged;
        if (estimated && t.position_error < kSuccessPosition && t.attitude_error < kSuccessAttitude)
          ++cell.within;
        if (t.status != LocalizationStatus::kConverged) continue;
        ++cell.converged;
        cell.pos_sq += t.position_error * t.position_error;
        cell.att_sq += t.attitude_error * t.attitude_error;
        if (t.position_error < kSuccessPosition && t.attitude_error < kSuccessAttitude)
          ++cell.success;
      }
  return cells;
}

void write_tables(const std::string& out, const World& world,
                  const sim::PointLaserSimOptions& sim_options,
                  const std::vector<std::vector<Cell>>& cells,
                  const std::vector<std::size_t>& sweep_returns, int seeds, bool four_dof) {
  const Eigen::Vector3i size = world.occupancy.size();
  const std::size_t n_loc = world.locations.size();
  const std::size_t n_jobs = sweep_returns.size();
  double returns = 0.0;
  for (std::size_t r : sweep_returns) returns += static_cast<double>(r);
  returns /= static_cast<double>(n_jobs);

  std::ofstream csv(out + "/table.csv");
  csv << "scenario,factor,trials,success_pct,pos_rmse_m,att_rmse_rad,ms_mean,"
         "ms_median,ms_p99,ms_max\n";
  std::ofstream md(out + "/table.md");
  md << "## Table 3.4 / Fig. 3.18: pan-tilt point laser, " << (four_dof ? "4" : "6")
     << "-DOF VDT optimization (" << world.name << ")\n\n";
  {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "Map: %s, %d x %d x %d voxels of %.3f m. Sweep: %zu readings (%d pans x %d "
                  "tilts, LIDAR-Lite v3: 0.05-40 m, sigma_r = %.3f m), %.0f returns on average. "
                  "%d noise seeds x %zu locations = %zu trials per cell.\n\n",
                  world.name.c_str(), size.x(), size.y(), size.z(), world.occupancy.resolution(),
                  sim_options.pattern.size(), sim_options.pattern.pan_steps,
                  sim_options.pattern.tilt_steps, sim_options.spec.sigma_range, returns, seeds,
                  n_loc, n_jobs);
    md << buf;
  }
  md << "Robot locations (" << world.how_located << "):\n\n";
  for (std::size_t k = 0; k < n_loc; ++k) {
    const Pose3& p = world.locations[k];
    const Eigen::Vector3d rpy = rpy_of(p.linear()) * 180 / kPi;
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "- L%zu: x %.3f, y %.3f, z %.3f m; roll %+.2f, pitch %+.2f, yaw %+.1f deg\n",
                  k + 1, p.translation().x(), p.translation().y(), p.translation().z(), rpy[0],
                  rpy[1], rpy[2]);
    md << buf;
  }
  md << "\nInitial guess: the truth plus Table 3.4's offset in x, y, z and in "
     << (four_dof ? "yaw (roll and pitch held at the true IMU values)" : "roll, pitch, yaw")
     << ": A +0.05 m / +0.025 rad, B 0.1 / 0.05, C 0.2 / 0.1, D 0.4 / 0.2. Factor k keeps every "
        "k-th reading of the sweep.\n\n"
        "Definitions: *converged* = the optimizer returned status `converged`; *success* = "
        "converged and within 0.1 m (position) and 0.05 rad (attitude, the rotation angle of "
        "R_est R_true^T) of the truth, in % of all trials; *within %* = the same thresholds "
        "whatever the status, as long as the optimizer produced an estimate (converged or not "
        "converged); the RMSEs (position: |t_est - t_true|, attitude: that rotation angle) are "
        "over the converged trials, successful or not; readings used = mean returns kept after "
        "downsampling; ms = wall time of one solve: mean, median, p99 (max).\n\n"
        "| scenario | factor | readings used | trials | converged | success % | within % | "
        "pos RMSE (m) | att RMSE (rad) | ms: mean, median, p99 (max) |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("\n%-8s %6s %8s %6s %9s %9s %12s %13s %8s\n", "scenario", "factor", "readings",
              "trials", "converged", "success%", "pos RMSE (m)", "att RMSE (rad)", "ms mean");
  for (std::size_t c = 0; c < kScenarios.size(); ++c)
    for (std::size_t f = 0; f < kFactors.size(); ++f) {
      const Cell& x = cells[c][f];
      const double used = x.observations / x.trials;
      const std::string pos = format_number(x.pos_rmse(), "%.6f");
      const std::string att = format_number(x.att_rmse(), "%.6f");
      const eval::ErrorStatistics per_solve = eval::error_statistics(x.solve_ms);
      csv << kScenarios[c].name << ',' << kFactors[f] << ',' << x.trials << ','
          << format_number(x.success_pct(), "%.2f") << ',' << pos << ',' << att << ','
          << format_number(x.ms_mean(), "%.3f") << ',' << format_number(per_solve.median, "%.3f")
          << ',' << format_number(per_solve.p99, "%.3f") << ','
          << format_number(per_solve.max, "%.3f") << '\n';
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "| %s | %d | %.0f | %d | %d | %.1f | %.1f | %s | %s | %.2f, %.2f, %.2f "
                    "(%.2f) |\n",
                    kScenarios[c].name, kFactors[f], used, x.trials, x.converged, x.success_pct(),
                    100.0 * x.within / x.trials, format_number(x.pos_rmse(), "%.4f").c_str(),
                    format_number(x.att_rmse(), "%.4f").c_str(), x.ms_mean(), per_solve.median,
                    per_solve.p99, per_solve.max);
      md << buf;
      std::printf("%-8s %6d %8.0f %6d %9d %9.1f %12s %13s %8.2f\n", kScenarios[c].name, kFactors[f],
                  used, x.trials, x.converged, x.success_pct(),
                  format_number(x.pos_rmse(), "%.4f").c_str(),
                  format_number(x.att_rmse(), "%.4f").c_str(), x.ms_mean());
    }
  md << "\nFigures: `rmse.png` (Fig. 3.18), `vdt_slice_horizontal.png`, "
        "`vdt_slice_vertical.png`.\n";
}

}  // namespace pan_tilt_study
