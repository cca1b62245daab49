// The Table 3.3 table: table.csv, table.md and the printed table, the repeats combined.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "turtlebot_study.hpp"

namespace turtlebot_study {

void write_tables(const std::string& out, const std::vector<std::string>& methods,
                  const std::vector<std::vector<Metrics>>& per_method) {
  std::ofstream csv(out + "/table.csv");
  csv << "method,pos_mae_m,pos_mae_std_m,ori_mae_rad,ori_mae_std_rad,pos_mse_m2,pos_mse_std_m2,"
         "ori_mse_rad2,"
         "ori_mse_std_rad2,has_cov,anees,anees_lo,anees_hi,lost_pct,ms_mean,ms_max,ms_median,ms_"
         "p99,nees_inside_95_pct\n";
  std::ofstream md(out + "/table.md");
  md << "| method | position MAE (m) | orientation MAE (rad) | position MSE (m^2 x 1e-3) | "
        "orientation MSE "
        "(rad^2 x 1e-3) | P_k | ANEES [95 % interval] | NEES ≤ χ²₃(95 %) (%) | lost % | ms mean | "
        "ms median | ms p99 | ms max |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::printf("\n%-8s %18s %18s %8s %22s %7s %8s %8s\n", "method", "pos MAE (m)", "ori MAE (rad)",
              "P_k", "ANEES [95%]", "lost%", "ms mean", "ms max");
  for (std::size_t m = 0; m < methods.size(); ++m) {
    const Metrics x = combine(per_method[m]);
    char line[512], inside[16] = "—";
    if (x.has_cov) std::snprintf(inside, sizeof inside, "%.1f", x.nees_inside_95_pct);
    std::snprintf(
        line, sizeof line,
        "%s,%.6f,%.6f,%.6f,%.6f,%.8f,%.8f,%.8f,%.8f,%d,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f,%.4f,"
        "%.4f,%.1f\n",
        methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std, x.pos_mse,
        x.pos_mse_std, x.ori_mse, x.ori_mse_std, x.has_cov ? 1 : 0,
        x.has_cov ? x.anees : std::nan(""), x.anees_lo, x.anees_hi, x.lost_pct, x.ms_stats.mean,
        x.ms_stats.max, x.ms_stats.median, x.ms_stats.p99,
        x.has_cov ? x.nees_inside_95_pct : std::nan(""));
    csv << line;
    std::snprintf(
        line, sizeof line,
        "| %s | %.4f ± %.4f | %.4f ± %.4f | %.4f ± %.4f | %.4f ± %.4f | %s | %s | %s | "
        "%.2f | %.3f | %.3f | %.3f | %.3f |\n",
        methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std, 1e3 * x.pos_mse,
        1e3 * x.pos_mse_std, 1e3 * x.ori_mse, 1e3 * x.ori_mse_std, x.has_cov ? "✓" : "✗",
        x.has_cov
            ? (std::to_string(x.anees).substr(0, 5) + " [" +
               std::to_string(x.anees_lo).substr(0, 4) + ", " +
               std::to_string(x.anees_hi).substr(0, 4) + "]" +
               (x.without_cov > 0 ? " (" + std::to_string(x.without_cov) + " scans without P_k)"
                                  : std::string()))
                  .c_str()
            : "—",
        inside, x.lost_pct, x.ms_stats.mean, x.ms_stats.median, x.ms_stats.p99, x.ms_stats.max);
    md << line;
    std::printf("%-8s %8.4f ± %7.4f %8.4f ± %7.4f %8s %8.3f [%.2f,%.2f] %7.2f %8.3f %8.3f\n",
                methods[m].c_str(), x.pos_mae, x.pos_mae_std, x.ori_mae, x.ori_mae_std,
                x.has_cov ? "yes" : "no", x.anees, x.anees_lo, x.anees_hi, x.lost_pct,
                x.ms_stats.mean, x.ms_stats.max);
  }
}

}  // namespace turtlebot_study
