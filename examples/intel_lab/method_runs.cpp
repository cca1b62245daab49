// vdtnav_intel_lab: the localization of the scans by one method, scored against the corrected
// poses and the relations (intel_study.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "intel_study.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace intel_study {

Row localize_method(const std::string& method, const VdtMap2& vdt, const mapping::OccupancyMap& map,
                    const LocalizerSettings& settings, const Eigen::Matrix3d& p0,
                    const Localization& in, const std::string& out) {
  const JoinedLogs& logs = in.logs;
  const std::size_t split = in.split;
  const double sigma_range = in.sigma_range;
  const std::vector<double>& times = in.times;
  const eval::Trajectory2& reference = in.reference;
  const std::vector<OdometryStep>& steps = in.steps;
  const std::vector<Relation>& relations = in.relations;
  const eval::RelationMetricOptions& ro = in.ro;
  std::unique_ptr<Localizer2D> loc =
      make_localizer(method, vdt, map.occupancy, settings, MapKnowledge(map.cells));
  loc->reset(logs.corrected.lasers[0].pose, p0);
  Row r;
  r.method = method;
  r.scans = split;
  eval::Trajectory2 est;
  std::vector<double> nees;
  std::vector<Eigen::Matrix3d> est_cov;  // NaN where the scan has no covariance
  std::vector<double> scan_ms;
  std::vector<double> tracked_iterations;
  eval::Trajectory2 converged_est, published_est;
  std::size_t converged = 0, correct = 0, correct_converged = 0, published = 0,
              correct_published = 0;
  const auto w0 = Clock::now();
  for (std::size_t k = 0; k < split; ++k) {
    LaserScan scan = logs.raw.lasers[k].scan;
    scan.sigma_range = sigma_range;
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    const LocalizationResult res = loc->update(steps[k], scan);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    scan_ms.push_back(ms);
    r.cpu_ms_max = std::max(r.cpu_ms_max, 1e3 * static_cast<double>(std::clock() - c0) /
                                              static_cast<double>(CLOCKS_PER_SEC));
    r.poses.push_back(res.pose);
    r.cov.push_back(res.covariance);
    est.push_back({times[k], res.pose});
    est_cov.push_back(res.has_covariance ? res.covariance
                                         : Eigen::Matrix3d::Constant(std::nan("")));
    if ((res.pose.head<2>() - reference[k].pose.head<2>()).norm() > 0.5) ++r.lost;
    const bool is_converged = res.status == LocalizationStatus::kConverged;
    const bool is_correct = (res.pose.head<2>() - reference[k].pose.head<2>()).norm() <= 0.1;
    converged += is_converged;
    correct += is_correct;
    correct_converged += is_correct && is_converged;
    if (is_converged) converged_est.push_back({times[k], res.pose});
    const bool is_published = published_by_default(res.status);
    published += is_published;
    correct_published += is_correct && is_published;
    if (is_published) published_est.push_back({times[k], res.pose});
    if (res.work.window_searches == 0 && res.work.coarse_to_fine == 0)
      tracked_iterations.push_back(res.iterations);
    if (res.status == LocalizationStatus::kLost) ++r.flagged_lost;
    if (res.has_covariance) {
      r.has_cov = true;
      nees.push_back(eval::nees(res.pose, reference[k].pose, res.covariance));
    }
  }
  r.wall_s = std::chrono::duration<double>(Clock::now() - w0).count();
  r.ms = eval::error_statistics(scan_ms);
  if (!tracked_iterations.empty()) {
    const eval::ErrorStatistics it = eval::error_statistics(tracked_iterations);
    r.iterations_median = it.median;
    r.iterations_p99 = it.p99;
  }
  r.converged_pct = 100.0 * static_cast<double>(converged) / static_cast<double>(split);
  r.correct_converged_pct =
      correct > 0 ? 100.0 * static_cast<double>(correct_converged) / static_cast<double>(correct)
                  : 0.0;
  r.rel = eval::relation_metric(est, relations, ro);
  r.rel_converged = eval::relation_metric(converged_est, relations, ro);
  r.published_pct = 100.0 * static_cast<double>(published) / static_cast<double>(split);
  r.correct_published_pct =
      correct > 0 ? 100.0 * static_cast<double>(correct_published) / static_cast<double>(correct)
                  : 0.0;
  r.rel_published = eval::relation_metric(published_est, relations, ro);
  r.ate = eval::absolute_trajectory_error(est, reference);
  r.rpe = eval::relative_pose_error(est, reference);
  if (r.has_cov) {
    r.anees = eval::anees(nees, 3);
    r.rel_nees = eval::relation_nees(est, est_cov, relations);  // exact stamps, as ro
  }
  std::vector<StampedPose3> tum;
  for (const auto& s : est) tum.push_back({s.t, pose3_from_pose2(s.pose)});
  save_tum_trajectory(out + "/traj_" + method + ".tum", tum);
  std::printf(
      "[intel] %-8s relations %zu: %.4f m / %.3f deg, ATE %.4f m, %zu scans off by > 0.5 m, "
      "%zu flagged lost, %.3f ms per scan (median %.3f, p99 %.1f, max %.1f), %.3f s wall; "
      "%.1f %% converged (%.1f %% of the scans within 0.1 m), %.1f %% published (%.1f %%), "
      "tracked-scan iterations median %.0f p99 %.0f; default output: relations %zu, %.4f m / "
      "%.3f deg\n",
      method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.rotation.mean * kRadToDeg,
      r.ate.unaligned_translation.rmse, r.lost, r.flagged_lost, r.ms.mean, r.ms.median, r.ms.p99,
      r.ms.max, r.wall_s, r.converged_pct, r.correct_converged_pct, r.published_pct,
      r.correct_published_pct, r.iterations_median, r.iterations_p99, r.rel_published.used,
      r.rel_published.translation.mean, r.rel_published.rotation.mean * kRadToDeg);
  return r;
}

}  // namespace intel_study
