// vdtnav join-odometry: the converter the Intel Research Lab study needs. The GMapping-corrected
// log holds the ranges with corrected poses on the logger's time base; a table holds, per scan,
// the absolute time (the relations' time base), the logger time, the raw odometry and the
// corrected pose. This joins them on the log's time (`--time-base`, logger by default: the
// table's log_t column is the corrected log's logger_timestamp) and writes
//   --out-raw        a CARMEN log: FLASER with the raw odometry as pose and odom fields,
//   --out-corrected  a CARMEN log: FLASER with the corrected pose (for map building),
//   --out-reference  the corrected poses as a TUM trajectory,
// all stamped with the absolute time, so trajectories compare directly with the relations.
#include <cstdio>

#include "common.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace vdtnav::tools {

namespace {

struct JoinArgs {
  std::string log, table, out_raw, out_corrected, out_reference;
  std::string time_base = "logger";
  double tolerance = 0.005;
};

void run_join(const JoinArgs& a) {
  const CarmenLog log = load_log(a.log, {}, a.time_base);
  const JoinedLogs j = join_odometry_table(log, load_odometry_table(a.table), a.table, a.tolerance);
  std::vector<StampedPose3> reference;
  for (const CarmenLaser& l : j.corrected.lasers) {
    reference.push_back({l.time, pose3_from_pose2(l.pose)});
  }
  const CarmenLog& raw = j.raw;
  const CarmenLog& corrected = j.corrected;
  const std::size_t unmatched = j.unmatched_scans;
  StagedOutputs staged;  // the three files, or none
  save_carmen_log(staged.file(a.out_raw), raw);
  save_carmen_log(staged.file(a.out_corrected), corrected);
  save_tum_trajectory(staged.file(a.out_reference), reference);
  staged.commit();
  std::printf("joined %zu scans (%zu scans without a table row) -> %s, %s, %s\n", raw.lasers.size(),
              unmatched, a.out_raw.c_str(), a.out_corrected.c_str(), a.out_reference.c_str());
}

}  // namespace

void add_join_odometry_command(CLI::App& app) {
  auto args = std::make_shared<JoinArgs>();
  CLI::App* cmd = app.add_subcommand(
      "join-odometry",
      "Join a corrected CARMEN log with a table of raw odometry on absolute time (Intel lab data)");
  cmd->add_option("--log", args->log, "GMapping-corrected CARMEN log (ranges, corrected poses)")
      ->required()
      ->check(input_file("--log"));
  cmd->add_option("--table", args->table,
                  "Rows: abs_t log_t raw_x raw_y raw_theta corrected_x corrected_y corrected_theta")
      ->required()
      ->check(input_file("--table"));
  cmd->add_option("--out-raw", args->out_raw, "CARMEN log with raw odometry poses")->required();
  cmd->add_option("--out-corrected", args->out_corrected, "CARMEN log with corrected poses")
      ->required();
  cmd->add_option("--out-reference", args->out_reference, "Corrected poses as TUM")->required();
  cmd->add_option("--tolerance", args->tolerance, "Seconds within which log and table times match")
      ->capture_default_str();
  add_time_base_option(*cmd, args->time_base);
  cmd->callback([args] { run_join(*args); });
}

}  // namespace vdtnav::tools
