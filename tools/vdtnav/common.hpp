#pragma once
/// \file
/// \brief What the `vdtnav` subcommands share: the map a localizer runs on, trajectories as 2D
/// stamped poses, time windows, and the subcommand registry.

#include <CLI/CLI.hpp>

#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map_files/load_map.hpp"

namespace vdtnav::tools {

/// \brief The 2D map of `localize --map`: a map_server map (MAP.yaml), an uncertain map file
/// (PREFIX.umap) or a saved 2D VDT map (.vdt), by vdtnav::load_map. \throws vdtnav::Error.
[[nodiscard]] LoadedMap load_map2(const std::string& path);

/// \return what MapLoadOptions::say prints: `[tag] line` on stderr.
[[nodiscard]] std::function<void(const std::string&)> say_on_stderr(const std::string& tag);

/// \brief A TUM file as a planar trajectory (z, roll and pitch ignored).
[[nodiscard]] eval::Trajectory2 load_trajectory2(const std::string& tum_path);

/// \brief A time window [from, to] (inclusive); unset ends are open.
struct TimeWindow {
  double from = -std::numeric_limits<double>::infinity();
  double to = std::numeric_limits<double>::infinity();
  [[nodiscard]] bool contains(double t) const noexcept { return t >= from && t <= to; }
  void add_options(CLI::App& app);
};

/// \brief The names of the CARMEN time bases, as `--time-base` takes them: `logger` (the
/// logger_timestamp, the default) or `ipc` (the ipc_timestamp, the time base of the raw `.clf`
/// logs the relations of the Freiburg SLAM benchmark are stamped with).
[[nodiscard]] const std::vector<std::string>& time_base_names();

/// \brief Adds `--time-base logger|ipc` to a subcommand that reads a CARMEN log.
void add_time_base_option(CLI::App& app, std::string& time_base);

/// \brief Adds `--threads N`: the threads of the work that runs in parallel (core/parallel.hpp:
/// map building, global search, 3D multi-start), 0 for the machine's cores; it overrides the
/// settings file's `threads:`. `threads` stays -1 when the flag is not given.
void add_threads_option(CLI::App& app, int& threads);

/// \brief set_threads(): `flag` when --threads was given (>= 0), else `settings_threads` (the
/// settings' `threads:`, 0: the machine's cores).
void apply_threads(int flag, int settings_threads);

/// \brief Loads a CARMEN log in the time base `time_base` (a time_base_names() entry): with
/// `ipc`, every laser's and ODOM's `time` (and each scan's time) becomes its ipc_timestamp, so
/// that time windows, odometry interpolation and the written trajectories all use it.
/// \throws what load_carmen_log() throws; ConfigError for an unknown time base.
[[nodiscard]] CarmenLog load_log(const std::string& path, const CarmenLogOptions& options,
                                 const std::string& time_base);

/// \brief When --max-range was not given: the log's own no-return code (detect_no_return_range)
/// lowers every scan's range_max to it, said on stderr with `tag`. \return the range used
/// (+inf when the log has no code).
double apply_no_return_code(CarmenLog& log, const char* tag);

/// \brief Indices of the log's laser messages inside the window.
[[nodiscard]] std::vector<std::size_t> scans_in(const CarmenLog& log, const TimeWindow& window);

/// \brief CLI11 check of an input file given with `flag`: a missing file (or a folder) throws
/// IoError "FLAG: File does not exist: PATH", bad input (exit 1) like a file that cannot be read,
/// not a usage error.
[[nodiscard]] CLI::Validator input_file(const std::string& flag);
/// \brief As input_file, for a file or a folder (a ROS 2 bag).
[[nodiscard]] CLI::Validator input_path(const std::string& flag);

/// \brief A status as the pose tables write it: to_string() with '_' for ' ' ("not_converged").
[[nodiscard]] std::string status_token(LocalizationStatus s);

/// \brief Statuses from a comma-separated list of status_token() names. \throws UsageError naming
/// `what` for an unknown name or an empty list.
[[nodiscard]] std::set<LocalizationStatus> parse_statuses(const std::string& text,
                                                          const std::string& what);

/// \brief Adds `--all-poses` and `--accept-status LIST` (the subcommand's default) to a subcommand
/// whose trajectory file is `trajectory` ("--out", "a sequence's trajectory.tum") and pose table
/// `table`.
void add_pose_selection_options(CLI::App& app, bool& all_poses, std::string& accept_status,
                                const std::string& trajectory, const std::string& table);

/// \brief Adds each subcommand to the application.
void add_map_command(CLI::App& app);
void add_localize_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_join_odometry_command(CLI::App& app);
#ifdef VDTNAV_CLI_3D
void add_map3d_command(CLI::App& app);
void add_localize3d_command(CLI::App& app);
#endif
/// \brief `vdtnav bag info BAG` (built with the ROS front end).
void add_bag_command(CLI::App& app);
/// `bag play` under `bag` (with vdtnav::ros2).
void add_bag_play_command(CLI::App& bag);

}  // namespace vdtnav::tools
