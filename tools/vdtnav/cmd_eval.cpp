// vdtnav eval: a trajectory against benchmark relations (Kuemmerle et al. 2009) and/or a reference
// trajectory (ATE with and without SE(2) Umeyama alignment, RPE), and the NEES of its covariance:
// against the reference pose by pose, and against the relations (relation NEES,
// eval/relation_nees.hpp). The trajectory's stamps are in the time base it was localized in
// (`vdtnav localize --time-base`); the relations' must be the same.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "common.hpp"
#include "exit_status.hpp"
#include "plots.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"
#include "vdtnav/io/relations.hpp"

namespace vdtnav::tools {

namespace {

constexpr double kRadToDeg = 57.29577951308232;

struct EvalArgs {
  std::string traj, relations, reference, cov, json_path, plot;
  double max_gap = 1.0;
  double stamp_tolerance = 1e-6;  // relation ends: the microsecond stamps are exact
  double match_tolerance = 0.01;  // estimate <-> reference (and covariance) association
  double rpe_delta = 1.0;
  bool json = false;
};

struct StampedCovariance {
  double t;
  Eigen::Matrix3d c;
};

/// The --cov table of `vdtnav localize` (t,status,explained,xx,xy,xt,yy,yt,tt), or the
/// covariance-only table of earlier versions (t,xx,xy,xt,yy,yt,tt).
std::vector<StampedCovariance> load_covariances(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  constexpr const char* kHeader = "t,status,explained,xx,xy,xt,yy,yt,tt";
  constexpr const char* kOldHeader = "t,xx,xy,xt,yy,yt,tt";
  std::vector<StampedCovariance> out;
  std::string line;
  std::size_t n = 0;
  bool with_status = true;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (n == 1) {
      with_status = line == kHeader;
      if (!with_status && line != kOldHeader) {
        throw FormatError(path, n, std::string("expected the header ") + kHeader);
      }
      continue;
    }
    if (line.empty()) continue;
    // strtod, not operator>>: rows without a covariance hold `nan`.
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    const std::size_t expected = with_status ? 9 : 7;
    std::vector<double> v;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      if (with_status && k == 1) continue;  // the status
      char* end = nullptr;
      const double x = std::strtod(fields[k].c_str(), &end);
      if (end == fields[k].c_str() || *end != '\0') break;
      v.push_back(x);
    }
    if (fields.size() != expected || v.size() != expected - (with_status ? 1 : 0) ||
        !std::isfinite(v[0])) {
      throw FormatError(path, n,
                        std::string("expected ") + (with_status ? kHeader : kOldHeader) +
                            " (numbers, nan allowed but for t)");
    }
    const std::size_t c0 = with_status ? 2 : 1;  // xx's index in v (explained skipped)
    const double xx = v[c0], xy = v[c0 + 1], xt = v[c0 + 2], yy = v[c0 + 3], yt = v[c0 + 4],
                 tt = v[c0 + 5];
    Eigen::Matrix3d c;
    c << xx, xy, xt, xy, yy, yt, xt, yt, tt;
    out.push_back({v[0], c});
  }
  return out;
}

