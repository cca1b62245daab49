// The machinery of the vdtnav_intel_lab study (intel_lab.cpp), internal to this example: one row
// of the table per method, the localization of the scans by one method (method_runs.cpp), the
// tables (tables.cpp) and the figures (figures.cpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"

namespace intel_study {

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
  eval::ErrorStatistics ms;           ///< each update's wall milliseconds: mean, median, p99, max
  double wall_s = 0.0;
  /// The slowest update's processor time (std::clock): its own work, without the time other
  /// processes of a shared machine took from it (ms.max, wall time, includes that).
  double cpu_ms_max = 0.0;
  /// Solver iterations of the tracked scans (solved from the prediction alone: no window search,
  /// no coarse-to-fine alignment, whatever their status), median and p99 (issue 57).
  double iterations_median = 0.0, iterations_p99 = 0.0;
  double converged_pct = 0.0;          ///< scans reported converged
  double correct_converged_pct = 0.0;  ///< of the scans within 0.1 m of the corrected pose
  /// The relations on the converged poses alone.
  eval::RelationMetricResult rel_converged;
  double published_pct = 0.0;          ///< scans the default outputs hold (converged, bridged)
  double correct_published_pct = 0.0;  ///< of the scans within 0.1 m of the corrected pose
  /// The relations on the poses a default pose file keeps (published_by_default()).
  eval::RelationMetricResult rel_published;
  std::vector<Pose2> poses;
  std::vector<Eigen::Matrix3d> cov;
};

/// The scans every method localizes (0..split-1 of the raw log, with their odometry steps and
/// times) and what they are scored against (the corrected poses and the relations).
struct Localization {
  const JoinedLogs& logs;
  std::size_t split;
  double sigma_range;
  const std::vector<double>& times;
  const eval::Trajectory2& reference;
  const std::vector<OdometryStep>& steps;
  const std::vector<Relation>& relations;
  const eval::RelationMetricOptions& ro;
};

/// Localizes the scans with `method` from the corrected pose of the first scan (covariance p0),
/// scores it, writes out/traj_METHOD.tum and prints one line.
Row localize_method(const std::string& method, const VdtMap2& vdt, const mapping::OccupancyMap& map,
                    const LocalizerSettings& settings, const Eigen::Matrix3d& p0,
                    const Localization& in, const std::string& out);

/// Writes the table of `rows` as CSV to `csv` and as Markdown to `md`.
void write_tables(std::ostream& csv, std::ostream& md, const std::vector<Row>& rows,
                  std::size_t split, std::size_t n, double build_s);

/// Writes trajectories.png and, for vdt-opt and vdt-ekf, scans_METHOD.png and errors_METHOD.png.
void write_figures(const std::string& out, const mapping::OccupancyMap& map, const Localization& in,
                   const std::vector<Row>& rows);

}  // namespace intel_study
