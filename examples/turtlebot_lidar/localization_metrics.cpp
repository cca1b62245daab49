// The metrics of the Table 3.3 study: one method's errors, ANEES, lost fraction and timings on one
// run, and their combination over repeats.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>

#include "turtlebot_study.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace turtlebot_study {

using namespace vdtnav;

namespace {

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}
double stdev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / (v.size() - 1));
}

/// The per-scan times of `m`: `ms` and its statistics.
void set_times(Metrics& m, std::vector<double> ms) {
  m.ms_stats = eval::error_statistics(ms);
  m.ms = std::move(ms);
}

}  // namespace

Metrics evaluate(const Trace& t, const sim::SimulatedRun& run) {
  Metrics m;
  std::vector<double> pe, oe, pe2, oe2, nees;
  int lost = 0;
  for (std::size_t k = 1; k < run.size(); ++k) {
    const Eigen::Vector3d e = pose_error(t.estimate[k], run.truth[k]);
    const double p = e.head<2>().norm(), o = std::abs(e[2]);
    pe.push_back(p);
    oe.push_back(o);
    pe2.push_back(p * p);
    oe2.push_back(o * o);
    lost += p > 0.5 ? 1 : 0;
    if (t.has_cov[k]) nees.push_back(e.dot(t.covariance[k].ldlt().solve(e)));
  }
  m.pos_mae = mean(pe), m.pos_mae_std = stdev(pe), m.ori_mae = mean(oe), m.ori_mae_std = stdev(oe);
  m.pos_mse = mean(pe2), m.pos_mse_std = stdev(pe2), m.ori_mse = mean(oe2),
  m.ori_mse_std = stdev(oe2);
  // A scan without a covariance (the estimator said it has none) has no NEES: the ANEES is over
  // the scans that reported one, and the others are counted.
  m.has_cov = !nees.empty();
  m.without_cov = static_cast<int>(pe.size() - nees.size());
  if (m.has_cov) {
    m.anees = mean(nees);
    const eval::ChiSquareInterval bounds = eval::anees_interval(nees.size(), 3, 0.95);
    m.anees_lo = bounds.lower;
    m.anees_hi = bounds.upper;
    m.nees_inside_95_pct = eval::anees(nees, 3).inside_95_pct;
  }
  m.lost_pct = 100.0 * lost / static_cast<double>(pe.size());
  set_times(m, t.ms);
  return m;
}

Metrics combine(const std::vector<Metrics>& r) {
  if (r.size() == 1) return r[0];
  Metrics m;
  auto col = [](double Metrics::*f, const std::vector<Metrics>& of) {
    std::vector<double> v;
    for (const auto& x : of) v.push_back(x.*f);
    return v;
  };
  m.pos_mae = mean(col(&Metrics::pos_mae, r)), m.pos_mae_std = stdev(col(&Metrics::pos_mae, r));
  m.ori_mae = mean(col(&Metrics::ori_mae, r)), m.ori_mae_std = stdev(col(&Metrics::ori_mae, r));
  m.pos_mse = mean(col(&Metrics::pos_mse, r)), m.pos_mse_std = stdev(col(&Metrics::pos_mse, r));
  m.ori_mse = mean(col(&Metrics::ori_mse, r)), m.ori_mse_std = stdev(col(&Metrics::ori_mse, r));
  std::vector<Metrics> with_cov;
  for (const auto& x : r) {
    m.without_cov += x.without_cov;
    if (x.has_cov) with_cov.push_back(x);
  }
  m.has_cov = !with_cov.empty();
  if (m.has_cov) {
    m.anees = mean(col(&Metrics::anees, with_cov));
    m.anees_lo = mean(col(&Metrics::anees_lo, with_cov));
    m.anees_hi = mean(col(&Metrics::anees_hi, with_cov));
    m.nees_inside_95_pct = mean(col(&Metrics::nees_inside_95_pct, with_cov));
  }
  m.lost_pct = mean(col(&Metrics::lost_pct, r));
  std::vector<double> ms;
  for (const auto& x : r) ms.insert(ms.end(), x.ms.begin(), x.ms.end());
  set_times(m, std::move(ms));
  return m;
}

}  // namespace turtlebot_study
