// vdtnav_intel_lab: the table of the study, table.csv and table.md (intel_study.hpp).
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "intel_study.hpp"

namespace intel_study {

void write_tables(std::ostream& csv, std::ostream& md, const std::vector<Row>& rows,
                  std::size_t split, std::size_t n, double build_s) {
  csv << "method,relations,rel_trans_mean_m,rel_trans_std_m,rel_rot_mean_deg,rel_rot_std_deg,"
         "rel_trans2_mean_m2,rel_rot2_mean_deg2,ate_rmse_m,ate_aligned_rmse_m,ate_rot_rmse_deg,"
         "rpe_trans_rmse_m,rpe_rot_rmse_deg,lost,scans,has_cov,anees,anees_lo,anees_hi,ms_mean,"
         "ms_max,wall_s,rel_nees_used,rel_nees_skipped_no_cov,rel_nees_mean,rel_nees_median,"
         "rel_nees_inside_7.81,flagged_lost,cpu_ms_max,anees_left_out,ms_median,ms_p99,"
         "iterations_median,iterations_p99,converged_pct,correct_converged_pct,"
         "relations_converged,rel_trans_converged_m,rel_rot_converged_deg,published_pct,"
         "correct_published_pct,relations_published,rel_trans_published_m,"
         "rel_rot_published_deg\n";
  md << "Intel Research Lab: map from scans " << split << ".." << n - 1
     << " (corrected poses), localization of scans 0.." << split - 1
     << " with raw odometry. Relations: both ends localized scans (exact stamps).\n\n"
     << "| method | relations | trans. err. (m) | rot. err. (deg) | ATE (m) | RPE (m / deg) | "
        "off > 0.5 m | flagged lost | ANEES [95 %] | relation NEES: n, mean, median, ≤ 7.81 | "
        "ms/scan: mean, median, p99 (max) | wall (s) |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    char b[1024];
    const bool loc = r.ate.ok();
    std::snprintf(
        b, sizeof b,
        "%s,%zu,%.6f,%.6f,%.4f,%.4f,%.8f,%.6f,%.6f,%.6f,%.4f,%.6f,%.4f,%zu,%zu,%d,%.4f,"
        "%.4f,%.4f,%.4f,%.4f,%.4f,%zu,%zu,%.4f,%.4f,%.4f,%zu,%.3f,%zu,%.4f,%.4f,%.0f,%.0f,"
        "%.2f,%.2f,%zu,%.6f,%.4f,%.2f,%.2f,%zu,%.6f,%.4f\n",
        r.method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.translation.std,
        r.rel.rotation.mean * kRadToDeg, r.rel.rotation.std * kRadToDeg,
        r.rel.translation_squared.mean, r.rel.rotation_squared.mean * kRadToDeg * kRadToDeg,
        loc ? r.ate.unaligned_translation.rmse : 0.0, loc ? r.ate.translation.rmse : 0.0,
        loc ? r.ate.unaligned_rotation.rmse * kRadToDeg : 0.0,
        r.rpe.ok() ? r.rpe.translation.rmse : 0.0,
        r.rpe.ok() ? r.rpe.rotation.rmse * kRadToDeg : 0.0, r.lost, r.scans, r.has_cov ? 1 : 0,
        r.anees.anees, r.anees.interval.lower, r.anees.interval.upper, r.ms.mean, r.ms.max,
        r.wall_s, r.rel_nees.used, r.rel_nees.skipped_no_covariance, r.rel_nees.mean,
        r.rel_nees.median, r.rel_nees.fraction_inside, r.flagged_lost, r.cpu_ms_max,
        r.has_cov ? r.scans - r.anees.count : 0, r.ms.median, r.ms.p99, r.iterations_median,
        r.iterations_p99, r.converged_pct, r.correct_converged_pct, r.rel_converged.used,
        r.rel_converged.translation.mean, r.rel_converged.rotation.mean * kRadToDeg,
        r.published_pct, r.correct_published_pct, r.rel_published.used,
        r.rel_published.translation.mean, r.rel_published.rotation.mean * kRadToDeg);
    csv << b;
    std::string anees = r.has_cov ? "" : "—";
    if (r.has_cov) {
      char a[96];
      std::snprintf(a, sizeof a, "%.2f [%.2f, %.2f]", r.anees.anees, r.anees.interval.lower,
                    r.anees.interval.upper);
      anees = a;
      const std::string note = eval::left_out_note(r.anees, r.scans, "without a covariance");
      if (!note.empty()) anees += " (" + note + ")";
    }
    std::string rel_nees = "—";
    if (r.rel_nees.ok()) {
      char a[128];
      std::snprintf(a, sizeof a, "%zu, %.1f, %.1f, %.0f %%", r.rel_nees.used, r.rel_nees.mean,
                    r.rel_nees.median, 100.0 * r.rel_nees.fraction_inside);
      rel_nees = a;
    }
    if (!loc) {
      std::snprintf(b, sizeof b,
                    "| %s | %zu | %.4f ± %.4f | %.3f ± %.3f | — | — | — | — | — | — | — | — |\n",
                    r.method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.translation.std,
                    r.rel.rotation.mean * kRadToDeg, r.rel.rotation.std * kRadToDeg);
    } else {
      std::snprintf(b, sizeof b,
                    "| %s | %zu | %.4f ± %.4f | %.3f ± %.3f | %.4f | %.4f / %.3f | %zu | %zu | %s "
                    "| %s | %.2f, %.2f, %.1f (%.1f) | %.3f |\n",
                    r.method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.translation.std,
                    r.rel.rotation.mean * kRadToDeg, r.rel.rotation.std * kRadToDeg,
                    r.ate.unaligned_translation.rmse, r.rpe.translation.rmse,
                    r.rpe.rotation.rmse * kRadToDeg, r.lost, r.flagged_lost, anees.c_str(),
                    rel_nees.c_str(), r.ms.mean, r.ms.median, r.ms.p99, r.ms.max, r.wall_s);
    }
    md << b;
  }
  md << "\nATE: unaligned RMSE against the corrected poses (same frame); RPE: consecutive scans. "
        "Relation NEES: e^T (J_i S_i J_i^T + J_j S_j J_j^T)^-1 e over the relations whose both "
        "ends have a covariance (chi2(3): mean 3, 95 % <= 7.81). "
        "Map VDT built in "
     << build_s << " s.\n";
}

}  // namespace intel_study
