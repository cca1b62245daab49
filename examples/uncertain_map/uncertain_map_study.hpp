#pragma once
// The parts of the uncertain-map example beyond main(): Fig. 5.2's approximation
// (approximation.cpp), the fits of Experiments 1 and 2 (experiments.cpp), their errors at the true
// boundary (boundary_errors.cpp) and figures (map_figures.cpp), the tables (tables.cpp),
// localization on a fitted map (localization.cpp) and the Intel lab study (intel_study.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/mapping_run.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace study {

/// The errors of a fitted map at the true boundary (Fig. 5.6): at every true boundary point in
/// the fitted band, the fitted DT_v along the fitted normal n (the dominant eigenvector of the
/// symmetric part of dDT_v/dp), e = n^T DT_v, and its sigma = sqrt(n^T cov(DT_v) n).
struct BoundaryErrors {
  std::vector<double> index, error, sigma;
  double sum_sq = 0.0, max_abs = 0.0;
  int within = 0;
  void add(double e, double s) {
    index.push_back(static_cast<double>(index.size()));
    error.push_back(e);
    sigma.push_back(s);
    sum_sq += e * e;
    max_abs = std::max(max_abs, std::abs(e));
    if (std::abs(e) <= 2.0 * s) ++within;
  }
  void add(const BoundaryErrors& o) {
    for (std::size_t k = 0; k < o.error.size(); ++k) add(o.error[k], o.sigma[k]);
  }
  [[nodiscard]] double rms() const {
    return error.empty() ? std::nan("") : std::sqrt(sum_sq / static_cast<double>(error.size()));
  }
  [[nodiscard]] double within_pct() const {
    return error.empty() ? std::nan("") : 100.0 * within / static_cast<double>(error.size());
  }
};

/// At most `max_points` of the true boundary points, evenly spread (every beam of every scan
/// gives one; neighbours repeat each other).
BoundaryErrors boundary_errors(const vdtnav::mapping::UncertainVdtMap& map,
                               const std::vector<Eigen::Vector2d>& truth, std::size_t max_points);

/// The errors at the true boundary with +-2 sigma, one point after the other (Fig. 5.6).
void plot_boundary_errors(const BoundaryErrors& e, const std::string& path,
                          const std::string& title);

/// The DT_x, DT_y and sigma fields (Fig. 5.4) and the zero contour against the observations and
/// the truth (Fig. 5.5) of one fitted map, over the window [lo, hi].
void plot_map(const vdtnav::mapping::UncertainVdtMap& map,
              const std::vector<Eigen::Vector2d>& truth, const std::string& prefix,
              const std::string& title);

/// One row of table.csv: a fit (an experiment, pooled over its runs) or an approximation.
struct Row {
  std::string experiment;
  double spacing = 0.0;
  int control_points = 0, samples = 0;
  double rms = 0.0, max = 0.0, within = std::nan(""), fit_s = 0.0, cov_s = 0.0;
};

/// Fig. 5.2: the least-squares B-spline approximation of the true VDT of `room` against the
/// spacing; its rows go to `rows`, the figure to fig5_2_approximation.png.
void approximation(const vdtnav::sim::MappingScene& room, const std::string& out,
                   std::vector<Row>& rows);

/// One experiment: the uncertain map fitted to `runs` noisy map-building runs through `scene`
/// (`noise` times `noise_scale`), its errors at the true boundary pooled into a row of `rows`; the
/// first run's map and figures (<name>_*.png), the map and the run kept in `keep` and `keep_run`
/// when given.
void fit_experiment(const std::string& name, const vdtnav::sim::MappingScene& scene,
                    const vdtnav::sim::LidarOptions& lidar, const vdtnav::sim::MappingNoise& noise,
                    double spacing, std::unique_ptr<vdtnav::mapping::UncertainVdtMap>* keep,
                    vdtnav::sim::MappingRun* keep_run, int runs, double noise_scale, unsigned seed,
                    const std::string& out, std::vector<Row>& rows);

/// Experiment 2's scene: the Willow Garage map's upper corridor, or the generated floor plan's
/// main corridor.
vdtnav::sim::MappingScene corridor(const std::string& data, std::uint32_t seed);

/// One row of localization.csv.
struct LocalizationRow {
  std::string map_model;
  double pos_rmse = 0.0, ori_rmse = 0.0, anees = 0.0, anees_lo = 0.0, anees_hi = 0.0;
  std::size_t anees_left_out = 0;    ///< poses the ANEES leaves out (no covariance, no finite NEES)
  std::string anees_note;            ///< eval::left_out_note: how many and why; "" for none
  double nees_inside_95_pct = 0.0;   ///< the per-step 95 % bound (eval::AneesResult)
  vdtnav::eval::ErrorStatistics ms;  ///< each update's wall time, milliseconds
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
  double spacing = 0.0;         ///< control points, metres; 0: from the data
};

/// The Intel lab: the uncertain map fitted to the last third's scans at the corrected poses with
/// the stated pose uncertainty, the first two thirds localized on it; writes intel.csv and
/// intel_map_sigma.png.
void intel_uncertain_map(const std::string& data, const std::string& out,
                         const IntelSettings& settings);

/// Writes table.csv (`rows`), localization.csv (`loc`) and table.md (both; `c2` is Experiment 2's
/// scene).
void write_tables(const std::string& out, const std::vector<Row>& rows,
                  const vdtnav::sim::MappingScene& c2, const std::vector<LocalizationRow>& loc);

}  // namespace study
