// vdtnav map: an occupancy grid from a log's poses and scans (log-odds with ray casting), saved as
// a ROS map_server map (PREFIX.yaml + PREFIX.pgm), and the VDT map built from it (PREFIX.vdt).
// Everything is checked, and the VDT built, before the first file is written: a failed run
// leaves no partial map behind.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common.hpp"
#include "exit_status.hpp"
#include "progress.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"

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
};

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
  const std::vector<std::size_t> idx = scans_in(log, a.window);
  if (idx.empty()) {
    throw UsageError(a.log + ": no laser message in the time window [" +
                     std::to_string(a.window.from) + ", " + std::to_string(a.window.to) +
                     "] (the log has " + std::to_string(log.lasers.size()) + " scans)");
  }
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
  cmd->add_option("--out", args->out, "Output prefix: PREFIX.yaml, PREFIX.pgm, PREFIX.vdt")
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
  add_threads_option(*cmd, args->threads);
  cmd->callback([args, max_range] {
    args->max_range_given = max_range->count() > 0;
    run_map(*args);
  });
}

}  // namespace vdtnav::tools
