#include "vdtnav/io/odometry_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

std::vector<OdometryTableRow> load_odometry_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open");
  std::vector<OdometryTableRow> rows;
  std::string line;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    OdometryTableRow r;
    r.line = n;
    if (!(s >> r.abs_time >> r.log_time >> r.raw[0] >> r.raw[1] >> r.raw[2] >> r.corrected[0] >>
          r.corrected[1] >> r.corrected[2]) ||
        !(s >> std::ws).eof()) {
      throw FormatError(path, n,
                        "expected 8 numbers: abs_t log_t raw_x raw_y raw_theta corrected_x "
                        "corrected_y corrected_theta");
    }
    if (!std::isfinite(r.abs_time) || !std::isfinite(r.log_time) || !r.raw.allFinite() ||
        !r.corrected.allFinite()) {
      throw FormatError(path, n, "expected finite numbers");
    }
    rows.push_back(r);
  }
  if (rows.empty()) throw FormatError(path, 0, "expected at least one row");
  return rows;
}

JoinedLogs join_odometry_table(const CarmenLog& log, const std::vector<OdometryTableRow>& table,
                               const std::string& table_path, double tolerance) {
  JoinedLogs out;
  // Logs are not always in time order (the Intel log has four scans earlier than the one before
  // them), so rows are looked up by log time, and the joined logs sorted by absolute time.
  std::vector<const OdometryTableRow*> by_log_time;
  for (const auto& row : table) by_log_time.push_back(&row);
  std::sort(by_log_time.begin(), by_log_time.end(),
            [](const auto* a, const auto* b) { return a->log_time < b->log_time; });
  for (const CarmenLaser& l : log.lasers) {
    auto it = std::lower_bound(by_log_time.begin(), by_log_time.end(), l.time - tolerance,
                               [](const auto* row, double t) { return row->log_time < t; });
    if (it == by_log_time.end() || std::abs((*it)->log_time - l.time) > tolerance) {
      ++out.unmatched_scans;
      continue;
    }
    const OdometryTableRow& row = **it;
    if ((row.corrected.head<2>() - l.pose.head<2>()).norm() > 1e-3 ||
        std::abs(wrap_angle(row.corrected[2] - l.pose[2])) > 1e-3) {
      throw FormatError(table_path, row.line,
                        "the corrected pose differs from the log's at line " +
                            std::to_string(l.line) +
                            " (same time): the table does not belong to this log");
    }
    CarmenLaser joined = l;
    joined.time = joined.ipc_time = joined.scan.time = row.abs_time;
    joined.pose = joined.odom = row.raw;
    out.raw.lasers.push_back(joined);
    joined.pose = joined.odom = row.corrected;
    out.corrected.lasers.push_back(joined);
  }
  const auto by_time = [](const CarmenLaser& a, const CarmenLaser& b) { return a.time < b.time; };
  std::stable_sort(out.raw.lasers.begin(), out.raw.lasers.end(), by_time);
  std::stable_sort(out.corrected.lasers.begin(), out.corrected.lasers.end(), by_time);
  if (out.raw.lasers.empty()) {
    throw ConfigError(table_path + ": no row matches a scan of the log within " +
                      std::to_string(tolerance) + " s");
  }
  return out;
}

}  // namespace vdtnav
