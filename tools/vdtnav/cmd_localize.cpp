// vdtnav localize: one localizer over a log on a map. Odometry from the log's ODOM lines (or the
// laser messages' odometry fields when those are unusable), one TUM line per scan in the log's
// time base (`--time-base logger|ipc`), the 3x3 covariance per scan as CSV, and figures. A run
// in which the map explains almost no scan is a dead-reckoning trajectory: it is said on stderr,
// and with --strict it fails.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include "common.hpp"
#include "exit_status.hpp"
#include "parse.hpp"
#include "plots.hpp"
#include "progress.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#ifdef VDTNAV_CLI_ROS
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/scan_sequence.hpp"
#endif

namespace vdtnav::tools {

namespace {

/// Below this fraction of converged scans the map does not explain the log (a wrong map, start
/// pose or time window): the trajectory is the odometry, and the run is reported as such.
constexpr double kMinLocalizedFraction = 0.10;

struct LocalizeArgs {
  std::string map, log, bag, method = "vdt-opt", init, init_sigma = "0.1,0.1,0.05", out, cov, plot;
  std::string odometry = "auto";
  std::string time_base = "logger";
  std::string config;
  bool print_config = false;
  TimeWindow window;
  double sigma_range = 0.02;
  double max_range = 80.0;
  bool max_range_given = false;  // else the log's own no-return code may lower it
  bool skip_malformed = false;
  bool quiet = false;
  bool strict = false;
  bool recover = false, no_recover = false;
  bool all_poses = false;
  // published_by_default(): the localizations on the map and the bridges across its gaps.
  std::string accept_status = "converged,bridged";
  // --bag: which topics and frames (vdtnav/ros/scan_sequence.hpp)
  std::string scan_topic, odom_topic, odom_frame = "odom", base_frame = "base_link", laser_pose;
  int threads = -1;  // --threads; -1: the settings' threads:
};

/// The scans to localize, from a CARMEN log or a bag: stamps, scans, odometry at each, and the
/// pose of the first when the input knows one (a CARMEN log's corrected pose).
struct ScanRun {
  std::string input;  // the --log or --bag path
  std::vector<double> times;
  std::vector<LaserScan> scans;
  std::vector<Pose2> odometry;
  std::optional<Pose2> first_pose;
  // Input scans not localized, with their status: no_odometry (outside the odometry's time span)
  // or no_transform (older than the first mounting transform).
  std::vector<std::pair<double, std::string>> not_localized;
};

ScanRun read_log_run(const LocalizeArgs& a) {
  CarmenLogOptions lo;
  lo.max_range = a.max_range;
  lo.skip_malformed = a.skip_malformed;
  CarmenLog log = load_log(a.log, lo, a.time_base);
  if (!a.max_range_given) apply_no_return_code(log, "localize");
  const std::vector<std::size_t> idx = scans_in(log, a.window);
  if (idx.empty()) {
    throw UsageError(a.log + ": no laser message in the time window (the log has " +
                     std::to_string(log.lasers.size()) + " scans)");
  }
  LogOdometry odom = log_odometry(log, idx);
  if (a.odometry == "laser" && odom.source != LogOdometrySource::kLaserOdomFields) {
    odom.source = LogOdometrySource::kLaserOdomFields;
    odom.reason = "--odometry laser";
    odom.poses.clear();
    for (std::size_t i : idx) odom.poses.push_back(log.lasers[i].odom);
  } else if (a.odometry == "odom" && odom.source != LogOdometrySource::kOdomMessages) {
    throw ConfigError(a.log + ": --odometry odom, but the ODOM lines are unusable: " + odom.reason);
  }
  std::fprintf(stderr, "[localize] %zu scans, odometry from %s%s%s\n", idx.size(),
               odom.source == LogOdometrySource::kOdomMessages ? "ODOM lines"
                                                               : "the laser messages' odom fields",
               odom.reason.empty() ? "" : " (ODOM lines unusable: ",
               odom.reason.empty() ? "" : (odom.reason + ")").c_str());
  ScanRun run;
  run.input = a.log;
  for (std::size_t i : idx) {
    run.times.push_back(log.lasers[i].time);
    run.scans.push_back(log.lasers[i].scan);
  }
  run.odometry = std::move(odom.poses);
  run.first_pose = log.lasers[idx.front()].pose;
  return run;
}

#ifdef VDTNAV_CLI_ROS
ScanRun read_bag_run(const LocalizeArgs& a) {
  const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(a.bag);
  ros::ScanSequenceOptions o;
  o.scan_topic = a.scan_topic;
  o.odom_topic = a.odom_topic;
  o.odom_frame = a.odom_frame;
  o.base_frame = a.base_frame;
  if (!a.laser_pose.empty()) o.laser_pose = parse_pose(a.laser_pose, "--laser-pose");
  o.sigma_range = a.sigma_range;
  if (a.max_range_given) o.max_range = a.max_range;
  ros::ScanSequence seq = ros::read_scan_sequence(*bag, o);
  std::string left_out;
  if (seq.skipped_no_odometry > 0) {
    left_out += "; " + std::to_string(seq.skipped_no_odometry) +
                " scans outside the odometry's time span left out (no_odometry)";
  }
  if (seq.skipped_no_transform > 0) {
    left_out += "; " + std::to_string(seq.skipped_no_transform) +
                " scans older than the first mounting transform left out (no_transform)";
  }
  std::fprintf(stderr,
               "[localize] %zu scans of %s (frame %s), odometry from %s, mounting from %s%s\n",
               seq.scans.size(), seq.scan_topic.c_str(), seq.scan_frame.c_str(),
               seq.odometry_source.c_str(), seq.mount_source.c_str(), left_out.c_str());
  if (!seq.scan_topic_choice.empty()) {
    std::fprintf(stderr, "[localize] scans: %s\n", seq.scan_topic_choice.c_str());
  }
  ScanRun run;
  run.input = a.bag;
  for (double t : seq.skipped_times) {
    if (a.window.contains(t)) run.not_localized.emplace_back(t, "no_odometry");
  }
  for (double t : seq.no_transform_times) {
    if (a.window.contains(t)) run.not_localized.emplace_back(t, "no_transform");
  }
  for (std::size_t k = 0; k < seq.scans.size(); ++k) {
    if (!a.window.contains(seq.scans[k].time)) continue;
    run.times.push_back(seq.scans[k].time);
    run.scans.push_back(std::move(seq.scans[k]));
    run.odometry.push_back(seq.odometry[k]);
  }
  if (run.scans.empty()) {
    throw UsageError(a.bag + ": no scan in the time window (the bag has " +
                     std::to_string(seq.scans.size()) + ")");
  }
  return run;
}
#endif

/// What a scan's row of the pose table says (one per scan of the window).
struct PoseRow {
  double t = 0.0;
  std::string status = "not_tried";  // --init global gave up before this scan
  double explained = std::nan("");   // nan: not measured
  Pose2 pose = Pose2::Zero();
  bool has_pose = false;
  bool written = false;  // to the TUM file
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Constant(std::nan(""));
};

/// The --cov table's header: the scan's time, status, explained fraction, then the covariance's
/// upper triangle (x, y, theta).
constexpr const char* kPoseTableHeader = "t,status,explained,xx,xy,xt,yy,yt,tt";

void run_localize(const LocalizeArgs& a) {
  // Options first: a typo must not cost a map build. The settings: the defaults for logs on maps
  // built from scans (log_settings()), then the keys the --config file names.
  LocalizerSettings settings = log_settings();
  if (!a.config.empty()) settings = load_localizer_config(a.config, settings);
  if (a.recover) settings.recovery.detect = settings.recovery.recover = true;
  if (a.no_recover) settings.recovery.recover = false;
  if (a.threads >= 0) settings.threads = a.threads;
  if (a.print_config) {
    std::fputs(localizer_settings_yaml(settings, a.method).c_str(), stdout);
    return;
  }
  apply_threads(a.threads, settings.threads);
  for (const auto& [flag, value] :
       {std::pair<const char*, const std::string*>{"--map", &a.map}, {"--out", &a.out}}) {
    if (value->empty()) throw UsageError(std::string("localize: ") + flag + " is required");
  }
  if (a.log.empty() == a.bag.empty()) {
    throw UsageError("localize: give one input, --log (CARMEN) or --bag (ROS 1 or ROS 2)");
  }
  if (!a.bag.empty() && a.init.empty()) {
    throw UsageError(
        "localize: a bag holds no pose in the map's frame: give --init x,y,yaw or "
        "--init global");
  }
  // The outputs' temporary names now: a folder that does not exist fails before any work.
  StagedOutputs staged;
  const std::string traj_path = staged.file(a.out);
  const std::string cov_path = a.cov.empty() ? std::string() : staged.file(a.cov);
  const Eigen::Vector3d sig = parse_sigmas(a.init_sigma, "--init-sigma");
  const std::set<LocalizationStatus> written_statuses =
      parse_statuses(a.accept_status, "--accept-status");
  const bool init_global = a.init == "global";
  const std::optional<Pose2> init_arg = a.init.empty() || init_global
                                            ? std::nullopt
                                            : std::optional<Pose2>(parse_pose(a.init, "--init"));
  std::fprintf(stderr, "[localize] loading map %s\n", a.map.c_str());
  const LoadedMap map = load_map2(a.map);
  std::fprintf(stderr, "[localize] map %d x %d cells of %.3f m (%s), read and built in %.3f s\n",
               map.occupancy.size().x(), map.occupancy.size().y(), map.occupancy.resolution(),
               map.source.c_str(), map.seconds);
  if (map.uncertain != nullptr) {
    // The map's covariance joins the update's and the reported covariance of the methods that
    // read the VDT (vdt-opt, vdt-ekf, the beam EKFs); its per-reading floor is the fit's.
    const mapping::UncertainVdtMap& um = map.uncertain->map;
    for (VdtSensorModelOptions* s :
         {&settings.vdt_opt.sensor, &settings.vdt_ekf.sensor, &settings.active_ekf.ekf.sensor,
          &settings.passive_ekf.ekf.sensor}) {
      s->map_uncertainty = &um;
      s->map_sigma = um.approximation_sigma();
    }
    std::fprintf(stderr,
                 "[localize] uncertain map: h = %.2f m, %zu cells in the band, covariance %s\n",
                 um.spacing(), um.band_cells(),
                 um.summary().covariance_ok ? "used by the VDT methods" : "absent");
  }
#ifdef VDTNAV_CLI_ROS
  ScanRun run = a.bag.empty() ? read_log_run(a) : read_bag_run(a);
#else
  ScanRun run = read_log_run(a);
#endif
  const std::size_t n_scans = run.scans.size();
  const std::vector<double>& times = run.times;
  const std::vector<OdometryStep> steps = odometry_steps(times, run.odometry);

  // One row per scan of the window, whatever its status (the --cov table); the TUM file gets
  // the poses of the accepted statuses.
  std::vector<PoseRow> rows(n_scans);
  for (std::size_t k = 0; k < n_scans; ++k) rows[k].t = times[k];

  Pose2 init = init_arg ? *init_arg : *run.first_pose;
  Eigen::Matrix3d init_cov =
      Eigen::Vector3d(sig[0] * sig[0], sig[1] * sig[1], sig[2] * sig[2]).asDiagonal();
  std::size_t first = 0;  // the first scan localized (--init global: the first one accepted)
  bool started = true;
  if (init_global) {
    GlobalLocalizationOptions g = settings.global;
    g.optimizer = settings.vdt_opt;
    const GlobalLocalizer global(*map.vdt, map.occupancy, g, MapKnowledge(map.ros.cells));
    const std::size_t tries = std::min<std::size_t>(n_scans, 50);
    started = false;
    for (; first < tries && !started; ++first) {
      LaserScan scan = run.scans[first];
      scan.sigma_range = a.sigma_range;
      const GlobalLocalizationResult r = global.localize(scan_points(scan));
      const bool here = r.result.status == LocalizationStatus::kConverged;
      // Ambiguous: the best pose and how many distinct others explain the scan as well.
      char why[160] = "";
      if (r.ambiguous) {
        std::snprintf(why, sizeof why,
                      ", ambiguous: best (%.2f, %.2f, %.2f), %zu other poses explain it as well",
                      r.result.pose[0], r.result.pose[1], r.result.pose[2], r.alternatives.size());
      }
      std::fprintf(stderr,
                   "[localize] --init global, scan %zu: %s (%.0f %% explained%s) in %.3f s\n",
                   first, here ? "accepted" : "refused", 100.0 * r.explained, why, r.seconds);
      if (!here) {
        rows[first].status = status_token(LocalizationStatus::kRefused);
        rows[first].explained = r.explained;
        continue;
      }
      started = true;
      init = r.result.pose;
      if (r.result.has_covariance) init_cov = r.result.covariance;
    }
    if (started) --first;  // the scan accepted; without one, all `tries` were refused
    if (started && first > 0) {
      std::fprintf(stderr, "[localize] starting at scan %zu; the %zu before it are refused\n",
                   first, first);
    }
  }
  std::map<LocalizationStatus, int> status_count;
  std::vector<Pose2> estimate;
  std::vector<LaserScan> scans;
  std::vector<double> scan_ms;  // each update's wall time: the summary's mean, median, p99, max
  std::vector<double> scan_iterations;  // each update's solver iterations (issue 57's counter)
  std::size_t with_cov = 0, processed = 0;
  std::unique_ptr<Localizer2D> loc;
  const auto wall0 = std::chrono::steady_clock::now();
  if (started) {
    loc = make_localizer(a.method, *map.vdt, map.occupancy, settings, MapKnowledge(map.ros.cells));
    loc->reset(init, init_cov);
    ProgressBar bar("[localize] " + a.method, n_scans, a.quiet);
    for (std::size_t k = first; k < n_scans; ++k) {
      LaserScan scan = run.scans[k];
      scan.sigma_range = a.sigma_range;
      const auto t0 = std::chrono::steady_clock::now();
      // The first scan localized starts at the reset pose: no motion into it.
      const LocalizationResult r = loc->update(k == first ? OdometryStep{} : steps[k], scan);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      scan_ms.push_back(ms);
      scan_iterations.push_back(static_cast<double>(r.iterations));
      ++processed;
      ++status_count[r.status];
      PoseRow& row = rows[k];
      row.status = status_token(r.status);
      row.written = a.all_poses || written_statuses.count(r.status) > 0;
      row.pose = r.pose;
      row.has_pose = true;
      row.explained = r.explained >= 0.0 ? r.explained : std::nan("");
      if (r.has_covariance) row.covariance = r.covariance;
      with_cov += r.has_covariance;
      estimate.push_back(r.pose);
      if (!a.plot.empty()) scans.push_back(std::move(scan));
      bar.update(k + 1);
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  // The outputs: written under temporary names, renamed when all are written.
  std::size_t written = 0;
  {
    std::ofstream traj(traj_path);
    if (!traj) throw IoError(a.out + ": cannot open for writing");
    traj << "# vdtnav localize --method " << a.method << ": t x y z qx qy qz qw (" << a.time_base
         << " time base); the poses of the scans "
         << (a.all_poses ? "of every status" : "with status " + a.accept_status) << "\n";
    for (const PoseRow& row : rows) {
      if (!row.has_pose || !row.written) continue;
      traj << tum_line(row.t, row.pose) << '\n';
      ++written;
    }
    if (!traj.flush()) throw IoError(a.out + ": write failed");
  }
  // Input scans not localized (no odometry or no mounting at their stamp): a row each too.
  for (const auto& [t, status] : run.not_localized) {
    PoseRow row;
    row.t = t;
    row.status = status;
    rows.push_back(row);
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const PoseRow& x, const PoseRow& y) { return x.t < y.t; });
  if (!a.cov.empty()) {
    std::ofstream cov(cov_path);
    if (!cov) throw IoError(a.cov + ": cannot open for writing");
    cov << kPoseTableHeader << '\n';
    for (const PoseRow& row : rows) {
      const Eigen::Matrix3d& c = row.covariance;
      char line[320];
      std::snprintf(line, sizeof line, "%.6f,%s,%.4f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", row.t,
                    row.status.c_str(), row.explained, c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2),
                    c(2, 2));
      cov << line;
    }
    if (!cov.flush()) throw IoError(a.cov + ": write failed");
  }
  if (!a.plot.empty() && !estimate.empty()) {
    plot_trajectories(staged.file(a.plot + "_trajectory.png"), map.ros,
                      {{a.method, estimate, false}}, a.method + " on " + run.input);
    plot_reprojected_scans(staged.file(a.plot + "_scans.png"), map.ros, estimate, scans,
                           "scans reprojected from the " + a.method + " poses");
  }
  staged.commit();

  const eval::ErrorStatistics ms = eval::error_statistics(scan_ms);
  std::printf(
      "%s: %zu scans processed in %.3f s wall (%.3f ms per scan mean, %.3f median, %.3f p99, "
      "%.3f max)\n",
      a.method.c_str(), processed, wall, ms.mean, ms.median, ms.p99, ms.max);
  if (!scan_iterations.empty()) {
    const eval::ErrorStatistics it = eval::error_statistics(scan_iterations);
    std::printf("  iterations per scan (every solve of the update): median %.0f, p99 %.0f\n",
                it.median, it.p99);
  }
  if (first > 0) std::printf("  %-22s %zu\n", "refused (--init global)", first);
  if (!started) std::printf("  %-22s %zu\n", "not tried", n_scans - first);
  for (const auto& [s, n] : status_count) std::printf("  %-22s %d\n", to_string(s), n);
  if (const auto* rec = dynamic_cast<const RecoveringLocalizer*>(loc.get())) {
    if (rec->recoveries() > 0 || rec->searches() > 0) {
      std::printf("  re-acquired              %d (global searches finished: %d, ambiguous: %d)\n",
                  rec->recoveries(), rec->searches(), rec->ambiguous());
    }
    if (!settings.recovery.recover && status_count.count(LocalizationStatus::kLost) > 0) {
      std::printf("  (--no-recover: the lost scans were not localized again)\n");
    }
  }
  std::printf("wrote %s (%zu of %zu poses: %s)", a.out.c_str(), written, n_scans,
              a.all_poses ? "every status" : a.accept_status.c_str());
  if (!a.cov.empty()) {
    std::printf(", %s (%zu rows, %zu covariances)", a.cov.c_str(), rows.size(), with_cov);
  }
  const int localized = status_count[LocalizationStatus::kConverged];
  if (!a.cov.empty() && with_cov == 0 && localized > 0) {
    std::printf(" — %s reports no covariance", a.method.c_str());
  }
  std::printf("\n");
  if (!a.plot.empty() && !estimate.empty()) {
    std::printf("wrote %s_trajectory.png, %s_scans.png\n", a.plot.c_str(), a.plot.c_str());
  }

  // What the run means: nothing localized (exit 3), too little (a warning, exit 3 with --strict),
  // lost scans with --strict (exit 3).
  if (!started) {
    throw NotLocalized(run.input + ": --init global: none of the first " + std::to_string(first) +
                       " scans could be localized on " + a.map +
                       " without ambiguity (give --init x,y,yaw); " + a.out + " holds no pose");
  }
  const double fraction = static_cast<double>(localized) / static_cast<double>(n_scans);
  char msg[512];
  std::snprintf(msg, sizeof msg,
                "only %d of %zu scans (%.1f %%) localized (converged), fewer than %.0f %%: the "
                "map does not explain this log's scans (wrong map, --init, --time-base or time "
                "window?)",
                localized, n_scans, 100.0 * fraction, 100.0 * kMinLocalizedFraction);
  if (localized == 0) throw NotLocalized(std::string(msg) + "; " + a.out + " holds no pose");
  if (fraction < kMinLocalizedFraction) {
    if (a.strict) throw NotLocalized(std::string(msg) + " (--strict)");
    std::fprintf(stderr, "vdtnav localize: warning: %s\n", msg);
  }
  const int lost = status_count[LocalizationStatus::kLost];
  if (a.strict && lost > 0) {
    throw NotLocalized("--strict: " + std::to_string(lost) + " of " + std::to_string(n_scans) +
                       " scans lost (the outputs are written)");
  }
}

}  // namespace

void add_localize_command(CLI::App& app) {
  auto args = std::make_shared<LocalizeArgs>();
  CLI::App* cmd = app.add_subcommand("localize", "Localize a log's scans on a map");
  // --map, --log and --out are required unless --print-config (checked in run_localize).
  cmd->add_option("--map", args->map,
                  "ROS map_server YAML, an uncertain map file PREFIX.umap (vdtnav map "
                  "--uncertain) or a 2D VDT map PREFIX.vdt (required)")
      ->check(input_file("--map"));
  cmd->add_option("--log", args->log, "CARMEN log, plain or gzip (this or --bag)")
      ->check(input_file("--log"));
#ifdef VDTNAV_CLI_ROS
  cmd->add_option("--bag", args->bag,
                  "ROS 1 bag (.bag) or ROS 2 bag (folder with metadata.yaml and .db3 files); "
                  "stamps are the scans' header stamps; --init is required")
      ->check(input_path("--bag"));
  cmd->add_option("--scan-topic", args->scan_topic,
                  "--bag: the sensor_msgs/LaserScan topic (default: the only one)");
  cmd->add_option("--odom-topic", args->odom_topic,
                  "--bag: a nav_msgs/Odometry topic (default: TF --odom-frame -> --base-frame "
                  "when the bag has it, else the only Odometry topic)");
  cmd->add_option("--odom-frame", args->odom_frame, "--bag: the odometry frame (REP 105)")
      ->capture_default_str();
  cmd->add_option("--base-frame", args->base_frame, "--bag: the robot's frame (REP 105)")
      ->capture_default_str();
  cmd->add_option("--laser-pose", args->laser_pose,
                  "--bag: the scanner's pose x,y,yaw in --base-frame when the bag has no "
                  "transform to the scans' frame");
#endif
  cmd->add_option("--method", args->method, "Localizer")
      ->check(CLI::IsMember(localizer_methods()))
      ->capture_default_str();
  cmd->add_option("--init", args->init,
                  "Initial pose x,y,yaw in the map frame, or 'global': found from the first scans "
                  "with no prior (branch and bound, settings section global:; default: the log's "
                  "first scan pose)");
  cmd->add_option("--init-sigma", args->init_sigma,
                  "Initial standard deviations sx,sy,syaw (metres, metres, radians; >= 0)")
      ->capture_default_str();
  args->window.add_options(*cmd);
  add_time_base_option(*cmd, args->time_base);
  cmd->add_option("--out", args->out, "Trajectory output (TUM: t x y z qx qy qz qw; required)");
  cmd->add_option("--config", args->config,
                  "Localizer settings (YAML, keys in --print-config and docs/settings.md); "
                  "unnamed keys keep their defaults")
      ->check(input_file("--config"));
  cmd->add_flag("--print-config", args->print_config,
                "Print the settings of --method (with --config applied), every key with its unit "
                "and meaning, and exit");
  cmd->add_option("--cov", args->cov,
                  "Pose table (CSV: t,status,explained,xx,xy,xt,yy,yt,tt): one row per scan of "
                  "the window whatever its status; explained and the covariance nan where not "
                  "measured");
  add_pose_selection_options(*cmd, args->all_poses, args->accept_status, "--out",
                             "the --cov table");
  cmd->add_option("--plot", args->plot,
                  "Figure prefix: PREFIX_trajectory.png, PREFIX_scans.png (reprojected scans)")
      ->check(plot_option_check);
  cmd->add_option("--odometry", args->odometry,
                  "auto: ODOM lines when usable, else the laser odom fields; odom; laser")
      ->check(CLI::IsMember({"auto", "odom", "laser"}))
      ->capture_default_str();
  cmd->add_option("--sigma-range", args->sigma_range, "Range noise standard deviation, metres")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI::Option* max_range =
      cmd->add_option("--max-range", args->max_range,
                      "Readings at or beyond this are no-returns (unset: 80, or lower where the "
                      "log's readings pile up at a no-return code)")
          ->capture_default_str();
  cmd->add_flag("--skip-malformed", args->skip_malformed, "Skip and count malformed log lines");
  auto* recover = cmd->add_flag(
      "--recover", args->recover,
      "vdt-opt, vdt-ekf: when the scans stop being explained (status lost), re-acquire the pose "
      "by global localization (the default; settings section recovery:)");
  cmd->add_flag("--no-recover", args->no_recover,
                "Report lost scans (status lost) but do not re-acquire them")
      ->excludes(recover);
  cmd->add_flag("--quiet", args->quiet, "No progress bar");
  add_threads_option(*cmd, args->threads);
  cmd->add_flag("--strict", args->strict,
                "Exit 3 when a scan is lost or fewer than 10 % of the scans localize (without it: "
                "exit 3 only when none does, a warning under 10 %)");
  cmd->callback([args, max_range] {
    args->max_range_given = max_range->count() > 0;
    run_localize(*args);
  });
}

}  // namespace vdtnav::tools