/// The covariance of each trajectory sample: the row closest in time within `tolerance`, NaN
/// where there is none.
std::vector<Eigen::Matrix3d> covariance_per_sample(const eval::Trajectory2& est,
                                                   std::vector<StampedCovariance> covs,
                                                   double tolerance) {
  std::sort(covs.begin(), covs.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  std::vector<Eigen::Matrix3d> out;
  for (const eval::StampedPose2& s : est) {
    const auto it = std::lower_bound(covs.begin(), covs.end(), s.t,
                                     [](const StampedCovariance& c, double t) { return c.t < t; });
    auto best = it;
    if (it != covs.begin() && (it == covs.end() || s.t - (it - 1)->t < it->t - s.t)) best = it - 1;
    out.push_back(best != covs.end() && std::abs(best->t - s.t) <= tolerance
                      ? best->c
                      : Eigen::Matrix3d::Constant(std::nan("")));
  }
  return out;
}

/// A number for JSON: null when not finite.
std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string stats_json(const eval::ErrorStatistics& s) {
  char b[256];
  std::snprintf(b, sizeof b,
                "{\"count\": %zu, \"rmse\": %.9g, \"mean\": %.9g, \"median\": %.9g, \"std\": %.9g, "
                "\"max\": %.9g}",
                s.count, s.rmse, s.mean, s.median, s.std, s.max);
  return b;
}

void print_stats(const char* name, const eval::ErrorStatistics& s, double scale, const char* unit) {
  std::printf("  %-28s rmse %.4f  mean %.4f  median %.4f  std %.4f  max %.4f %s (n = %zu)\n", name,
              s.rmse * scale, s.mean * scale, s.median * scale, s.std * scale, s.max * scale, unit,
              s.count);
}

void run_eval(const EvalArgs& a) {
  if (a.relations.empty() && a.reference.empty()) {
    throw UsageError("vdtnav eval: give --relations REL, --reference REF.tum, or both");
  }
  StagedOutputs staged;  // --json-out and --plot appear when the evaluation completes
  bool plotted = false;
  const eval::Trajectory2 est = load_trajectory2(a.traj);
  std::vector<StampedCovariance> covs;
  if (!a.cov.empty()) covs = load_covariances(a.cov);
  std::ostringstream js;
  js << "{\n  \"trajectory\": \"" << a.traj << "\",\n  \"poses\": " << est.size();
  std::printf("trajectory %s: %zu poses\n", a.traj.c_str(), est.size());

  if (!a.relations.empty()) {
    const std::vector<Relation> rels = load_relations(a.relations).relations;
    eval::RelationMetricOptions ro;
    ro.stamp_tolerance = a.stamp_tolerance;
    ro.interpolate = a.max_gap > 0.0;
    ro.max_gap = a.max_gap;
    const eval::RelationMetricResult m = eval::relation_metric(est, rels, ro);
    std::printf(
        "relations %s: %zu used of %zu (skipped: %zu no stamp within %.3f s, %zu outside "
        "the trajectory, %zu in gaps > %.3f s)\n",
        a.relations.c_str(), m.used, rels.size(), m.skipped_no_stamp, a.stamp_tolerance,
        m.skipped_outside, m.skipped_in_gap, a.max_gap);
    if (m.ok()) {
      std::printf("  translational error  %.4f +- %.4f m     squared %.6f +- %.6f m^2\n",
                  m.translation.mean, m.translation.std, m.translation_squared.mean,
                  m.translation_squared.std);
      std::printf("  rotational error     %.4f +- %.4f deg   squared %.6f +- %.6f deg^2\n",
                  m.rotation.mean * kRadToDeg, m.rotation.std * kRadToDeg,
                  m.rotation_squared.mean * kRadToDeg * kRadToDeg,
                  m.rotation_squared.std * kRadToDeg * kRadToDeg);
    }
    char b[768];
    std::snprintf(b, sizeof b,
                  ",\n  \"relations\": {\"file\": \"%s\", \"total\": %zu, \"used\": %zu, "
                  "\"skipped_no_stamp\": %zu, \"skipped_outside\": %zu, \"skipped_in_gap\": %zu, "
                  "\"trans_mean_m\": %.9g, \"trans_std_m\": %.9g, \"trans2_mean_m2\": %.9g, "
                  "\"trans2_std_m2\": %.9g, \"rot_mean_deg\": %.9g, \"rot_std_deg\": %.9g, "
                  "\"rot2_mean_deg2\": %.9g, \"rot2_std_deg2\": %.9g}",
                  a.relations.c_str(), rels.size(), m.used, m.skipped_no_stamp, m.skipped_outside,
                  m.skipped_in_gap, m.translation.mean, m.translation.std,
                  m.translation_squared.mean, m.translation_squared.std,
                  m.rotation.mean * kRadToDeg, m.rotation.std * kRadToDeg,
                  m.rotation_squared.mean * kRadToDeg * kRadToDeg,
                  m.rotation_squared.std * kRadToDeg * kRadToDeg);
    js << b;
    if (!a.cov.empty()) {
      // Relation NEES: ends at estimate samples (--stamp-tolerance), each with its covariance.
      eval::RelationNeesOptions no;
      no.stamp_tolerance = a.stamp_tolerance;
      const eval::RelationNeesResult rn =
          eval::relation_nees(est, covariance_per_sample(est, covs, a.match_tolerance), rels, no);
      std::printf(
          "relation NEES (%s): %zu relations; skipped: %zu without an estimate at an end, %zu "
          "without a covariance at an end (not localized), %zu singular\n",
          a.cov.c_str(), rn.used, rn.skipped_no_stamp, rn.skipped_no_covariance,
          rn.skipped_singular);
      if (rn.ok()) {
        std::printf(
            "  mean %.3f  median %.3f  inside the chi2(3) 95%% bound %.2f: %.1f %% (consistent: "
            "mean 3, 95 %%)\n",
            rn.mean, rn.median, no.bound, 100.0 * rn.fraction_inside);
      }
      js << ",\n  \"relation_nees\": {\"file\": \"" << a.cov << "\", \"used\": " << rn.used
         << ", \"skipped_no_stamp\": " << rn.skipped_no_stamp
         << ", \"skipped_no_covariance\": " << rn.skipped_no_covariance
         << ", \"skipped_singular\": " << rn.skipped_singular
         << ", \"mean\": " << json_number(rn.ok() ? rn.mean : std::nan(""))
         << ", \"median\": " << json_number(rn.ok() ? rn.median : std::nan(""))
         << ", \"bound\": " << json_number(no.bound)
         << ", \"fraction_inside\": " << json_number(rn.ok() ? rn.fraction_inside : std::nan(""))
         << "}";
    }
  }

  if (!a.reference.empty()) {
    const eval::Trajectory2 ref = load_trajectory2(a.reference);
    eval::AteOptions ao;
    ao.max_time_difference = a.match_tolerance;
    const eval::AteResult ate = eval::absolute_trajectory_error(est, ref, ao);
    eval::RpeOptions rpo;
    rpo.delta = a.rpe_delta;
    rpo.max_time_difference = a.match_tolerance;
    const eval::RpeResult rpe = eval::relative_pose_error(est, ref, rpo);
    std::printf("reference %s: %zu poses, %zu matched within %.3f s\n", a.reference.c_str(),
                ref.size(), ate.matches.size(), a.match_tolerance);
    if (ate.ok()) {
      print_stats("ATE translation (aligned)", ate.translation, 1.0, "m");
      print_stats("ATE rotation (aligned)", ate.rotation, kRadToDeg, "deg");
      print_stats("ATE translation (unaligned)", ate.unaligned_translation, 1.0, "m");
      print_stats("ATE rotation (unaligned)", ate.unaligned_rotation, kRadToDeg, "deg");
    }
    if (rpe.ok()) {
      print_stats("RPE translation", rpe.translation, 1.0, "m");
      print_stats("RPE rotation", rpe.rotation, kRadToDeg, "deg");
    }
    js << ",\n  \"reference\": {\"file\": \"" << a.reference
       << "\", \"matched\": " << ate.matches.size()
       << ", \"ate_aligned_trans_m\": " << stats_json(ate.translation)
       << ", \"ate_aligned_rot_rad\": " << stats_json(ate.rotation)
       << ", \"ate_trans_m\": " << stats_json(ate.unaligned_translation)
       << ", \"ate_rot_rad\": " << stats_json(ate.unaligned_rotation)
       << ", \"rpe_frames\": " << a.rpe_delta
       << ", \"rpe_trans_m\": " << stats_json(rpe.translation)
       << ", \"rpe_rot_rad\": " << stats_json(rpe.rotation) << "}";

    std::vector<double> nees_values;
    std::vector<double> t_plot;
    std::vector<Eigen::Vector3d> err_plot, sig_plot;
    std::size_t ci = 0;
    for (const auto& m : ate.matches) {
      const eval::StampedPose2& e = est[m.estimate];
      const Eigen::Vector3d err = pose_error(e.pose, ref[m.reference].pose);
      t_plot.push_back(e.t - est.front().t);
      err_plot.push_back(err);
      if (!covs.empty()) {
        while (ci < covs.size() && covs[ci].t < e.t - a.match_tolerance) ++ci;
        if (ci < covs.size() && std::abs(covs[ci].t - e.t) <= a.match_tolerance &&
            covs[ci].c.allFinite()) {
          nees_values.push_back(eval::nees(e.pose, ref[m.reference].pose, covs[ci].c));
          sig_plot.push_back(2.0 * covs[ci].c.diagonal().cwiseSqrt());
        } else {
          sig_plot.push_back(Eigen::Vector3d::Constant(std::nan("")));
        }
      }
    }
    if (!a.cov.empty()) {
      const eval::AneesResult an = eval::anees(nees_values, 3);
      std::printf(
          "NEES (%s against the reference): ANEES %.3f, 95%% interval [%.3f, %.3f] over %zu "
          "poses: %s%s%s\n",
          a.cov.c_str(), an.anees, an.interval.lower, an.interval.upper, an.count,
          an.count == 0                  ? "no covariance matched"
          : an.failures > 0              ? "inconsistent (a covariance gave no finite NEES)"
          : an.consistent                ? "consistent"
          : an.anees > an.interval.upper ? "over-confident"
                                         : "conservative",
          an.count + an.failures < err_plot.size() || an.failures > 0 ? "; " : "",
          eval::left_out_note(an, err_plot.size(), "without a covariance").c_str());
      char b[256];
      std::snprintf(b, sizeof b,
                    ",\n  \"nees\": {\"file\": \"%s\", \"count\": %zu, \"failures\": %zu, "
                    "\"anees\": %.9g, \"lo\": %.9g, \"hi\": %.9g}",
                    a.cov.c_str(), an.count, an.failures, an.anees, an.interval.lower,
                    an.interval.upper);
      js << b;
    }
    if (!a.plot.empty() && !err_plot.empty()) {
      plot_errors(staged.file(a.plot + "_errors.png"), t_plot, err_plot, sig_plot,
                  "error against " + a.reference + " (unaligned)");
      plotted = true;
    }
  }
  js << "\n}\n";
  if (a.json) std::printf("%s", js.str().c_str());
  if (!a.json_path.empty()) {
    std::ofstream f(staged.file(a.json_path));
    if (!f) throw IoError(a.json_path + ": cannot open for writing");
    f << js.str();
    if (!f.flush()) throw IoError(a.json_path + ": write failed");
  }
  staged.commit();
  if (plotted) std::printf("wrote %s_errors.png\n", a.plot.c_str());
}

}  // namespace

