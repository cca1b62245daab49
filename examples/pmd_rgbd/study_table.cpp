// The PMD study's table: per filter the errors, the ANEES, the frames within 2 sigma and the time
// per frame (table.csv, table.md and the printout).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "pmd_study.hpp"
#include "study_common.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace pmd_study {

using namespace vdtnav;
using study::rms;
using namespace vdtnav::rgbd_ground;

void write_tables(const std::string& out, const Scenario& sc, const FilterRun& run) {
  const ScooterDrive& drive = sc.drive;
  const std::size_t n = sc.n;
  const std::vector<Trace>& traces = run.traces;
  const double front_ms = run.front_ms;

  // ------------------------------------------------------------------ metrics
  std::ofstream csv(out + "/table.csv");
  csv << "method,frames,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,within_2sigma_pct,"
         "ms_per_frame,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct,"
         "pos_rmse_over_sources\n";
  std::ofstream md(out + "/table.md");
  md << "| method | frames | pos RMSE (m) | yaw RMSE (rad) | ANEES [95 %] | within 2σ (x and y) "
        "% | NEES ≤ χ²₃(95 %) (%) | ms/frame: mean, median, p99 (max) |\n"
        "|---|---|---|---|---|---|---|---|\n";
  std::printf("\n%-18s %6s %9s %9s %22s %8s %8s\n", "method", "frames", "pos[m]", "yaw[rad]",
              "ANEES [95%]", "2sig%", "ms");
  // The fusion against its two sources (issue 35: at least as accurate as either alone): the
  // fused filter's position RMSE over the smaller of the boundaries' (vdt-ekf) and the bearings'.
  std::vector<double> pos_rmse;
  for (const Trace& t : traces) {
    std::vector<double> pos;
    for (std::size_t k = 0; k < n; ++k)
      pos.push_back(pose_error(t.estimate[k], drive.truth[k]).head<2>().norm());
    pos_rmse.push_back(rms(pos));
  }
  const double over_sources = pos_rmse[1] / std::min(pos_rmse[0], pos_rmse[2]);
  for (std::size_t i = 0; i < traces.size(); ++i) {
    const Trace& t = traces[i];
    std::vector<double> yaw, nees_values;
    std::size_t within = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d e = pose_error(t.estimate[k], drive.truth[k]);
      yaw.push_back(e[2]);
      nees_values.push_back(eval::nees(t.estimate[k], drive.truth[k], t.covariance[k]));
      within += std::abs(e[0]) <= 2.0 * std::sqrt(t.covariance[k](0, 0)) &&
                std::abs(e[1]) <= 2.0 * std::sqrt(t.covariance[k](1, 1));
    }
    const eval::AneesResult a = eval::anees(nees_values, 3);
    const double pct = 100.0 * static_cast<double>(within) / static_cast<double>(n);
    const double ms = t.ms / static_cast<double>(n) + (t.uses_frames ? front_ms : 0.0);
    const eval::ErrorStatistics per_frame = eval::error_statistics(t.frame_ms);
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%zu,%.4f,%.5f,%.3f,%.3f,%.3f,%.1f,%.3f,%zu,%.3f,%.3f,%.3f,%.1f,%.3f\n",
                  t.name.c_str(), n, pos_rmse[i], rms(yaw), a.anees, a.interval.lower,
                  a.interval.upper, pct, ms, n - a.count, per_frame.median, per_frame.p99,
                  per_frame.max, a.inside_95_pct, i == 1 ? over_sources : std::nan(""));
    const std::string note = eval::left_out_note(a, n);
    csv << line;
    std::snprintf(line, sizeof line,
                  "| %s | %zu | %.4f | %.5f | %.2f [%.2f, %.2f]%s | %.1f | %.1f | %.3f, %.3f, "
                  "%.3f (%.3f) |\n",
                  t.name.c_str(), n, pos_rmse[i], rms(yaw), a.anees, a.interval.lower,
                  a.interval.upper, note.empty() ? "" : (" (" + note + ")").c_str(), pct,
                  a.inside_95_pct, ms, per_frame.median, per_frame.p99, per_frame.max);
    md << line;
    std::printf("%-18s %6zu %9.4f %9.5f %8.2f [%.2f,%.2f] %8.1f %8.2f\n", t.name.c_str(), n,
                pos_rmse[i], rms(yaw), a.anees, a.interval.lower, a.interval.upper, pct, ms);
  }
  char fusion[160];
  std::snprintf(fusion, sizeof fusion,
                "\nvdt-ekf+bearings' position RMSE over the better source's alone: %.3f (<= 1: "
                "the fusion pays).\n",
                over_sources);
  md << fusion;
  std::printf("%s", fusion);
  md << "\nFront end (boundaries, back-projection, pruning): "
     << std::to_string(front_ms).substr(0, 5)
     << " ms per frame, included in ms/frame of the filters that use frames.\n";
}

}  // namespace pmd_study
