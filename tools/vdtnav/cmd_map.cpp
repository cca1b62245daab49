// vdtnav map: an occupancy grid from a log's poses and scans (log-odds with ray casting), saved as
// a ROS map_server map (PREFIX.yaml + PREFIX.pgm), and the VDT map built from it (PREFIX.vdt);
// with --uncertain also the uncertain VDT map of the same scans (thesis ch. 5) at the stated pose
// noise, with the covariance of its control points (PREFIX.umap, the occupancy grid inside).
// The poses are the log's, or a TUM trajectory's (--poses) interpolated at the scans' times.
// Everything is checked, and the VDT built, before the first file is written: a failed run
// leaves no partial map behind.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common.hpp"
#include "exit_status.hpp"
#include "parse.hpp"
#include "progress.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/mapping/uncertain_map_file.hpp"

namespace vdtnav::tools {

namespace {

struct MapArgs {
  std::string log;
  double resolution = 0.05;
  std::string out;
  TimeWindow window;
  double margin = 1.0;
  double max_range = 80.0;
  bool max_range_given = false;  // else the log's own no-return code may lower it
  std::string time_base = "logger";
  bool skip_malformed = false;
  bool quiet = false;
  int threads = -1;
  // --uncertain
  bool uncertain = false;
  std::string poses;                          // TUM trajectory (else the log's poses)
  std::string pose_sigma = "0.05,0.05,0.01";  // of the poses: x, y (m), yaw (rad)
  double sigma_range = 0.02;
  double spacing = 0.0;  // <= 0: from the data
  double max_gap = 0.5;  // seconds between the TUM poses around a scan
};

/// The uncertain map of the scans at their poses with the stated noise, saved with `cells`.
void write_uncertain_map(const MapArgs& a, const std::vector<Pose2>& poses,
                         const std::vector<LaserScan>& scans, const Grid<std::int8_t, 2>& cells) {
  const Eigen::Vector3d sig = parse_sigmas(a.pose_sigma, "--pose-sigma");
  std::vector<mapping::MapScan> map_scans;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    LaserScan scan = scans[k];
    scan.sigma_range = a.sigma_range;
    mapping::MapScan s;
    s.pose = poses[k];
    s.pose_covariance = sig.cwiseAbs2().asDiagonal();
    s.points = scan_points(scan);
    map_scans.push_back(std::move(s));
  }
  mapping::UncertainMapOptions o;
  o.spacing = a.spacing;
  std::fprintf(stderr,
               "[map] fitting the uncertain map to %zu scans (pose sigma %s, range sigma %.3f m)\n",
               map_scans.size(), a.pose_sigma.c_str(), a.sigma_range);
  const mapping::UncertainVdtMap um = mapping::UncertainVdtMap::fit(map_scans, o);
  const mapping::UncertainMapSummary& sm = um.summary();
  if (!sm.covariance_ok) {
    throw ConfigError("the uncertain map's covariance failed (" + sm.message +
                      "): nothing written for " + a.out + ".umap");
  }
  mapping::save_uncertain_map(a.out + ".umap", um, cells);
  std::printf(
      "wrote %s.umap: h = %.2f m, %d control points, %zu cells in the band, %d readings "
      "(%d cleared by the beams), %d Eikonal and %d free-space samples; fit %.1f s "
      "(%d iterations%s), covariance %.1f s\n",
      a.out.c_str(), sm.spacing, sm.control_points, um.band_cells(), sm.boundary_points,
      sm.cleared_readings, sm.eikonal_samples, sm.free_space_samples, sm.fit_seconds, sm.iterations,
      sm.converged ? "" : ", stopped before converging", sm.covariance_seconds);
}

/// The log's scans at the TUM trajectory's poses (the laser's pose, as a log's FLASER gives it,
/// interpolated; scans outside it are left out).
void poses_from_trajectory(const MapArgs& a, CarmenLog* log, std::vector<std::size_t>* idx) {
  const eval::Trajectory2 traj = load_trajectory2(a.poses);
  eval::check_trajectory(traj, "--poses");
  std::vector<std::size_t> kept;
  std::size_t outside = 0;
  for (const std::size_t i : *idx) {
    const eval::InterpolatedPose ip = eval::interpolate(traj, log->lasers[i].time, a.max_gap);
    if (!ip.ok()) {
      ++outside;
      continue;
    }
    log->lasers[i].pose = ip.pose;
    kept.push_back(i);
  }
  if (outside > 0) {
    std::fprintf(stderr,
                 "[map] %zu of %zu scans have no pose in %s (outside it or in a gap over %.2f s): "
                 "left out\n",
                 outside, idx->size(), a.poses.c_str(), a.max_gap);
  }
  if (kept.empty()) {
    throw UsageError(a.poses + ": no scan of " + a.log +
                     " lies within the trajectory (check --time-base and the stamps)");
  }
  *idx = std::move(kept);
}

void run_map(const MapArgs& a) {
  apply_threads(a.threads, 0);
  if (!std::isfinite(a.margin) || a.margin < 0.0) {
    char got[32];
    std::snprintf(got, sizeof got, "%g", a.margin);
    throw UsageError(std::string("--margin: expected a finite number of metres >= 0, got ") + got);
  }
  CarmenLogOptions lo;
  lo.max_range = a.max_range;
  lo.skip_malformed = a.skip_malformed;
  std::fprintf(stderr, "[map] reading %s\n", a.log.c_str());
  CarmenLog log = load_log(a.log, lo, a.time_base);
  if (!a.max_range_given) apply_no_return_code(log, "map");
  if (!log.malformed_lines.empty()) {
    std::fprintf(stderr, "[map] skipped %zu malformed lines (first: line %zu)\n",
                 log.malformed_lines.size(), log.malformed_lines.front());
  }
  std::vector<std::size_t> idx = scans_in(log, a.window);
  if (idx.empty()) {
    throw UsageError(a.log + ": no laser message in the time window [" +
                     std::to_string(a.window.from) + ", " + std::to_string(a.window.to) +
                     "] (the log has " + std::to_string(log.lasers.size()) + " scans)");
  }
  if (!a.poses.empty() && !idx.empty()) poses_from_trajectory(a, &log, &idx);
  std::vector<Pose2> poses;
  std::vector<LaserScan> scans;
  for (std::size_t i : idx) {
    poses.push_back(log.lasers[i].pose);
    scans.push_back(log.lasers[i].scan);
  }
  mapping::OccupancyMapperOptions mo;
  mo.resolution = a.resolution;
  mo.margin = a.margin;
  const auto [frame, size] = mapping::map_extent(poses, scans, mo);
  std::fprintf(stderr, "[map] %zu scans from t = %.3f to %.3f s into %d x %d cells of %.3f m\n",
               idx.size(), log.lasers[idx.front()].time, log.lasers[idx.back()].time, size.x(),
               size.y(), a.resolution);
  mapping::OccupancyMapper mapper(frame, size, mo);
  {
    ProgressBar bar("[map] ray casting", scans.size(), a.quiet);
    for (std::size_t k = 0; k < scans.size(); ++k) {
      mapper.insert(poses[k], scans[k]);
      bar.update(k + 1);
    }
  }
  const Grid<std::int8_t, 2> cells = mapper.ros_cells();
  const OccupancyGrid<2> occupied = occupancy(cells);
  std::size_t n_occupied = 0;
  for (std::size_t i = 0; i < occupied.num_cells(); ++i) n_occupied += occupied[i] != 0;
  const mapping::MappingStats& st = mapper.stats();
  if (n_occupied == 0) {
    throw ConfigError(a.log + ": the map of " + std::to_string(idx.size()) +
                      " scans has no occupied cell (" + std::to_string(st.hits) + " returns, " +
                      std::to_string(st.no_returns) +
                      " no-returns at or beyond --max-range): nothing written");
  }
  const auto t0 = std::chrono::steady_clock::now();
  const VdtMap2 vdt = VdtMap2::build(occupied);
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (a.uncertain) write_uncertain_map(a, poses, scans, cells);
  save_ros_map(a.out, cells);
  save_vdt_map(a.out + ".vdt", vdt);
  std::printf("wrote %s.yaml, %s.pgm, %s.vdt (VDT built in %.3f s)\n", a.out.c_str(), a.out.c_str(),
              a.out.c_str(), build_s);
  std::printf("beams: %zu returns, %zu no-return (cleared, not marked), %zu non-finite dropped\n",
              st.hits, st.no_returns, st.dropped_not_finite);
}

}  // namespace

