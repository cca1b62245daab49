// Localization on the Experiment 2 map: the same simulated run localized with the constant
// per-reading map floor and with the fitted map's own covariance (thesis ch. 5's use of the map
// uncertainty), by vdt-opt and vdt-ekf; and on the occupancy map of the same mapping scans (the
// cells their readings fall in, 5 cm) for reference.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "uncertain_map_study.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/viz/plot.hpp"

namespace study {

using namespace vdtnav;

namespace {

/// A localizer's errors over the run and the reported sigmas.
struct Track {
  std::vector<double> t, ex, ey, ephi, sx, sy, sphi;
};

void plot_tracks(const std::vector<std::string>& names, const std::vector<Track>& tracks,
                 const std::string& path) {
  viz::Figure fig(1600, 1100, 3, 1);
  fig.title("Localization on the fitted Experiment 2 map: errors and +-2 sigma (vdt-opt)");
  const std::vector<viz::Rgb> colours = {{213, 94, 0}, {0, 114, 178}};
  const char* labels[3] = {"x error (m)", "y error (m)", "heading error (rad)"};
  for (int axis = 0; axis < 3; ++axis) {
    viz::Axes& ax = fig.axes(axis, 0);
    ax.ylabel(labels[axis]).xlabel("time (s)");
    for (std::size_t m = 0; m < tracks.size(); ++m) {
      const Track& tr = tracks[m];
      const std::vector<double>& e = axis == 0 ? tr.ex : axis == 1 ? tr.ey : tr.ephi;
      const std::vector<double>& s = axis == 0 ? tr.sx : axis == 1 ? tr.sy : tr.sphi;
      std::vector<double> lo(s.size()), hi(s.size());
      for (std::size_t k = 0; k < s.size(); ++k) {
        lo[k] = -2.0 * s[k];
        hi[k] = 2.0 * s[k];
      }
      ax.line(
          tr.t, lo,
          viz::Style().with_color(colours[m]).with_dashes().with_label("+-2 sigma, " + names[m]));
      ax.line(tr.t, hi, viz::Style().with_color(colours[m]).with_dashes());
      ax.line(tr.t, e,
              viz::Style().with_color(colours[m]).with_width(1.0).with_label("error, " + names[m]));
    }
    if (axis == 0) ax.legend(viz::LegendLocation::kUpperRight);
  }
  fig.save_png(path);
}

}  // namespace

std::vector<LocalizationRow> localize_on_fitted_map(const mapping::UncertainVdtMap& map,
                                                    const OccupancyGrid<2>& world,
                                                    const std::vector<sim::TimedPose>& drive,
                                                    const sim::LidarOptions& lidar, unsigned seed,
                                                    const std::string& out) {
  // The localizers read the fitted field sampled at 5 cm (outside the band: the exact VDT of the
  // observed points).
  const VdtMap2 vdt = map.to_vdt_map(0.05);
  // The occupancy map of the same scans: the 5 cm cells the readings fall in.
  const Eigen::Vector2i ogm_size =
      (map.cells().cast<double>() * (map.spacing() / 0.05)).array().ceil().cast<int>().matrix();
  OccupancyGrid<2> ogm(ogm_size, GridFrame<2>(0.05, map.origin()));
  for (const Eigen::Vector2d& p : map.observed_points()) {
    const Eigen::Vector2i c = ogm.frame().cell_of(p);
    if (ogm.contains(c)) ogm(c) = 1;
  }
  const VdtMap2 ogm_vdt = VdtMap2::build(ogm);
  const sim::SimulatedRun run =
      sim::simulate_run(world, drive, lidar, sim::NoiseProfile::table_3_2_sigma(), seed + 7919u);
  std::printf(
      "[localization] %zu scans of a new run through the Experiment 2 world, localized "
      "on the fitted map (sampled at 0.05 m)\n",
      run.size());
  struct Model {
    std::string name;
    const VdtMap2* vdt;
    const mapping::UncertainVdtMap* uncertainty;
    double map_sigma;
  };
  // The constant floor: the sensor model's default, resolution / sqrt(12) per reading,
  // independent. The map's covariance: propagate() with the correlations between the endpoints,
  // and per reading only what the fit's boundary floor says the spline cannot follow.
  const std::vector<Model> models = {{"ogm constant-floor", &ogm_vdt, nullptr, -1.0},
                                     {"constant-floor", &vdt, nullptr, -1.0},
                                     {"map-variance", &vdt, &map, map.approximation_sigma()}};
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
  std::vector<LocalizationRow> rows;
  std::vector<Track> opt_tracks;
  for (const std::string method : {"vdt-opt", "vdt-ekf"}) {
    for (const Model& m : models) {
      VdtSensorModelOptions so;
      so.map_uncertainty = m.uncertainty;
      so.map_sigma = m.map_sigma;
      std::unique_ptr<Localizer2D> loc;
      if (std::string(method) == "vdt-opt") {
        VdtOptimizerOptions o;
        o.sensor = so;
        loc = std::make_unique<VdtOptimizationLocalizer>(*m.vdt, o);
      } else {
        VdtEkfOptions o;
        o.sensor = so;
        loc = std::make_unique<VdtEkfLocalizer>(*m.vdt, o);
      }
      loc->reset(run.truth[0], p0);
      std::vector<double> nees;
      double se_pos = 0.0, se_ori = 0.0;
      Track tr;
      std::vector<double> scan_ms;
      for (std::size_t k = 0; k < run.size(); ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const LocalizationResult res = loc->update(run.odometry[k], run.scans[k]);
        scan_ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
        const Eigen::Vector3d e = pose_error(res.pose, run.truth[k]);
        se_pos += e.head<2>().squaredNorm();
        se_ori += e[2] * e[2];
        if (res.has_covariance) nees.push_back(eval::nees(res.pose, run.truth[k], res.covariance));
        tr.t.push_back(run.times[k]);
        tr.ex.push_back(e[0]);
        tr.ey.push_back(e[1]);
        tr.ephi.push_back(e[2]);
        tr.sx.push_back(std::sqrt(std::max(0.0, res.covariance(0, 0))));
        tr.sy.push_back(std::sqrt(std::max(0.0, res.covariance(1, 1))));
        tr.sphi.push_back(std::sqrt(std::max(0.0, res.covariance(2, 2))));
      }
      const eval::AneesResult a = eval::anees(nees, 3);
      LocalizationRow row;
      row.map_model = std::string(method) + " " + m.name;
      row.pos_rmse = std::sqrt(se_pos / static_cast<double>(run.size()));
      row.ori_rmse = std::sqrt(se_ori / static_cast<double>(run.size()));
      row.anees = a.anees;
      row.anees_lo = a.interval.lower;
      row.anees_hi = a.interval.upper;
      row.anees_left_out = run.size() - a.count;
      row.anees_note = eval::left_out_note(a, run.size());
      row.nees_inside_95_pct = a.inside_95_pct;
      row.ms = eval::error_statistics(scan_ms);
      std::printf(
          "  %-28s position RMSE %.4f m, heading RMSE %.5f rad, ANEES %.2f [%.2f, %.2f]%s, "
          "%.3f ms per scan (median %.3f, p99 %.3f, max %.3f)\n",
          row.map_model.c_str(), row.pos_rmse, row.ori_rmse, row.anees, row.anees_lo, row.anees_hi,
          a.interval.contains(a.anees) ? "" : " (outside)", row.ms.mean, row.ms.median, row.ms.p99,
          row.ms.max);
      rows.push_back(row);
      if (std::string(method) == "vdt-opt" && m.vdt == &vdt) opt_tracks.push_back(std::move(tr));
    }
  }
  plot_tracks({models[1].name, models[2].name}, opt_tracks, out + "/localization_errors.png");
  return rows;
}

}  // namespace study
