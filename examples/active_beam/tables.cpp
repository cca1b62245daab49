// vdtnav_active_beam: the table of the study, table.csv and table.md (active_beam_study.hpp).
#include <cstdio>
#include <ostream>
#include <string>

#include "active_beam_study.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace active_beam_study {

void write_table_header(std::ostream& csv, std::ostream& md) {
  csv << "dataset,strategy,steps,rmse_x_m,rmse_y_m,rmse_phi_rad,anees,anees_lo,anees_hi,"
         "lost_pct,ms_select,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct\n";
  md << "| dataset | strategy | steps | RMSE x (m) | RMSE y (m) | RMSE phi (rad) | ANEES [95 %] "
        "| NEES ≤ χ²₃(95 %) (%) | lost % | ms/selection | ms/step: median, p99 (max) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|\n";
}

void write_table_row(std::ostream& csv, std::ostream& md, const Dataset& ds, std::size_t d,
                     BeamStrategy s, const Run& r) {
  const std::string dataset = d == 0 ? "dataset1" : "dataset2";
  const eval::ErrorStatistics per_step = eval::error_statistics(r.step_ms);
  char line[512];
  std::snprintf(line, sizeof line,
                "%s,%s,%zu,%.5f,%.5f,%.6f,%.3f,%.3f,%.3f,%.2f,%.4f,%zu,%.4f,%.4f,%.4f,%.1f\n",
                dataset.c_str(), to_string(s), ds.drive.size(), r.rmse_x, r.rmse_y, r.rmse_phi,
                r.anees.anees, r.anees.interval.lower, r.anees.interval.upper, r.lost_pct,
                r.ms_select, ds.drive.size() - r.anees.count, per_step.median, per_step.p99,
                per_step.max, r.anees.inside_95_pct);
  const std::string note = eval::left_out_note(r.anees, ds.drive.size());
  csv << line;
  std::snprintf(line, sizeof line,
                "| %s | %s | %zu | %.4f | %.4f | %.5f | %.2f [%.2f, %.2f]%s | %.1f | %.1f | %.3f | "
                "%.3f, %.3f (%.3f) |\n",
                ds.name.c_str(), to_string(s), ds.drive.size(), r.rmse_x, r.rmse_y, r.rmse_phi,
                r.anees.anees, r.anees.interval.lower, r.anees.interval.upper,
                note.empty() ? "" : (" (" + note + ")").c_str(), r.anees.inside_95_pct, r.lost_pct,
                r.ms_select, per_step.median, per_step.p99, per_step.max);
  md << line;
}

}  // namespace active_beam_study
