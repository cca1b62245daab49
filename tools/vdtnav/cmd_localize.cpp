// vdtnav localize: one localizer over a log on a map. Odometry from the log's ODOM lines (or the
// laser messages' odometry fields when those are unusable), one TUM line per scan in the log's
// time base, the 3x3 covariance per scan as CSV, and figures.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "common.hpp"
#include "plots.hpp"
#include "progress.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace vdtnav::tools {

namespace {

struct LocalizeArgs {
  std::string map, log, method = "vdt-opt", init, init_sigma = "0.1,0.1,0.05", out, cov, plot;
  std::string odometry = "auto";
  TimeWindow window;
  double sigma_range = 0.02;
  double max_range = 80.0;
  bool skip_malformed = false;
  bool quiet = false;
};

void run_localize(const LocalizeArgs& a) {
  std::fprintf(stderr, "[localize] loading map %s\n", a.map.c_str());
  const LoadedMap map = load_map(a.map);
  std::fprintf(stderr, "[localize] map %d x %d cells of %.3f m, VDT built in %.3f s\n",
               map.occupancy.size().x(), map.occupancy.size().y(), map.occupancy.resolution(),
               map.build_seconds);
  CarmenLogOptions lo;
  lo.max_range = a.max_range;
  lo.skip_malformed = a.skip_malformed;
  const CarmenLog log = load_carmen_log(a.log, lo);
  const std::vector<std::size_t> idx = scans_in(log, a.window);
  if (idx.empty()) {
    throw ConfigError(a.log + ": no laser message in the time window (the log has " +
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
  std::vector<double> times;
  for (std::size_t i : idx) times.push_back(log.lasers[i].time);
  const std::vector<OdometryStep> steps = odometry_steps(times, odom.poses);

  const Pose2 init = a.init.empty() ? log.lasers[idx.front()].pose : parse_pose(a.init, "--init");
  const Pose2 sig = parse_pose(a.init_sigma, "--init-sigma");
  const LocalizerSettings settings = log_settings();
  std::unique_ptr<Localizer2D> loc = make_localizer(a.method, *map.vdt, map.occupancy, settings);
  loc->reset(init, Eigen::Vector3d(sig[0] * sig[0], sig[1] * sig[1], sig[2] * sig[2]).asDiagonal());

  std::ofstream traj(a.out);
  if (!traj) throw IoError(a.out + ": cannot open for writing");
  traj << "# vdtnav localize --method " << a.method << ": t x y z qx qy qz qw (log time base)\n";
  std::ofstream cov;
  if (!a.cov.empty()) {
    cov.open(a.cov);
    if (!cov) throw IoError(a.cov + ": cannot open for writing");
    cov << "t,xx,xy,xt,yy,yt,tt\n";
  }
  std::map<LocalizationStatus, int> status_count;
  std::vector<Pose2> estimate;
  std::vector<LaserScan> scans;
  double ms_sum = 0.0, ms_max = 0.0;
  std::size_t with_cov = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  {
    ProgressBar bar("[localize] " + a.method, idx.size(), a.quiet);
    for (std::size_t k = 0; k < idx.size(); ++k) {
      LaserScan scan = log.lasers[idx[k]].scan;
      scan.sigma_range = a.sigma_range;
      const auto t0 = std::chrono::steady_clock::now();
      const LocalizationResult r = loc->update(steps[k], scan);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      ms_sum += ms;
      ms_max = std::max(ms_max, ms);
      ++status_count[r.status];
      traj << tum_line(times[k], r.pose) << '\n';
      if (cov.is_open()) {  // one row per scan; nan where the method reports no covariance
        const Eigen::Matrix3d c =
            r.has_covariance ? r.covariance : Eigen::Matrix3d::Constant(std::nan(""));
        char line[256];
        std::snprintf(line, sizeof line, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", times[k], c(0, 0),
                      c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2));
        cov << line;
        with_cov += r.has_covariance;
      }
      estimate.push_back(r.pose);
      if (!a.plot.empty()) scans.push_back(std::move(scan));
      bar.update(k + 1);
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("%s: %zu scans localized in %.3f s wall (%.3f ms per scan mean, %.3f max)\n",
              a.method.c_str(), idx.size(), wall, ms_sum / static_cast<double>(idx.size()), ms_max);
  for (const auto& [s, n] : status_count) std::printf("  %-22s %d\n", to_string(s), n);
  std::printf("wrote %s", a.out.c_str());
  if (cov.is_open()) std::printf(", %s (%zu covariances)", a.cov.c_str(), with_cov);
  if (cov.is_open() && with_cov == 0) std::printf(" — %s reports no covariance", a.method.c_str());
  std::printf("\n");
  if (!a.plot.empty()) {
    plot_trajectories(a.plot + "_trajectory.png", map.ros, {{a.method, estimate, false}},
                      a.method + " on " + a.log);
    plot_reprojected_scans(a.plot + "_scans.png", map.ros, estimate, scans,
                           "scans reprojected from the " + a.method + " poses");
    std::printf("wrote %s_trajectory.png, %s_scans.png\n", a.plot.c_str(), a.plot.c_str());
  }
}

}  // namespace

void add_localize_command(CLI::App& app) {
  auto args = std::make_shared<LocalizeArgs>();
  CLI::App* cmd = app.add_subcommand("localize", "Localize a log's scans on a map");
  cmd->add_option("--map", args->map, "ROS map_server YAML")->required()->check(CLI::ExistingFile);
  cmd->add_option("--log", args->log, "CARMEN log (plain or gzip)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--method", args->method, "Localizer")
      ->required()
      ->check(CLI::IsMember(localizer_methods()));
  cmd->add_option("--init", args->init,
                  "Initial pose x,y,yaw in the map frame (default: the log's first scan pose)");
  cmd->add_option("--init-sigma", args->init_sigma, "Initial standard deviations x,y,yaw")
      ->capture_default_str();
  args->window.add_options(*cmd);
  cmd->add_option("--out", args->out, "Trajectory output (TUM: t x y z qx qy qz qw)")->required();
  cmd->add_option(
      "--cov", args->cov,
      "Covariance output (CSV: t,xx,xy,xt,yy,yt,tt; one row per scan, nan without one)");
  cmd->add_option("--plot", args->plot,
                  "Figure prefix: PREFIX_trajectory.png, PREFIX_scans.png (reprojected scans)");
  cmd->add_option("--odometry", args->odometry,
                  "auto: ODOM lines when usable, else the laser odom fields; odom; laser")
      ->check(CLI::IsMember({"auto", "odom", "laser"}))
      ->capture_default_str();
  cmd->add_option("--sigma-range", args->sigma_range, "Range noise standard deviation, metres")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--max-range", args->max_range, "Readings at or beyond this are no-returns")
      ->capture_default_str();
  cmd->add_flag("--skip-malformed", args->skip_malformed, "Skip and count malformed log lines");
  cmd->add_flag("--quiet", args->quiet, "No progress bar");
  cmd->callback([args] { run_localize(*args); });
}

}  // namespace vdtnav::tools
