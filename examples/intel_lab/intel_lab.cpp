// vdtnav_intel_lab: the Intel Research Lab study (thesis 3.4.2, Dataset 2) on the real log.
//
// The data (../shared/data/intel-lab): the GMapping-corrected log (910 scans of 180 beams), a
// table joining each scan's raw odometry and corrected pose on the absolute time base of the
// Kuemmerle et al. benchmark relations. The thesis built its map from the third loop and
// localized the first two; here:
//   1. join the log and the table (the converter behind `vdtnav join-odometry`);
//   2. build an occupancy map (log-odds ray casting) from the corrected poses of the last third of
//      the scans, and its VDT map (`vdtnav map`);
//   3. localize the first two thirds with the raw odometry and the scans, with every method
//      (`vdtnav localize`), starting at the corrected pose of the first scan;
//   4. evaluate against the relations whose both ends are localized scans (exact stamps)
//      and against the corrected poses: ATE, RPE, lost scans (> 0.5 m), NEES, and the relation
//      NEES of the methods with a covariance (`vdtnav eval --relations R --cov C`); count the
//      scans each method reports lost (status kLost: flagged_lost).
// Writes table.csv, table.md and PNGs (map, trajectories, reprojected scans, errors over time).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/viz/viz.hpp"

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;
constexpr double kRadToDeg = 57.29577951308232;

struct Row {
  std::string method;
  eval::RelationMetricResult rel;
  eval::AteResult ate;
  eval::RpeResult rpe;
  std::size_t lost = 0, scans = 0;  ///< lost: farther than 0.5 m from the corrected pose
  std::size_t flagged_lost = 0;     ///< reported lost (status kLost)
  bool has_cov = false;
  eval::AneesResult anees;
  eval::RelationNeesResult rel_nees;  ///< relations whose both ends have a covariance
  double ms_mean = 0.0, ms_max = 0.0, wall_s = 0.0;
  /// The slowest update's processor time (std::clock): its own work, without the time other
  /// processes of a shared machine took from it (ms_max, wall time, includes that).
  double cpu_ms_max = 0.0;
  std::vector<Pose2> poses;
  std::vector<Eigen::Matrix3d> cov;
};

viz::RgbImage ros_image(const Grid<std::int8_t, 2>& cells) {
  const int w = cells.size().x(), h = cells.size().y();
  viz::RgbImage img(w, h);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const int v = cells(Eigen::Vector2i(i, j));
      const auto g = static_cast<std::uint8_t>(v < 0 ? 205 : (v >= 65 ? 0 : 255));
      img.set(i, h - 1 - j, {g, g, g});
    }
  }
  return img;
}

