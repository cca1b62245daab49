// The tables: table.csv (the fits and the approximation), localization.csv (localization on the
// Experiment 2 map) and table.md (both).

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "uncertain_map_study.hpp"

namespace study {

using namespace vdtnav;

void write_tables(const std::string& out, const std::vector<Row>& rows, const sim::MappingScene& c2,
                  const std::vector<LocalizationRow>& loc) {
  std::ofstream csv(out + "/table.csv");
  csv << "experiment,spacing_m,control_points,samples,rms_error_m,max_error_m,"
         "within_2sigma_pct,fit_s,cov_s\n";
  std::ofstream md(out + "/table.md");
  md << "| experiment | spacing (m) | control points | samples | RMS error (m) | max error "
        "(m) | within 2 sigma (%) | fit (s) | covariance (s) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%.3f,%d,%d,%.5f,%.5f,%.2f,%.3f,%.3f\n",
                  r.experiment.c_str(), r.spacing, r.control_points, r.samples, r.rms, r.max,
                  r.within, r.fit_s, r.cov_s);
    csv << line;
    std::snprintf(line, sizeof line, "| %s | %.3f | %d | %d | %.4f | %.4f | %.1f | %.2f | %.2f |\n",
                  r.experiment.c_str(), r.spacing, r.control_points, r.samples, r.rms, r.max,
                  r.within, r.fit_s, r.cov_s);
    md << line;
  }
  std::ofstream lcsv(out + "/localization.csv");
  lcsv << "map_model,pos_rmse_m,ori_rmse_rad,anees,anees_lo,anees_hi,anees_left_out,ms_mean,"
          "ms_median,ms_p99,ms_max,nees_inside_95_pct\n";
  md << "\nLocalization on the Experiment 2 map (" << c2.name
     << "):\n\n| map model | position RMSE (m) | orientation RMSE (rad) | ANEES [95 %] | "
        "NEES ≤ χ²₃(95 %) (%) | ms/scan: mean, median, p99 (max) |\n|---|---|---|---|---|---|\n";
  for (const auto& r : loc) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%.5f,%.6f,%.3f,%.3f,%.3f,%zu,%.4f,%.4f,%.4f,%.4f,%.1f\n",
                  r.map_model.c_str(), r.pos_rmse, r.ori_rmse, r.anees, r.anees_lo, r.anees_hi,
                  r.anees_left_out, r.ms.mean, r.ms.median, r.ms.p99, r.ms.max,
                  r.nees_inside_95_pct);
    lcsv << line;
    std::snprintf(line, sizeof line,
                  "| %s | %.4f | %.5f | %.2f [%.2f, %.2f]%s | %.1f | %.3f, %.3f, %.3f (%.3f) |\n",
                  r.map_model.c_str(), r.pos_rmse, r.ori_rmse, r.anees, r.anees_lo, r.anees_hi,
                  r.anees_note.empty() ? "" : (" (" + r.anees_note + ")").c_str(),
                  r.nees_inside_95_pct, r.ms.mean, r.ms.median, r.ms.p99, r.ms.max);
    md << line;
  }
}

}  // namespace study
