// The Intel Research Lab with an uncertain map: the map fitted to the scans of the last third at
// their corrected poses with a stated pose uncertainty (what `vdtnav map --uncertain` fits, saved
// to intel.umap and mapped back, as `vdtnav localize --map intel.umap` reads it), the first two
// thirds localized on it (vdt-opt with the real-log settings of `vdtnav localize`), the relation
// NEES (Kuemmerle's relations, SPEC's definition) with and without the map's covariance, and on
// the occupancy map of the same scans for reference; with the time each map took to build.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "uncertain_map_study.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/mapping/uncertain_map_file.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;

namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
}  // namespace

void intel_uncertain_map(const std::string& data, const std::string& out,
                         const IntelSettings& settings) {
  using Clock = std::chrono::steady_clock;
  const std::string dir = data + "/intel-lab/";
  std::printf(
      "[intel] the uncertain map of the Intel lab from the last third of %sintel.gfs.log.gz\n",
      dir.c_str());
  const CarmenLog gfs = load_carmen_log(dir + "intel.gfs.log.gz");
  const std::string table_path = dir + "intel_910_odom_vs_corrected.txt";
  const JoinedLogs logs = join_odometry_table(gfs, load_odometry_table(table_path), table_path);
  const std::size_t n = logs.raw.lasers.size();
  const std::size_t split = n - n / 3;

  // The map: the corrected poses of scans split..n-1 with the stated uncertainty.
  const Eigen::Matrix3d pose_cov = Eigen::Vector3d(settings.pose_sigma * settings.pose_sigma,
                                                   settings.pose_sigma * settings.pose_sigma,
                                                   settings.heading_sigma * settings.heading_sigma)
                                       .asDiagonal();
  std::vector<mapping::MapScan> scans;
  std::vector<Pose2> map_poses;
  std::vector<LaserScan> map_lasers;
  for (std::size_t i = split; i < n; ++i) {
    LaserScan laser = logs.corrected.lasers[i].scan;
    laser.sigma_range = settings.sigma_range;
    mapping::MapScan s;
    s.pose = logs.corrected.lasers[i].pose;
    s.pose_covariance = pose_cov;
    s.points = scan_points(laser);
    scans.push_back(std::move(s));
    map_poses.push_back(logs.corrected.lasers[i].pose);
    map_lasers.push_back(laser);
  }
  mapping::UncertainMapOptions mo;
  mo.spacing = settings.spacing;  // 0: from the data
  // The occupancy map of the same scans, as the Intel study builds it.
  const auto t_ogm = Clock::now();
  mapping::OccupancyMapperOptions oo;
  oo.resolution = 0.05;
  const mapping::OccupancyMap ogm = mapping::build_occupancy_map(map_poses, map_lasers, oo);
  const VdtMap2 ogm_vdt = VdtMap2::build(ogm.occupancy);
  const double ogm_s = std::chrono::duration<double>(Clock::now() - t_ogm).count();
  const mapping::UncertainVdtMap fitted_map = mapping::UncertainVdtMap::fit(scans, mo);
  mapping::save_uncertain_map(out + "/intel.umap", fitted_map, ogm.cells);
  const mapping::UncertainMapFile file = mapping::load_uncertain_map(out + "/intel.umap");
  const mapping::UncertainVdtMap& map = file.map;
  const auto& sm = fitted_map.summary();
  std::printf(
      "[intel] %zu scans (sigma %.3f m, %.4f rad, range %.3f m), h = %.2f m: %d control "
      "points, %d boundary points (%d cleared by the beams), %d Eikonal and %d free-space "
      "samples: fit %.1f s (%d iterations%s), covariance %.1f s%s; saved to intel.umap and "
      "mapped back\n",
      scans.size(), settings.pose_sigma, settings.heading_sigma, settings.sigma_range, sm.spacing,
      sm.control_points, sm.boundary_points, sm.cleared_readings, sm.eikonal_samples,
      sm.free_space_samples, sm.fit_seconds, sm.iterations, sm.converged ? "" : ", NOT converged",
      sm.covariance_seconds, sm.covariance_ok ? "" : " (FAILED)");
  const VdtMap2 fitted = map.to_vdt_map(0.05);

  // Localize scans 0..split-1 with the raw odometry.
  std::vector<std::size_t> idx(split);
  for (std::size_t i = 0; i < split; ++i) idx[i] = i;
  const LogOdometry odom = log_odometry(logs.raw, idx);
  std::vector<double> times;
  for (std::size_t i : idx) times.push_back(logs.raw.lasers[i].time);
  const std::vector<OdometryStep> steps = odometry_steps(times, odom.poses);
  const std::vector<Relation> relations = load_relations(dir + "intel.relations").relations;
  eval::RelationMetricOptions ro;  // exact stamps only: one scan every ~3 s
  ro.stamp_tolerance = 1e-6;
  ro.interpolate = false;

  struct Model {
    std::string name;
    const VdtMap2* vdt;
    const mapping::UncertainVdtMap* uncertainty;
    double map_sigma;           // < 0: the sensor model's default
    double correlation_length;  // the squares (0: off)
  };
  const LocalizerSettings base = log_settings();
  const std::vector<Model> models = {
      {"ogm squares", &ogm_vdt, nullptr, -1.0, base.vdt_opt.sensor.map_correlation_length},
      {"fitted floor", &fitted, nullptr, -1.0, 0.0},
      {"fitted squares", &fitted, nullptr, -1.0, base.vdt_opt.sensor.map_correlation_length},
      {"fitted map-variance", &fitted, &map, map.approximation_sigma(),
       base.vdt_opt.sensor.map_correlation_length},
  };
  std::ofstream csv(out + "/intel.csv");
  csv << "map_model,relations,rel_trans_mean_m,rel_rot_mean_deg,rel_nees_used,rel_nees_mean,"
         "rel_nees_median,rel_nees_inside_7.81,ms_per_scan,ms_median,ms_p99,ms_max,build_s,"
         "covariance_s\n";
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05).asDiagonal();
  for (const Model& m : models) {
    LocalizerSettings s = base;
    s.vdt_opt.sensor.map_uncertainty = m.uncertainty;
    s.vdt_opt.sensor.map_sigma = m.map_sigma;
    s.vdt_opt.sensor.map_correlation_length = m.correlation_length;
    std::unique_ptr<Localizer2D> loc =
        make_localizer("vdt-opt", *m.vdt, ogm.occupancy, s, MapKnowledge(ogm.cells));
    loc->reset(logs.corrected.lasers[0].pose, p0);
    eval::Trajectory2 est;
    std::vector<Eigen::Matrix3d> cov;
    std::vector<double> scan_ms;
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < split; ++k) {
      LaserScan scan = logs.raw.lasers[k].scan;
      scan.sigma_range = settings.sigma_range;
      const auto u0 = Clock::now();
      const LocalizationResult res = loc->update(steps[k], scan);
      scan_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - u0).count());
      est.push_back({times[k], res.pose});
      cov.push_back(res.has_covariance ? res.covariance : Eigen::Matrix3d::Constant(std::nan("")));
    }
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / split;
    const eval::ErrorStatistics per_scan = eval::error_statistics(scan_ms);
    const eval::RelationMetricResult rel = eval::relation_metric(est, relations, ro);
    const eval::RelationNeesResult rn = eval::relation_nees(est, cov, relations);
    std::printf(
        "[intel] vdt-opt on the %-20s relations %zu: %.4f m / %.3f deg; relation NEES "
        "n %zu, mean %.2f, median %.2f, %.1f %% <= 7.81; %.2f ms/scan (median %.2f, p99 %.2f, "
        "max %.2f)\n",
        (m.name + " map").c_str(), rel.used, rel.translation.mean, rel.rotation.mean * kRadToDeg,
        rn.used, rn.mean, rn.median, 100.0 * rn.fraction_inside, ms, per_scan.median, per_scan.p99,
        per_scan.max);
    // The map's build: the occupancy grid and its VDT, or the fit and its covariance.
    const bool is_ogm = m.vdt == &ogm_vdt;
    char line[512];
    std::snprintf(
        line, sizeof line, "%s,%zu,%.5f,%.4f,%zu,%.3f,%.3f,%.4f,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f\n",
        m.name.c_str(), rel.used, rel.translation.mean, rel.rotation.mean * kRadToDeg, rn.used,
        rn.mean, rn.median, rn.fraction_inside, ms, per_scan.median, per_scan.p99, per_scan.max,
        is_ogm ? ogm_s : sm.fit_seconds, is_ogm ? 0.0 : sm.covariance_seconds);
    csv << line;
  }

  // The fitted map's sigma over the lab.
  const Eigen::Vector2d lo = map.origin();
  const Eigen::Vector2d hi = lo + map.cells().cast<double>() * map.spacing();
  const double res = 0.05;
  const Eigen::Vector2i size = ((hi - lo) / res).array().ceil().cast<int>().matrix();
  Grid<float, 2> fs(size, GridFrame<2>(res, lo), NAN);
  for (int y = 0; y < size.y(); ++y) {
    for (int x = 0; x < size.x(); ++x) {
      const mapping::UncertainMapSample smp =
          map.evaluate(fs.frame().cell_center(Eigen::Vector2i(x, y)));
      if (smp.inside)
        fs(Eigen::Vector2i(x, y)) = static_cast<float>(std::sqrt(smp.covariance.trace()));
    }
  }
  viz::Figure fig(1200, 1100, 1, 1);
  fig.axes(0, 0)
      .title("Intel lab: sqrt(trace cov DT_v) of the map fitted to the last third")
      .image(viz::heatmap(fs, viz::Colormap::kViridis, 0.0, 0.1), lo.x(), hi.x(), lo.y(), hi.y())
      .equal_aspect()
      .colorbar(viz::Colormap::kViridis, 0.0, 0.1, "sigma (m)");
  fig.save_png(out + "/intel_map_sigma.png");
}

}  // namespace study