void map_axes(viz::Axes& ax, const Grid<std::int8_t, 2>& cells) {
  const auto& f = cells.frame();
  ax.image(ros_image(cells), f.origin().x(), f.origin().x() + cells.size().x() * f.resolution(),
           f.origin().y(), f.origin().y() + cells.size().y() * f.resolution())
      .equal_aspect()
      .xlabel("x [m]")
      .ylabel("y [m]");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The Intel Research Lab study: map from the last third, localize the first two"};
  std::string data = "../shared/data", out = "out/intel_lab";
  double resolution = 0.05, sigma_range = 0.02;
  std::vector<std::string> methods = localizer_methods();
  app.add_option("--data", data, "Folder with intel-lab/ (read in place)")->capture_default_str();
  app.add_option("--out", out, "Output folder")->capture_default_str();
  app.add_option("--resolution", resolution, "Map resolution, metres")->capture_default_str();
  app.add_option("--sigma-range", sigma_range, "Range noise standard deviation, metres")
      ->capture_default_str();
  app.add_option("--methods", methods, "Methods to run")
      ->check(CLI::IsMember(localizer_methods()))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    const std::string dir = data + "/intel-lab/";
    std::filesystem::create_directories(out);
    std::printf("[intel] joining %sintel.gfs.log.gz with the raw-odometry table\n", dir.c_str());
    const CarmenLog gfs = load_carmen_log(dir + "intel.gfs.log.gz");
    const std::string table_path = dir + "intel_910_odom_vs_corrected.txt";
    const JoinedLogs logs = join_odometry_table(gfs, load_odometry_table(table_path), table_path);
    const std::size_t n = logs.raw.lasers.size();
    const std::size_t split = n - n / 3;  // the last third maps, the first two thirds localize
    save_carmen_log(out + "/intel_raw.log", logs.raw);
    std::vector<StampedPose3> reference_tum;
    for (const auto& l : logs.corrected.lasers)
      reference_tum.push_back({l.time, pose3_from_pose2(l.pose)});
    save_tum_trajectory(out + "/intel_corrected.tum", reference_tum);

    // 2. The map from the corrected poses of scans split..n-1.
    std::vector<Pose2> map_poses;
    std::vector<LaserScan> map_scans;
    for (std::size_t i = split; i < n; ++i) {
      map_poses.push_back(logs.corrected.lasers[i].pose);
      map_scans.push_back(logs.corrected.lasers[i].scan);
    }
    mapping::OccupancyMapperOptions mo;
    mo.resolution = resolution;
    const mapping::OccupancyMap map = mapping::build_occupancy_map(map_poses, map_scans, mo);
    save_ros_map(out + "/intel_map", map.cells);
    const auto tb = Clock::now();
    const VdtMap2 vdt = VdtMap2::build(map.occupancy);
    const double build_s = std::chrono::duration<double>(Clock::now() - tb).count();
    std::printf(
        "[intel] map from scans %zu..%zu (t = %.1f..%.1f): %d x %d cells of %.2f m, VDT "
        "built in %.3f s -> %s/intel_map.yaml\n",
        split, n - 1, logs.raw.lasers[split].time, logs.raw.lasers[n - 1].time,
        map.cells.size().x(), map.cells.size().y(), resolution, build_s, out.c_str());

    // 3. Localize scans 0..split-1 with the raw odometry.
    std::vector<std::size_t> idx(split);
    for (std::size_t i = 0; i < split; ++i) idx[i] = i;
    const LogOdometry odom = log_odometry(logs.raw, idx);
    std::vector<double> times;
    eval::Trajectory2 reference;
    for (std::size_t i : idx) {
      times.push_back(logs.raw.lasers[i].time);
      reference.push_back({logs.raw.lasers[i].time, logs.corrected.lasers[i].pose});
    }
    const std::vector<OdometryStep> steps = odometry_steps(times, odom.poses);
    const std::vector<Relation> relations = load_relations(dir + "intel.relations").relations;
    eval::RelationMetricOptions ro;  // exact stamps only: one scan every ~3 s
    ro.stamp_tolerance = 1e-6;
    ro.interpolate = false;

    std::vector<Row> rows;
    {  // The GMapping-corrected poses themselves, for scale.
      Row r;
      r.method = "gmapping (reference)";
      r.rel = eval::relation_metric(reference, relations, ro);
      r.scans = split;
      rows.push_back(r);
    }
    const LocalizerSettings settings = log_settings();
    const Eigen::Matrix3d p0 = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05).asDiagonal();
    for (const std::string& method : methods) {
      std::unique_ptr<Localizer2D> loc =
          make_localizer(method, vdt, map.occupancy, settings, MapKnowledge(map.cells));
      loc->reset(logs.corrected.lasers[0].pose, p0);
      Row r;
      r.method = method;
      r.scans = split;
      eval::Trajectory2 est;
      std::vector<double> nees;
      std::vector<Eigen::Matrix3d> est_cov;  // NaN where the scan has no covariance
      const auto w0 = Clock::now();
      for (std::size_t k = 0; k < split; ++k) {
        LaserScan scan = logs.raw.lasers[k].scan;
        scan.sigma_range = sigma_range;
        const auto t0 = Clock::now();
        const std::clock_t c0 = std::clock();
        const LocalizationResult res = loc->update(steps[k], scan);
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        r.ms_mean += ms / static_cast<double>(split);
        r.ms_max = std::max(r.ms_max, ms);
        r.cpu_ms_max = std::max(r.cpu_ms_max, 1e3 * static_cast<double>(std::clock() - c0) /
                                                  static_cast<double>(CLOCKS_PER_SEC));
        r.poses.push_back(res.pose);
        r.cov.push_back(res.covariance);
        est.push_back({times[k], res.pose});
        est_cov.push_back(res.has_covariance ? res.covariance
                                             : Eigen::Matrix3d::Constant(std::nan("")));
        if ((res.pose.head<2>() - reference[k].pose.head<2>()).norm() > 0.5) ++r.lost;
        if (res.status == LocalizationStatus::kLost) ++r.flagged_lost;
        if (res.has_covariance) {
          r.has_cov = true;
          nees.push_back(eval::nees(res.pose, reference[k].pose, res.covariance));
        }
      }
      r.wall_s = std::chrono::duration<double>(Clock::now() - w0).count();
      r.rel = eval::relation_metric(est, relations, ro);
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
          "%zu flagged lost, %.3f ms per scan (max %.1f), %.3f s wall\n",
          method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.rotation.mean * kRadToDeg,
          r.ate.unaligned_translation.rmse, r.lost, r.flagged_lost, r.ms_mean, r.ms_max, r.wall_s);
      rows.push_back(std::move(r));
    }

    // 4. Tables.
    std::ofstream csv(out + "/table.csv");
    csv << "method,relations,rel_trans_mean_m,rel_trans_std_m,rel_rot_mean_deg,rel_rot_std_deg,"
           "rel_trans2_mean_m2,rel_rot2_mean_deg2,ate_rmse_m,ate_aligned_rmse_m,ate_rot_rmse_deg,"
           "rpe_trans_rmse_m,rpe_rot_rmse_deg,lost,scans,has_cov,anees,anees_lo,anees_hi,ms_mean,"
           "ms_max,wall_s,rel_nees_used,rel_nees_skipped_no_cov,rel_nees_mean,rel_nees_median,"
           "rel_nees_inside_7.81,flagged_lost,cpu_ms_max,anees_left_out\n";
    std::ofstream md(out + "/table.md");
    md << "Intel Research Lab: map from scans " << split << ".." << n - 1
       << " (corrected poses), localization of scans 0.." << split - 1
       << " with raw odometry. Relations: both ends localized scans (exact stamps).\n\n"
       << "| method | relations | trans. err. (m) | rot. err. (deg) | ATE (m) | RPE (m / deg) | "
          "off > 0.5 m | flagged lost | ANEES [95 %] | relation NEES: n, mean, median, ≤ 7.81 | "
          "ms/scan (max) | wall (s) |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows) {
      char b[1024];
      const bool loc = r.ate.ok();
      std::snprintf(
          b, sizeof b,
          "%s,%zu,%.6f,%.6f,%.4f,%.4f,%.8f,%.6f,%.6f,%.6f,%.4f,%.6f,%.4f,%zu,%zu,%d,%.4f,"
          "%.4f,%.4f,%.4f,%.4f,%.4f,%zu,%zu,%.4f,%.4f,%.4f,%zu,%.3f,%zu\n",
          r.method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.translation.std,
          r.rel.rotation.mean * kRadToDeg, r.rel.rotation.std * kRadToDeg,
          r.rel.translation_squared.mean, r.rel.rotation_squared.mean * kRadToDeg * kRadToDeg,
          loc ? r.ate.unaligned_translation.rmse : 0.0, loc ? r.ate.translation.rmse : 0.0,
          loc ? r.ate.unaligned_rotation.rmse * kRadToDeg : 0.0,
          r.rpe.ok() ? r.rpe.translation.rmse : 0.0,
          r.rpe.ok() ? r.rpe.rotation.rmse * kRadToDeg : 0.0, r.lost, r.scans, r.has_cov ? 1 : 0,
          r.anees.anees, r.anees.interval.lower, r.anees.interval.upper, r.ms_mean, r.ms_max,
          r.wall_s, r.rel_nees.used, r.rel_nees.skipped_no_covariance, r.rel_nees.mean,
          r.rel_nees.median, r.rel_nees.fraction_inside, r.flagged_lost, r.cpu_ms_max,
          r.has_cov ? r.scans - r.anees.count : 0);
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
        std::snprintf(
            b, sizeof b,
            "| %s | %zu | %.4f ± %.4f | %.3f ± %.3f | %.4f | %.4f / %.3f | %zu | %zu | %s "
            "| %s | %.2f (%.1f) | %.3f |\n",
            r.method.c_str(), r.rel.used, r.rel.translation.mean, r.rel.translation.std,
            r.rel.rotation.mean * kRadToDeg, r.rel.rotation.std * kRadToDeg,
            r.ate.unaligned_translation.rmse, r.rpe.translation.rmse,
            r.rpe.rotation.rmse * kRadToDeg, r.lost, r.flagged_lost, anees.c_str(),
            rel_nees.c_str(), r.ms_mean, r.ms_max, r.wall_s);
      }
      md << b;
    }
    md << "\nATE: unaligned RMSE against the corrected poses (same frame); RPE: consecutive scans. "
          "Relation NEES: e^T (J_i S_i J_i^T + J_j S_j J_j^T)^-1 e over the relations whose both "
          "ends have a covariance (chi2(3): mean 3, 95 % <= 7.81). "
          "Map VDT built in "
       << build_s << " s.\n";

    // 5. Figures.
    {
      viz::Figure fig(1400, 1300);
      viz::Axes& ax = fig.axes();
      map_axes(ax, map.cells);
      ax.title("Intel lab: trajectories over the map built from the last third");
      std::vector<double> rx, ry;
      for (const auto& s : reference) {
        rx.push_back(s.pose[0]);
        ry.push_back(s.pose[1]);
      }
      ax.line(rx, ry,
              viz::Style{}.with_color({0, 0, 0}).with_width(2.5).with_dashes().with_label(
                  "corrected (GMapping)"));
      for (std::size_t k = 1; k < rows.size(); ++k) {
        std::vector<double> xs, ys;
        for (const Pose2& p : rows[k].poses) {
          xs.push_back(p[0]);
          ys.push_back(p[1]);
        }
        ax.line(xs, ys, viz::Style{}.with_width(1.5).with_label(rows[k].method));
      }
      ax.legend(viz::LegendLocation::kUpperRight);
      fig.save_png(out + "/trajectories.png");
    }
    for (std::size_t k = 1; k < rows.size(); ++k) {
      const Row& r = rows[k];
      if (r.method != "vdt-opt" && r.method != "vdt-ekf") continue;
      viz::Figure fig(1400, 1300);
      viz::Axes& ax = fig.axes();
      map_axes(ax, map.cells);
      ax.title("scans reprojected from the " + r.method + " poses (scans 0.." +
               std::to_string(split - 1) + ")");
      std::vector<double> xs, ys;
      for (std::size_t i = 0; i < r.poses.size(); ++i) {
        for (const auto& p : scan_points(logs.raw.lasers[i].scan).points) {
          const Eigen::Vector2d q = transform_point(r.poses[i], p);
          xs.push_back(q.x());
          ys.push_back(q.y());
        }
      }
      ax.scatter(xs, ys,
                 viz::Style{}
                     .with_color(viz::kColorCycle[1])
                     .with_marker(viz::Marker::kCircle, 2.0)
                     .with_alpha(0.3));
      fig.save_png(out + "/scans_" + r.method + ".png");

      viz::Figure ef(1400, 1100, 3, 1);
      ef.title(r.method + ": error against the corrected poses, with +-2 sigma");
      const char* names[3] = {"x error [m]", "y error [m]", "yaw error [rad]"};
      for (int c = 0; c < 3; ++c) {
        std::vector<double> t, e, lo, hi;
        for (std::size_t i = 0; i < r.poses.size(); ++i) {
          t.push_back(times[i] - times[0]);
          e.push_back(pose_error(r.poses[i], reference[i].pose)[c]);
          const double s2 = 2.0 * std::sqrt(std::max(0.0, r.cov[i](c, c)));
          lo.push_back(-s2);
          hi.push_back(s2);
        }
        viz::Axes& ax2 = ef.axes(c, 0);
        ax2.band(t, lo, hi, viz::Style{}.with_color(viz::kColorCycle[0]).with_label("+-2 sigma"));
        ax2.line(t, e,
                 viz::Style{}.with_color(viz::kColorCycle[1]).with_width(1.5).with_label("error"));
        ax2.ylabel(names[c]).grid(true);
        if (c == 2) ax2.xlabel("time [s]");
        ax2.legend(c == 0 ? viz::LegendLocation::kUpperRight : viz::LegendLocation::kNone);
      }
      ef.save_png(out + "/errors_" + r.method + ".png");
    }
    std::printf(
        "[intel] wrote %s/table.csv, table.md, trajectories.png, scans_*.png, errors_*.png\n",
        out.c_str());
    std::ifstream t(out + "/table.md");
    std::printf("%s", std::string(std::istreambuf_iterator<char>(t), {}).c_str());
  } catch (const vdtnav::Error& e) {
    std::fprintf(stderr, "vdtnav_intel_lab: %s\n", e.what());
    return 1;
  }
  return 0;
}
