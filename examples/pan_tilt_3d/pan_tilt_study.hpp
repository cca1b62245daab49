// The machinery of the vdtnav_pan_tilt_3d study (pan_tilt_3d.cpp), internal to this example: the
// scenarios of Table 3.4 and the downsampling factors, the world the study runs in (world.cpp),
// the localization trials (trials.cpp), the table (tables.cpp) and the figures (figures.cpp).
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sim/point_laser_simulator.hpp"

namespace pan_tilt_study {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

/// Table 3.4: the initial guess is off by +dt in x, y, z and +dr in roll, pitch and yaw.
struct Scenario {
  const char* name;
  double dt;  ///< metres
  double dr;  ///< radians
};
constexpr std::array<Scenario, 4> kScenarios{
    {{"A", 0.05, 0.025}, {"B", 0.1, 0.05}, {"C", 0.2, 0.1}, {"D", 0.4, 0.2}}};
/// Downsampling factors of 3.4.4.2 (1: the whole sweep).
constexpr std::array<int, 5> kFactors{1, 2, 5, 10, 100};
constexpr double kSuccessPosition = 0.1;   ///< metres
constexpr double kSuccessAttitude = 0.05;  ///< radians

/// The world the study runs in: the occupancy the simulator casts rays in, its VDT and the three
/// robot locations.
struct World {
  std::string name;
  OccupancyGrid<3> occupancy;
  std::vector<Pose3> locations;
  std::string how_located;  ///< one line on how the locations were chosen
};

/// One localization attempt.
struct Trial {
  LocalizationStatus status = LocalizationStatus::kTooFewObservations;
  double position_error = 0.0;  ///< metres
  double attitude_error = 0.0;  ///< radians (rotation angle of R_est R_true^T)
  double ms = 0.0;
  int observations = 0;
  int inliers = 0;
  double final_cost = 0.0;
  /// --verbose: the truncated VCD at the estimate and at the truth (multi_start.hpp); an estimate
  /// that scores lower than the truth is a wrong minimum no search could have told apart.
  double tvcd_estimate = 0.0, tvcd_truth = 0.0;
};

/// One cell of Table 3.4 x factors.
struct Cell {
  int trials = 0, converged = 0, success = 0;
  int within = 0;  ///< an estimate (converged or not) within the success thresholds
  double pos_sq = 0.0, att_sq = 0.0, ms = 0.0, observations = 0.0;
  std::vector<double> solve_ms;  ///< each trial's solve: the table's median, p99 and max
  [[nodiscard]] double success_pct() const { return trials ? 100.0 * success / trials : 0.0; }
  [[nodiscard]] double pos_rmse() const {
    return converged ? std::sqrt(pos_sq / converged) : std::numeric_limits<double>::quiet_NaN();
  }
  [[nodiscard]] double att_rmse() const {
    return converged ? std::sqrt(att_sq / converged) : std::numeric_limits<double>::quiet_NaN();
  }
  [[nodiscard]] double ms_mean() const { return trials ? ms / trials : 0.0; }
};

/// \return the world height of the beam origin at zero pan and tilt (the "sensor height").
double sensor_z(const Pose3& robot, const PanTiltCalibration& calibration);

/// Builds the world: the generated 3D room (map_path empty) or the OctoMap at map_path, with its
/// VDT and the three robot locations. \return false (the error printed) when map_path is given
/// but this build has no OctoMap front end.
bool build_world(const std::string& map_path, unsigned seed, double resolution, World& world,
                 std::unique_ptr<VdtMap3>& vdt);

/// The trials of the study.
struct TrialRuns {
  /// trials[job][scenario * factors + factor], job = location * seeds + seed
  std::vector<std::vector<Trial>> trials;
  std::vector<std::size_t> sweep_returns;  ///< per job: returns of the whole sweep
  double seconds = 0.0;                    ///< wall time of all the trials
};

/// Runs every scenario x factor at every location x noise seed on `threads` threads (progress on
/// stderr).
TrialRuns run_trials(const World& world, const VdtOptimizer3& optimizer,
                     const sim::PointLaserSimOptions& sim_options,
                     const MultiStartOptions& multi_start, unsigned seed, int seeds, bool four_dof,
                     bool verbose, int threads);

/// \return the cells of Table 3.4 x factors, cells[scenario][factor] (--verbose: every unsuccessful
/// trial listed on stderr).
std::vector<std::vector<Cell>> tabulate(const std::vector<std::vector<Trial>>& trials, int seeds,
                                        bool verbose);

/// Writes table.csv and table.md to `out` and the table to stdout.
void write_tables(const std::string& out, const World& world,
                  const sim::PointLaserSimOptions& sim_options,
                  const std::vector<std::vector<Cell>>& cells,
                  const std::vector<std::size_t>& sweep_returns, int seeds, bool four_dof);

/// Writes vdt_slice_horizontal.png and vdt_slice_vertical.png (figures.cpp).
void write_vdt_slices(const World& world, const VdtMap3& vdt, const PanTiltCalibration& cal,
                      const std::string& out);

/// Fig. 3.18: writes the RMSE figure to `path` (figures.cpp).
void write_rmse_figure(const std::vector<std::vector<Cell>>& cells, const std::string& title,
                       const std::string& path);

}  // namespace pan_tilt_study
