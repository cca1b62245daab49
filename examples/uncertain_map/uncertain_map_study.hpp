#pragma once
// The parts of the uncertain-map example beyond the fits: localization on a fitted map
// (localization.cpp) and the Intel lab study (intel_study.cpp).

#include <string>
#include <vector>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace study {

/// One row of localization.csv.
struct LocalizationRow {
  std::string map_model;
  double pos_rmse = 0.0, ori_rmse = 0.0, anees = 0.0, anees_lo = 0.0, anees_hi = 0.0;
  std::size_t anees_left_out = 0;  ///< poses the ANEES leaves out (no covariance, no finite NEES)
  std::string anees_note;          ///< eval::left_out_note: how many and why; "" for none
};

/// Drives `drive` through `world` again (a new run of `lidar` with Table 3.2's odometry and range
/// noise) and localizes it on the fitted map with vdt-opt and vdt-ekf, each with the constant
/// per-reading map floor and with the map's own covariance; writes localization_errors.png.
std::vector<LocalizationRow> localize_on_fitted_map(
    const vdtnav::mapping::UncertainVdtMap& map, const vdtnav::OccupancyGrid<2>& world,
    const std::vector<vdtnav::sim::TimedPose>& drive, const vdtnav::sim::LidarOptions& lidar,
    unsigned seed, const std::string& out);

/// What the Intel study states about its map-building run.
struct IntelSettings {
  double pose_sigma = 0.05;     ///< of the corrected poses' x and y, metres
  double heading_sigma = 0.01;  ///< of the corrected poses' heading, radians
  double sigma_range = 0.02;    ///< of the ranges, metres
  double spacing = 0.25;        ///< control points, metres
};

/// The Intel lab: the uncertain map fitted to the last third's scans at the corrected poses with
/// the stated pose uncertainty, the first two thirds localized on it; writes intel.csv and
/// intel_map_sigma.png.
void intel_uncertain_map(const std::string& data, const std::string& out,
                         const IntelSettings& settings);

}  // namespace study
