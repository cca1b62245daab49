// The UAV study's table: per method the frames localized, the errors, the ANEES, the recovery
// time after feature-poor spans and the time per frame (table.csv, table.md and the printout).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "study_common.hpp"
#include "uav_study.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace uav_study {

using namespace vdtnav;
using study::rms;
using namespace vdtnav::uav_camera;

void write_tables(const std::string& out, const Scenario& sc, const FlightRun& run) {
  const std::vector<UavFlightSample>& flight = sc.flight;
  const std::vector<Trace>& traces = run.traces;
  const std::vector<char>& features = run.features;
  const std::vector<double>& front_ms = run.front_ms;
  const int min_explained = run.min_explained;

  double mean_front_ms = 0.0;
  for (double v : front_ms) mean_front_ms += v / static_cast<double>(front_ms.size());
  std::size_t with_features = 0;
  for (char f : features) with_features += f ? 1 : 0;
  std::ofstream csv(out + "/table.csv");
  csv << "method,frames,localized_pct,pos_rmse_m,yaw_rmse_rad,anees,anees_lo,anees_hi,"
         "recovery_s,ms_per_frame,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct\n";
  std::ofstream md(out + "/table.md");
  md << "| method | frames | localized % | pos RMSE (m) | yaw RMSE (rad) | ANEES [95 %] | "
        "NEES ≤ χ²₃(95 %) (%) | recovery (s) | ms/frame: mean, median, p99 (max) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  std::printf("\n%-8s %6s %9s %9s %9s %18s %9s %8s\n", "method", "frames", "local.%", "pos[m]",
              "yaw[rad]", "ANEES [95%]", "recov[s]", "ms");
  for (const Trace& t : traces) {
    const bool has_cov = t.name != "udt-opt";
    std::vector<double> pos, yaw, nees_values;
    std::size_t localized = 0;
    for (std::size_t k = 0; k < flight.size(); ++k) {
      if (!features[k] || t.status[k] != LocalizationStatus::kConverged) continue;
      ++localized;
      const Eigen::Vector3d e = pose_error(t.estimate[k], flight[k].pose);
      pos.push_back(e.head<2>().norm());
      yaw.push_back(e[2]);
      if (t.has_cov[k])
        nees_values.push_back(eval::nees(t.estimate[k], flight[k].pose, t.covariance[k]));
    }
    // Re-acquisition: from each return of features after a feature-poor span, the time until
    // the position error is below 0.2 m.
    std::vector<double> recovery;
    for (std::size_t k = 1; k < flight.size(); ++k) {
      if (!(features[k] && !features[k - 1])) continue;
      for (std::size_t j = k; j < flight.size(); ++j) {
        if (pose_error(t.estimate[j], flight[j].pose).head<2>().norm() < 0.2) {
          recovery.push_back(flight[j].time - flight[k].time);
          break;
        }
        if (j + 1 == flight.size()) recovery.push_back(flight[j].time - flight[k].time);
      }
    }
    double recovery_s = 0.0;
    for (double r : recovery) recovery_s += r / static_cast<double>(recovery.size());
    if (recovery.empty()) recovery_s = std::nan("");
    double anees = std::nan(""), lo = std::nan(""), hi = std::nan("");
    std::size_t left_out = with_features;
    std::string note;                  // the frames that see the road the ANEES leaves out, and why
    double inside_pct = std::nan("");  // the per-frame 95 % bound (eval::AneesResult)
    if (has_cov && !nees_values.empty()) {
      const eval::AneesResult a = eval::anees(nees_values, 3);
      anees = a.anees;
      lo = a.interval.lower;
      hi = a.interval.upper;
      left_out = with_features - a.count;
      inside_pct = a.inside_95_pct;
      note = eval::left_out_note(a, with_features, "not localized or without a covariance");
    }
    const double pct = with_features ? 100.0 * localized / with_features : 0.0;
    int counts[5] = {0, 0, 0, 0, 0};
    for (LocalizationStatus st : t.status) ++counts[static_cast<int>(st)];
    std::printf(
        "  %s statuses: converged %d, not converged %d, too few %d, diverged %d, refused %d\n",
        t.name.c_str(), counts[0], counts[1], counts[2], counts[3], counts[4]);
    if (has_cov) {  // per-component normalised squared errors: which one is off
      Eigen::Vector3d z = Eigen::Vector3d::Zero();
      int nz = 0;
      for (std::size_t k = 0; k < flight.size(); ++k) {
        if (!features[k] || !t.has_cov[k]) continue;
        const Eigen::Vector3d e = pose_error(t.estimate[k], flight[k].pose);
        for (int c = 0; c < 3; ++c) z[c] += e[c] * e[c] / t.covariance[k](c, c);
        ++nz;
      }
      if (nz > 0) z /= nz;
      std::printf("  %s mean e^2/sigma^2: x %.2f, y %.2f, yaw %.2f (1 when calibrated)\n",
                  t.name.c_str(), z[0], z[1], z[2]);
    }
    const double ms = t.ms / flight.size() + mean_front_ms;
    std::vector<double> frame_ms = t.frame_ms;  // the front end's time and the localizer's
    for (std::size_t k = 0; k < frame_ms.size(); ++k) frame_ms[k] += front_ms[k];
    const eval::ErrorStatistics per_frame = eval::error_statistics(frame_ms);
    char line[512], inside_text[16] = "—";
    if (!std::isnan(inside_pct)) std::snprintf(inside_text, sizeof inside_text, "%.1f", inside_pct);
    std::snprintf(line, sizeof line,
                  "%s,%zu,%.2f,%.4f,%.5f,%.3f,%.3f,%.3f,%.2f,%.3f,%zu,%.3f,%.3f,%.3f,%.1f\n",
                  t.name.c_str(), flight.size(), pct, rms(pos), rms(yaw), anees, lo, hi, recovery_s,
                  ms, left_out, per_frame.median, per_frame.p99, per_frame.max, inside_pct);
    csv << line;
    std::snprintf(
        line, sizeof line,
        "| %s | %zu | %.1f | %.4f | %.5f | %s | %s | %s | %.2f, %.2f, %.2f (%.2f) |\n",
        t.name.c_str(), flight.size(), pct, rms(pos), rms(yaw),
        has_cov
            ? (std::to_string(anees).substr(0, 5) + " [" + std::to_string(lo).substr(0, 4) + ", " +
               std::to_string(hi).substr(0, 4) + "]" + (note.empty() ? "" : " (" + note + ")"))
                  .c_str()
            : "—",
        inside_text, recovery.empty() ? "—" : std::to_string(recovery_s).substr(0, 4).c_str(), ms,
        per_frame.median, per_frame.p99, per_frame.max);
    md << line;
    std::printf("%-8s %6zu %9.1f %9.4f %9.5f %8.2f [%.2f,%.2f] %9.2f %8.2f\n", t.name.c_str(),
                flight.size(), pct, rms(pos), rms(yaw), anees, lo, hi, recovery_s, ms);
  }
  md << "\nFrames that see the road (>= " << min_explained
     << " edge points explained at the true pose): " << with_features << " of " << flight.size()
     << ". Front end (edges + ground projection): " << std::to_string(mean_front_ms).substr(0, 4)
     << " ms per frame, included in ms/frame.\n";
  std::printf("frames that see the road: %zu of %zu; front end %.2f ms per frame\n", with_features,
              flight.size(), mean_front_ms);
}

}  // namespace uav_study
