#include "common.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "exit_status.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/parallel.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace vdtnav::tools {

LoadedMap load_map2(const std::string& path) { return load_map(path, MapLoadOptions{}, 2); }

std::function<void(const std::string&)> say_on_stderr(const std::string& tag) {
  return [tag](const std::string& line) {
    std::fprintf(stderr, "[%s] %s\n", tag.c_str(), line.c_str());
  };
}

eval::Trajectory2 load_trajectory2(const std::string& tum_path) {
  const TumTrajectory tum = load_tum_trajectory(tum_path);
  eval::Trajectory2 out;
  out.reserve(tum.poses.size());
  for (const auto& s : tum.poses) out.push_back({s.t, pose2_from_pose3(s.pose)});
  return out;
}

CLI::Validator input_file(const std::string& flag) {
  return CLI::Validator(
      [flag](std::string& path) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
          throw IoError(flag + ": File does not exist: " + path);
        }
        if (std::filesystem::is_directory(path, ec)) {
          throw IoError(flag + ": expected a file, got the folder " + path);
        }
        return std::string();
      },
      "FILE");
}

CLI::Validator input_path(const std::string& flag) {
  return CLI::Validator(
      [flag](std::string& path) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
          throw IoError(flag + ": no such file or folder: " + path);
        }
        return std::string();
      },
      "PATH");
}

std::string status_token(LocalizationStatus s) {
  std::string t = to_string(s);
  std::replace(t.begin(), t.end(), ' ', '_');
  return t;
}

namespace {

constexpr LocalizationStatus kAllStatuses[] = {LocalizationStatus::kConverged,
                                               LocalizationStatus::kNotConverged,
                                               LocalizationStatus::kTooFewObservations,
                                               LocalizationStatus::kDiverged,
                                               LocalizationStatus::kRefused,
                                               LocalizationStatus::kLost,
                                               LocalizationStatus::kBridged};

/// "converged, not_converged, ..., lost, bridged": the names parse_statuses() takes.
std::string status_names() {
  std::string names;
  for (LocalizationStatus s : kAllStatuses) names += (names.empty() ? "" : ", ") + status_token(s);
  return names;
}

}  // namespace

std::set<LocalizationStatus> parse_statuses(const std::string& text, const std::string& what) {
  std::set<LocalizationStatus> out;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string name = text.substr(begin, comma - begin);
    bool known = false;
    for (LocalizationStatus s : kAllStatuses) {
      if (status_token(s) == name) {
        out.insert(s);
        known = true;
      }
    }
    if (!known) {
      throw UsageError(what + ": unknown status '" + name + "' (expected some of " +
                       status_names() + ", comma-separated)");
    }
    begin = comma + 1;
  }
  return out;
}

void add_pose_selection_options(CLI::App& app, bool& all_poses, std::string& accept_status,
                                const std::string& trajectory, const std::string& table) {
  app.add_flag(
      "--all-poses", all_poses,
      trajectory + " holds the pose of every scan, whatever its status (" + table + " says which)");
  app.add_option(
         "--accept-status", accept_status,
         "Statuses whose poses " + trajectory + " holds, comma-separated among " + status_names())
      ->capture_default_str();
}

void TimeWindow::add_options(CLI::App& app) {
  app.add_option("--from", from, "First time used, in the log's time base (seconds)");
  app.add_option("--to", to, "Last time used, in the log's time base (seconds)");
}

const std::vector<std::string>& time_base_names() {
  static const std::vector<std::string> names = {"logger", "ipc"};
  return names;
}

void add_time_base_option(CLI::App& app, std::string& time_base) {
  app.add_option("--time-base", time_base,
                 "CARMEN timestamp used as the log's time: logger (logger_timestamp) or ipc "
                 "(ipc_timestamp; the Freiburg benchmark relations use the raw .clf's ipc time)")
      ->check(CLI::IsMember(time_base_names()))
      ->capture_default_str();
}

void add_threads_option(CLI::App& app, int& threads) {
  app.add_option("--threads", threads,
                 "Threads of the work that runs in parallel (map building, global search, 3D "
                 "multi-start); 0: the machine's cores (the default, or the --config file's "
                 "threads:). Results are the same for any count")
      ->check(CLI::Range(0, 4096));
}

void apply_threads(int flag, int settings_threads) {
  set_threads(flag >= 0 ? flag : settings_threads);
}

CarmenLog load_log(const std::string& path, const CarmenLogOptions& options,
                   const std::string& time_base) {
  if (time_base != "logger" && time_base != "ipc") {
    throw UsageError("--time-base: expected logger or ipc, got '" + time_base + "'");
  }
  CarmenLog log = load_carmen_log(path, options);
  if (time_base == "ipc") {
    for (CarmenLaser& l : log.lasers) l.time = l.scan.time = l.ipc_time;
    for (CarmenOdometry& o : log.odometry) o.time = o.ipc_time;
  }
  return log;
}

double apply_no_return_code(CarmenLog& log, const char* tag) {
  const double r = detect_no_return_range(log);
  if (!std::isfinite(r)) return r;
  std::size_t lowered = 0;
  for (CarmenLaser& l : log.lasers) {
    if (r < l.scan.range_max) {
      l.scan.range_max = r;
      ++lowered;
    }
  }
  if (lowered > 0) {
    std::fprintf(stderr,
                 "[%s] the log marks no return with readings from %.2f m: those are dropped "
                 "(--max-range to choose another limit)\n",
                 tag, r);
  }
  return r;
}

std::vector<std::size_t> scans_in(const CarmenLog& log, const TimeWindow& window) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < log.lasers.size(); ++i) {
    if (window.contains(log.lasers[i].time)) out.push_back(i);
  }
  return out;
}

}  // namespace vdtnav::tools
