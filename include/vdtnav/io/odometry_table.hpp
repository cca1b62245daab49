#pragma once
/// \file
/// \brief Joining a GMapping-corrected CARMEN log with a table of raw odometry (the form in which
/// the Intel Research Lab data comes: ../shared/data/intel-lab/intel_910_odom_vs_corrected.txt).
///
/// The corrected log holds the ranges with corrected poses on the logger's time base; the table
/// holds, per scan, `abs_t log_t raw_x raw_y raw_theta corrected_x corrected_y corrected_theta`,
/// abs_t being the time base of the benchmark relations. The join gives two logs stamped with
/// abs_t: one whose laser poses and odometry fields are the raw odometry (what a robot would have
/// recorded), one with the corrected poses (pseudo ground truth, for map building).

#include <cstddef>
#include <string>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/io/carmen_log.hpp"

namespace vdtnav {

/// \brief One row of the table.
struct OdometryTableRow {
  double abs_time = 0.0;  ///< seconds, the relations' time base
  double log_time = 0.0;  ///< seconds, the corrected log's logger time
  Pose2 raw = Pose2::Zero();
  Pose2 corrected = Pose2::Zero();
  std::size_t line = 0;  ///< 1-based line in the table
};

/// \brief Reads the table (`#` lines are comments).
/// \throws IoError if unreadable, FormatError (`file:line: what was expected`) for a bad row.
[[nodiscard]] std::vector<OdometryTableRow> load_odometry_table(const std::string& path);

/// \brief The joined logs.
struct JoinedLogs {
  CarmenLog raw;                    ///< laser pose = odom = raw odometry, time = abs_time
  CarmenLog corrected;              ///< laser pose = odom = corrected pose, time = abs_time
  std::size_t unmatched_scans = 0;  ///< scans of the log without a table row
};

/// \brief Joins on log time (|log_time - laser time| <= tolerance).
/// \throws FormatError (naming `table_path` and the row) when a matched row's corrected pose
/// differs from the log's by more than 1 mm or 1 mrad: the table does not belong to the log;
/// ConfigError when nothing matches.
[[nodiscard]] JoinedLogs join_odometry_table(const CarmenLog& log,
                                             const std::vector<OdometryTableRow>& table,
                                             const std::string& table_path,
                                             double tolerance = 0.005);

}  // namespace vdtnav
