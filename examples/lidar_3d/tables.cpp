// The tables: table.csv and table.md, one row per localizer run, and the printed summary; the
// per-update record they are made of.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace lidar3d {

using namespace vdtnav;

void Run::record(const LocalizationResult3& r, const Pose3& truth, double update_s) {
  seconds += update_s;
  scan_ms.push_back(1e3 * update_s);
  estimates.push_back(r.pose);
  covariances.push_back(r.covariance);
  int dof = 0;
  nees.push_back(eval::nees(r.pose, truth, r.covariance, &dof));
  nees_dof.push_back(dof);
  lost += r.status == LocalizationStatus::kLost;
  iterations += r.iterations;
  scan_iterations.push_back(r.iterations);
  converged += r.status == LocalizationStatus::kConverged;
  refused += r.status == LocalizationStatus::kRefused;
}

void write_rows(std::ostream& csv, std::ostream& md, const std::vector<Pose3>& truth,
                const Run* runs, std::size_t count_runs) {
  csv << "method,scans,pos_rmse_m,att_rmse_rad,anees,anees_lo,anees_hi,lost_pct,ms_per_scan,"
         "anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct,converged_pct,"
         "iterations_median,iterations_p99\n";
  md << "| method | scans | position RMSE (m) | attitude RMSE (rad) | ANEES | 95 % interval | "
        "NEES ≤ χ²(95 %) (%) | lost % | converged % | iterations per scan: median, p99 | ms per "
        "scan: mean, median, p99 (max) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (std::size_t m = 0; m < count_runs; ++m) {
    const Run& r = runs[m];
    const std::size_t count = r.estimates.size();  // the rebuilt rows: the first scans
    double se_p = 0.0, se_a = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      se_p += (r.estimates[k].translation() - truth[k].translation()).squaredNorm();
      se_a += std::pow(attitude_error(r.estimates[k], truth[k]), 2);
    }
    const double n = static_cast<double>(count);
    const int dof = r.nees_dof.empty() ? 6 : r.nees_dof.back();
    const eval::AneesResult a = eval::anees(r.nees, dof);
    const double lost_pct = 100.0 * r.lost / n;
    const double ms = 1e3 * r.seconds / n;
    const eval::ErrorStatistics per_scan = eval::error_statistics(r.scan_ms);
    const eval::ErrorStatistics its = eval::error_statistics(r.scan_iterations);
    const double converged_pct = 100.0 * r.converged / n;
    char line[512];
    std::snprintf(
        line, sizeof line,
        "%s,%zu,%.4f,%.5f,%.3f,%.3f,%.3f,%.1f,%.2f,%zu,%.3f,%.3f,%.3f,%.1f,%.1f,%.0f,%.0f\n",
        r.name.c_str(), count, std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees, a.interval.lower,
        a.interval.upper, lost_pct, ms, count - a.count, per_scan.median, per_scan.p99,
        per_scan.max, a.inside_95_pct, converged_pct, its.median, its.p99);
    const std::string note = eval::left_out_note(a, count);
    csv << line;
    std::snprintf(line, sizeof line,
                  "| %s | %zu | %.4f | %.5f | %.2f%s | [%.2f, %.2f] | %.1f | %.1f | %.1f | %.0f, "
                  "%.0f | %.2f, %.2f, %.2f (%.2f) |\n",
                  r.name.c_str(), count, std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees,
                  note.empty() ? "" : (" (" + note + ")").c_str(), a.interval.lower,
                  a.interval.upper, a.inside_95_pct, lost_pct, converged_pct, its.median, its.p99,
                  ms, per_scan.median, per_scan.p99, per_scan.max);
    md << line;
    std::printf(
        "%s: position RMSE %.4f m, attitude RMSE %.5f rad, ANEES %.2f in [%.2f, %.2f] "
        "(%d dof), lost %.1f %%, refused %d, converged %.1f %%, %.2f ms (median %.2f, p99 %.2f, "
        "max %.2f) and %.1f iterations per scan (median %.0f, p99 %.0f)\n",
        r.name.c_str(), std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees, a.interval.lower,
        a.interval.upper, dof, lost_pct, r.refused, converged_pct, ms, per_scan.median,
        per_scan.p99, per_scan.max, static_cast<double>(r.iterations) / n, its.median, its.p99);
  }
}

void write_tables(const std::string& out, const std::string& world_name,
                  const std::vector<Pose3>& truth, double speed, std::size_t readings_sum,
                  double voxel, const sim::Lidar3dSpec& vlp16, const VdtLocalizer3Options& o6,
                  std::size_t mapping_scans, double map_pose_sigma, const Run (&runs)[kRuns],
                  double sim_seconds) {
  std::ofstream csv(out + "/table.csv");
  std::ofstream md(out + "/table.md");
  md << "# 3D LiDAR localization: simulated VLP-16 scans on the " << world_name << " map\n\n"
     << truth.size() << " scans at 10 Hz, " << speed << " m/s, about "
     << readings_sum / truth.size() << " readings per scan after " << voxel
     << " m voxel downsampling (of " << vlp16.rings * vlp16.rays_per_ring()
     << " rays); odometry noise 5 % per metre + 0.02 m/s, 5 % per radian + 0.01 rad/s; IMU roll "
        "and pitch sigma "
     << o6.sigma_imu_attitude
     << " rad. The scans are ray cast in the map's own voxels (no map error but quantisation); "
        "the *-rebuilt rows localize them on the map `vdtnav map3d` makes of a separate mapping "
        "drive ("
     << mapping_scans << " scans registered with " << map_pose_sigma << " m / "
     << 0.1 * map_pose_sigma
     << " rad of pose error per axis), as a real map is made. ANEES interval: 95 % (chi-square, "
        "N x dof).\n\n";
  write_rows(csv, md, truth, runs, kRuns);
  md << "\nTimes: localizer update per scan (observations given), this machine; the ray casting "
        "of the simulated scans took "
     << 1e3 * sim_seconds / static_cast<double>(truth.size())
     << " ms per scan and is not counted.\n\nFigures: `trajectory.png` (top view), "
        "`errors.png` (errors with +-2 sigma of the reported covariance).\n";
}

}  // namespace lidar3d