void add_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Evaluate a trajectory against benchmark relations and/or a reference trajectory");
  cmd->add_option("--traj", args->traj, "Estimated trajectory (TUM)")
      ->required()
      ->check(input_file("--traj"));
  cmd->add_option("--relations", args->relations, "Kuemmerle relations file (t1 t2 x y z r p y)")
      ->check(input_file("--relations"));
  cmd->add_option("--reference", args->reference, "Reference trajectory (TUM)")
      ->check(input_file("--reference"));
  cmd->add_option("--cov", args->cov,
                  "Covariances (the CSV `localize --cov` writes: "
                  "t,status,explained,xx,xy,xt,yy,yt,tt): NEES "
                  "against --reference; relation NEES (mean, median, fraction <= 7.81) with "
                  "--relations")
      ->check(input_file("--cov"));
  cmd->add_option("--max-gap", args->max_gap,
                  "Interpolate the estimate at relation ends only inside gaps up to S seconds "
                  "(0: exact stamps only)")
      ->capture_default_str();
  cmd->add_option("--stamp-tolerance", args->stamp_tolerance,
                  "Seconds within which an estimate counts as taken at a relation's stamp "
                  "(the Kuemmerle stamps are exact to the microsecond)")
      ->capture_default_str();
  cmd->add_option(
         "--match-tolerance", args->match_tolerance,
         "Seconds within which an estimate is matched to a --reference pose or a --cov row")
      ->capture_default_str();
  cmd->add_option("--rpe-delta", args->rpe_delta, "RPE pair spacing, frames")
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "Also print the results as JSON");
  cmd->add_option("--json-out", args->json_path, "Write the JSON to this file");
  cmd->add_option("--plot", args->plot, "Figure prefix: PREFIX_errors.png (needs --reference)")
      ->check(plot_option_check);
  cmd->callback([args] { run_eval(*args); });
}

}  // namespace vdtnav::tools
