// The machinery of the vdtnav_active_beam study (active_beam.cpp), internal to this example: the
// two datasets (datasets.cpp), the localization with one beam strategy (beam_localization.cpp),
// the table rows (tables.cpp) and the figures (figures.cpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "vdtnav/estimation/active_beam.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/sensor/odometry.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace active_beam_study {

using namespace vdtnav;
using Eigen::Vector2d;
using Clock = std::chrono::steady_clock;

/// A dataset: the world (also the map: thin walls through its occupied cells' centres), the drive,
/// the sensor.
struct Dataset {
  std::string name;
  OccupancyGrid<2> world;
  std::vector<sim::TimedPose> drive;
  RotatingBeamOptions beam;
  double map_sigma = -1.0;  ///< the EKF's per-reading map floor
};

/// Odometry of the drive with Table 3.2's noise (datasets.cpp).
std::vector<OdometryStep> odometry(const std::vector<sim::TimedPose>& drive, std::mt19937_64& rng);

/// One strategy's run over a dataset: the errors, sigmas and beam per step, and the scores.
struct Run {
  BeamStrategy strategy;
  std::vector<double> t, ex, ey, ephi, sx, sy, sphi, bearing, goal;
  std::vector<Pose2> estimate;
  double rmse_x = 0, rmse_y = 0, rmse_phi = 0, lost_pct = 0, ms_select = 0;
  eval::AneesResult anees;
  int selections = 0;
  int gated = 0;  ///< readings refused by the ray-cast gate
  /// Each step's time on the robot (the gate, the EKF update and the selection when the beam
  /// needs a goal; not the simulated reading): the table's median, p99 and max.
  std::vector<double> step_ms;
};

/// Dataset 1 (the Willow Garage map with --data, else a generated floor plan, Table 4.1's sensor)
/// and dataset 2 (the fetch-office map with --data, else a generated floor plan, Table 4.3's
/// sensor), each with a drive of `minutes` through it.
std::vector<Dataset> make_datasets(const std::string& data, unsigned seed, double minutes);

/// Localizes the drive of `ds` with the VDT EKF and one reading per step, the beam pointed by
/// `strategy`; `seed` seeds the range noise.
Run localize(const Dataset& ds, const VdtMap2& map, BeamStrategy strategy,
             const std::vector<OdometryStep>& odo, std::uint32_t seed);

/// Writes the header of table.csv to `csv` and of table.md to `md`.
void write_table_header(std::ostream& csv, std::ostream& md);

/// Writes the row of run `r` (strategy `s` on dataset number `d`, `ds`) to `csv` and `md`.
void write_table_row(std::ostream& csv, std::ostream& md, const Dataset& ds, std::size_t d,
                     BeamStrategy s, const Run& r);

/// Writes PREFIX_trajectory.png, PREFIX_errors.png, PREFIX_segments.png and
/// PREFIX_snapshot.png (Figs. 4.3-4.7).
void plots(const Dataset& ds, const std::vector<Run>& runs, const std::string& prefix);

}  // namespace active_beam_study