void add_map_command(CLI::App& app) {
  auto args = std::make_shared<MapArgs>();
  CLI::App* cmd = app.add_subcommand(
      "map",
      "Build an occupancy map (ROS YAML + PGM) and its VDT map from a log's poses and scans");
  cmd->add_option("--log", args->log, "CARMEN log (plain or gzip); its laser poses are used")
      ->required()
      ->check(input_file("--log"));
  cmd->add_option("--resolution", args->resolution, "Cell size, metres")
      ->required()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--out", args->out,
                  "Output prefix: PREFIX.yaml, PREFIX.pgm, PREFIX.vdt (and PREFIX.umap)")
      ->required();
  args->window.add_options(*cmd);
  cmd->add_option("--margin", args->margin, "Free border around the data, metres (>= 0)")
      ->capture_default_str();
  add_time_base_option(*cmd, args->time_base);
  CLI::Option* max_range =
      cmd->add_option("--max-range", args->max_range,
                      "Readings at or beyond this are no-returns: they clear, they mark nothing "
                      "(unset: 80, or lower where the log's readings pile up at a no-return code)")
          ->capture_default_str();
  cmd->add_flag("--skip-malformed", args->skip_malformed,
                "Skip and count malformed log lines instead of stopping at the first");
  cmd->add_flag("--quiet", args->quiet, "No progress bar");
  cmd->add_flag("--uncertain", args->uncertain,
                "Also fit the uncertain VDT map of the scans (thesis ch. 5): PREFIX.umap, for "
                "localize --map PREFIX.umap");
  cmd->add_option("--poses", args->poses,
                  "TUM trajectory (t x y z qx qy qz qw) giving the scans' poses, interpolated at "
                  "their times, instead of the log's")
      ->check(input_file("--poses"));
  cmd->add_option("--pose-sigma", args->pose_sigma,
                  "Standard deviations of the poses' errors x,y (m),yaw (rad) (--uncertain)")
      ->capture_default_str();
  cmd->add_option("--sigma-range", args->sigma_range,
                  "Range noise standard deviation, metres (--uncertain)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--spacing", args->spacing,
                  "Control point spacing of the uncertain map, metres (unset: five times the "
                  "median gap between consecutive readings, within [0.2, 0.5])")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-gap", args->max_gap,
                  "Seconds between the --poses samples around a scan beyond which it has no pose")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  add_threads_option(*cmd, args->threads);
  cmd->callback([args, max_range] {
    args->max_range_given = max_range->count() > 0;
    run_map(*args);
  });
}

}  // namespace vdtnav::tools
