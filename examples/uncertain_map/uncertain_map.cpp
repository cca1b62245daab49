// Uncertain VDT maps (thesis ch. 5): B-spline distance fields fitted to noisy scans through the
// Eikonal equation, their covariance, and localization on them.
//
//   vdtnav_uncertain_map --out out/uncertain_map [--seed 1] [--runs 3] [--data ../shared/data]
//
// Fig. 5.2: the least-squares B-spline approximation of the true VDT against the spacing.
// Experiment 1: the L-shaped room seen from 3 poses by a 180 degree LiDAR (Table 5.1's noise),
// control points at 0.2 m. Experiment 2: a corridor (the Willow Garage map with --data, else the
// generated floor plan's main corridor) driven with a 270 degree LiDAR (Table 5.2's noise),
// control points at 0.25 m. Localization on the Experiment 2 map, with the constant map floor and
// with the fitted map's covariance. With --data, the Intel lab: the uncertain map from the last
// third's scans, the first two thirds localized on it (intel_study.cpp).
// Writes table.csv, localization.csv, table.md and the figures.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Eigenvalues>

#include "uncertain_map_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/mapping_run.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"
#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/plot.hpp"

using namespace vdtnav;
using Eigen::Vector2d;

namespace {

constexpr double kPi = 3.14159265358979323846;

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
BoundaryErrors boundary_errors(const mapping::UncertainVdtMap& map,
                               const std::vector<Vector2d>& truth, std::size_t max_points) {
  BoundaryErrors out;
  const std::size_t step = std::max<std::size_t>(1, truth.size() / max_points);
  for (std::size_t k = 0; k < truth.size(); k += step) {
    const mapping::UncertainMapSample s = map.evaluate(truth[k]);
    if (!s.inside || !s.covariance.allFinite()) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 *
                                                            (s.jacobian + s.jacobian.transpose()));
    const int i = std::abs(es.eigenvalues()[1]) >= std::abs(es.eigenvalues()[0]) ? 1 : 0;
    const Vector2d n = es.eigenvectors().col(i);
    out.add(n.dot(s.value), std::sqrt(std::max(0.0, n.dot(s.covariance * n))));
  }
  return out;
}

struct Row {
  std::string experiment;
  double spacing = 0.0;
  int control_points = 0, samples = 0;
  double rms = 0.0, max = 0.0, within = std::nan(""), fit_s = 0.0, cov_s = 0.0;
};

/// The DT_x, DT_y and sigma fields (Fig. 5.4) and the zero contour against the observations and
/// the truth (Fig. 5.5) of one fitted map, over the window [lo, hi].
void plot_map(const mapping::UncertainVdtMap& map, const std::vector<Vector2d>& truth,
              const std::string& prefix, const std::string& title) {
  const Vector2d lo = map.origin();
  const Vector2d hi = lo + map.cells().cast<double>() * map.spacing();
  const double res = std::max(0.01, (hi - lo).maxCoeff() / 1200.0);
  const Eigen::Vector2i size = ((hi - lo) / res).array().ceil().cast<int>().matrix();
  Grid<float, 2> fx(size, GridFrame<2>(res, lo), NAN), fy = fx, fs = fx;
  std::vector<double> zx, zy;
  for (int y = 0; y < size.y(); ++y) {
    for (int x = 0; x < size.x(); ++x) {
      const Vector2d c = fx.frame().cell_center(Eigen::Vector2i(x, y));
      const mapping::UncertainMapSample s = map.evaluate(c);
      if (!s.inside) continue;
      fx(Eigen::Vector2i(x, y)) = static_cast<float>(s.value.x());
      fy(Eigen::Vector2i(x, y)) = static_cast<float>(s.value.y());
      fs(Eigen::Vector2i(x, y)) = static_cast<float>(std::sqrt(s.covariance.trace()));
      // The zero contour: where DT_v is shorter than half a pixel and points across it.
      if (s.value.norm() < 0.5 * res) {
        zx.push_back(c.x());
        zy.push_back(c.y());
      }
    }
  }
  const double band = 1.0;
  const double shi = std::min(0.1, viz::finite_range(fs).second);
  {
    viz::Figure fig(1800, 650, 1, 3);
    fig.title(title + ": the fitted map (Fig. 5.4)");
    fig.axes(0, 0)
        .image(viz::heatmap(fx, viz::Colormap::kBlueWhiteRed, -band, band), lo.x(), hi.x(), lo.y(),
               hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kBlueWhiteRed, -band, band, "DT_x (m)")
        .title("DT_x");
    fig.axes(0, 1)
        .image(viz::heatmap(fy, viz::Colormap::kBlueWhiteRed, -band, band), lo.x(), hi.x(), lo.y(),
               hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kBlueWhiteRed, -band, band, "DT_y (m)")
        .title("DT_y");
    fig.axes(0, 2)
        .image(viz::heatmap(fs, viz::Colormap::kViridis, 0.0, shi), lo.x(), hi.x(), lo.y(), hi.y())
        .equal_aspect()
        .colorbar(viz::Colormap::kViridis, 0.0, shi, "sigma (m)")
        .title("sqrt(trace cov DT_v)");
    fig.save_png(prefix + "_fields.png");
  }
  {
    viz::Figure fig(1400, 1100, 1, 1);
    std::vector<double> ox, oy, tx, ty;
    for (const auto& p : map.observed_points()) {
      ox.push_back(p.x());
      oy.push_back(p.y());
    }
    const std::size_t step = std::max<std::size_t>(1, truth.size() / 20000);
    for (std::size_t k = 0; k < truth.size(); k += step) {
      tx.push_back(truth[k].x());
      ty.push_back(truth[k].y());
    }
    fig.axes(0, 0)
        .title(title + ": zero contour of the fitted VDT (Fig. 5.5)")
        .scatter(ox, oy,
                 viz::Style()
                     .with_color({0, 114, 178})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_alpha(0.35)
                     .with_label("observations (given poses)"))
        .scatter(tx, ty,
                 viz::Style()
                     .with_color({0, 0, 0})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_label("true boundary"))
        .scatter(zx, zy,
                 viz::Style()
                     .with_color({213, 94, 0})
                     .with_marker(viz::Marker::kCircle, 1)
                     .with_label("fitted DT_v = 0"))
        .xlim(lo.x(), hi.x())
        .ylim(lo.y(), hi.y())
        .equal_aspect()
        .legend(viz::LegendLocation::kUpperRight);
    fig.save_png(prefix + "_zero_contour.png");
  }
}

void plot_boundary_errors(const BoundaryErrors& e, const std::string& path,
                          const std::string& title) {
  std::vector<double> lo(e.sigma.size()), hi(e.sigma.size());
  for (std::size_t k = 0; k < e.sigma.size(); ++k) {
    lo[k] = -2.0 * e.sigma[k];
    hi[k] = 2.0 * e.sigma[k];
  }
  viz::Figure fig(1600, 600, 1, 1);
  fig.axes(0, 0)
      .title(title)
      .xlabel("true boundary point")
      .ylabel("fitted DT_v along the normal (m)")
      .band(e.index, lo, hi, viz::Style().with_label("+-2 sigma"))
      .line(e.index, e.error, viz::Style().with_width(1.0).with_label("error"))
      .legend(viz::LegendLocation::kUpperRight);
  fig.save_png(path);
}

/// Experiment 2's scene: the Willow Garage map's upper corridor, or the generated floor plan's
/// main corridor.
sim::MappingScene corridor(const std::string& data, std::uint32_t seed) {
  if (!data.empty()) {
    const std::string pgm = data + "/ros-maps/willow-garage/willow-full.pgm";
    if (std::filesystem::exists(pgm)) {
      // 540 x 587 px for 54.0 m x 58.7 m (the Stage world): 0.1 m/px. The corridor along
      // y ~ 48 m from x ~ 11 m to 36 m, cropped with its walls and the rooms' doorways.
      const OccupancyGrid<2> full = load_occupancy_image(pgm, Vector2d(54.0, 58.7), 0.1);
      const Eigen::Vector2i lo(80, 420), hi(380, 530);
      OccupancyGrid<2> crop(hi - lo,
                            GridFrame<2>(0.1, full.frame().cell_center(lo) - Vector2d(0.05, 0.05)));
      for (int y = 0; y < crop.size().y(); ++y) {
        for (int x = 0; x < crop.size().x(); ++x) {
          crop(Eigen::Vector2i(x, y)) = full(lo + Eigen::Vector2i(x, y));
        }
      }
      std::vector<Vector2d> path = sim::plan_tour(crop, 2, 0.5, seed);
      return sim::scene_along("Willow Garage corridor", std::move(crop), std::move(path));
    }
    std::printf("[exp2] %s not found: using the generated floor plan\n", pgm.c_str());
  }
  return sim::generated_corridor(seed);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Uncertain VDT maps (thesis ch. 5): Experiments 1 and 2, Figs. 5.2-5.6, "
      "localization on the fitted map, and the Intel lab with --data"};
  std::string out = "out/uncertain_map", data;
  unsigned seed = 1;
  int runs = 3;
  double noise_scale = 1.0;
  study::IntelSettings intel;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--seed", seed, "seed of the noise (and of the generated plan)")
      ->capture_default_str();
  app.add_option("--runs", runs, "noisy map-building runs per experiment (errors pooled)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--noise-scale", noise_scale,
                 "factor on Tables 5.1 and 5.2's pose and range noise (0: exact poses and ranges)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--data", data,
                 "real data folder (e.g. ../shared/data): the Willow Garage map for Experiment 2 "
                 "and the Intel lab study; without it, the generated floor plan only");
  app.add_option("--intel-pose-sigma", intel.pose_sigma,
                 "Intel: stated sigma of the corrected poses' x and y, metres")
      ->capture_default_str();
  app.add_option("--intel-heading-sigma", intel.heading_sigma,
                 "Intel: stated sigma of the corrected poses' heading, radians")
      ->capture_default_str();
  app.add_option("--intel-spacing", intel.spacing, "Intel: control point spacing, metres")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    std::filesystem::create_directories(out);
    std::vector<Row> rows;

    // ------------------------------------------------------------ Fig. 5.2
    const sim::MappingScene room = sim::l_shaped_room(0.01);
    {
      std::printf("[fig5.2] least-squares B-spline approximation of the true VDT of the %s\n",
                  room.name.c_str());
      const VdtMap2 truth = VdtMap2::build(room.world);
      std::vector<Vector2d> boundary;
      for (int y = 0; y < room.world.size().y(); ++y) {
        for (int x = 0; x < room.world.size().x(); ++x) {
          if (room.world(Eigen::Vector2i(x, y))) {
            boundary.push_back(room.world.cell_center(Eigen::Vector2i(x, y)));
          }
        }
      }
      const auto vdt = [&](const Vector2d& p) -> Vector2d {
        return p - truth.nearest_occupied_point(p);
      };
      std::vector<double> hs = {0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5}, rms, mx;
      for (double h : hs) {
        mapping::UncertainMapOptions o;
        o.spacing = h;
        o.band = 1.0;
        const auto map = mapping::UncertainVdtMap::approximate(boundary, vdt, o);
        double ss = 0.0, m = 0.0;
        int n = 0;
        for (const auto& p : boundary) {
          const auto s = map.evaluate(p);
          if (!s.inside) continue;
          ss += s.value.squaredNorm();
          m = std::max(m, s.value.norm());
          ++n;
        }
        Row r;
        r.experiment = "approximation";
        r.spacing = h;
        r.control_points = map.summary().control_points;
        r.samples = map.summary().eikonal_samples;
        r.rms = std::sqrt(ss / std::max(1, n));
        r.max = m;
        r.fit_s = map.summary().fit_seconds;
        rows.push_back(r);
        rms.push_back(r.rms);
        mx.push_back(r.max);
        std::printf(
            "  h = %.2f m: %5d control points, |DT_v| at the true boundary rms %.4f m, "
            "max %.4f m\n",
            h, r.control_points, r.rms, r.max);
      }
      viz::Figure fig(1200, 700, 1, 1);
      fig.axes(0, 0)
          .title("Fig. 5.2: least-squares B-spline approximation of the true VDT (L-shaped room)")
          .xlabel("control point spacing (m)")
          .ylabel("|DT_v| at the true boundary (m)")
          .line(hs, rms, viz::Style().with_marker(viz::Marker::kCircle).with_label("rms"))
          .line(hs, mx, viz::Style().with_marker(viz::Marker::kSquare).with_label("max"))
          .legend(viz::LegendLocation::kUpperLeft);
      fig.save_png(out + "/fig5_2_approximation.png");
    }

    // ------------------------------------------------------------ Experiments 1 and 2
    const auto experiment = [&](const std::string& name, const sim::MappingScene& scene,
                                const sim::LidarOptions& lidar, const sim::MappingNoise& noise,
                                double spacing, std::unique_ptr<mapping::UncertainVdtMap>* keep,
                                sim::MappingRun* keep_run) {
      Row row;
      row.experiment = name;
      row.spacing = spacing;
      BoundaryErrors pooled;
      for (int r = 0; r < runs; ++r) {
        const sim::MappingNoise scaled{noise_scale * noise.sigma_xy, noise_scale * noise.sigma_phi,
                                       noise_scale * noise.sigma_range};
        const sim::MappingRun run = sim::simulate_mapping_run(
            scene.world, scene.poses, lidar, scaled, seed * 1000u + static_cast<unsigned>(r));
        mapping::UncertainMapOptions o;
        o.spacing = spacing;
        auto map =
            std::make_unique<mapping::UncertainVdtMap>(mapping::UncertainVdtMap::fit(run.scans, o));
        const auto& s = map->summary();
        const BoundaryErrors e = boundary_errors(*map, run.true_boundary, 4000);
        std::printf(
            "  [%s run %d/%d] %zu scans, %d control points, %d boundary points, %d "
            "Eikonal samples (%d on cut loci), %d scan poses: fit %.2f s (%d iterations%s), "
            "covariance %.2f s%s; true boundary rms %.4f m, max %.4f m, within 2 sigma "
            "%.1f %%\n",
            name.c_str(), r + 1, runs, run.scans.size(), s.control_points, s.boundary_points,
            s.eikonal_samples, s.cut_locus_samples, s.scan_poses, s.fit_seconds, s.iterations,
            s.converged ? "" : ", NOT converged", s.covariance_seconds,
            s.covariance_ok ? "" : " (FAILED)", e.rms(), e.max_abs, e.within_pct());
        std::fflush(stdout);
        if (r == 0) {
          row.control_points = s.control_points;
          row.samples = s.eikonal_samples;
          plot_map(*map, run.true_boundary, out + "/" + name, name + " (" + scene.name + ")");
          plot_boundary_errors(e, out + "/" + name + "_boundary_error.png",
                               name + ": error of the fitted VDT at the true boundary (Fig. 5.6)");
          if (keep != nullptr) *keep = std::move(map);
          if (keep_run != nullptr) *keep_run = run;
        }
        row.fit_s += s.fit_seconds / runs;
        row.cov_s += s.covariance_seconds / runs;
        pooled.add(e);
      }
      row.rms = pooled.rms();
      row.max = pooled.max_abs;
      row.within = pooled.within_pct();
      rows.push_back(row);
    };

    {
      std::printf("[experiment1] %s, 3 poses, 180 deg LiDAR, Table 5.1 noise, h = 0.2 m, %d runs\n",
                  room.name.c_str(), runs);
      sim::LidarOptions lidar;
      lidar.fov = kPi;
      lidar.angular_resolution = 0.5 * kPi / 180.0;
      lidar.range_max = 10.0;
      experiment("experiment1", room, lidar, sim::MappingNoise::table_5_1(), 0.2, nullptr, nullptr);
    }

    const sim::MappingScene c2 = corridor(data, seed);
    const std::vector<sim::TimedPose> drive = sim::mapping_drive(c2);
    sim::LidarOptions lidar2;  // 270 degrees at 0.25 degrees
    lidar2.range_max = 10.0;
    std::unique_ptr<mapping::UncertainVdtMap> map2;
    sim::MappingRun run2;
    std::printf(
        "[experiment2] %s: %zu key scans over %.1f s, 270 deg LiDAR (0.25 deg, 10 m), "
        "Table 5.2 noise, h = 0.25 m, %d runs\n",
        c2.name.c_str(), c2.poses.size(), drive.back().t, runs);
    experiment("experiment2", c2, lidar2, sim::MappingNoise::table_5_2(), 0.25, &map2, &run2);

    // ------------------------------------------------------------ localization on map 2
    const std::vector<study::LocalizationRow> loc =
        study::localize_on_fitted_map(*map2, c2.world, drive, lidar2, seed, out);

    // ------------------------------------------------------------ tables
    {
      std::ofstream csv(out + "/table.csv");
      csv << "experiment,spacing_m,control_points,samples,rms_error_m,max_error_m,"
             "within_2sigma_pct,fit_s,cov_s\n";
      std::ofstream md(out + "/table.md");
      md << "| experiment | spacing (m) | control points | samples | RMS error (m) | max error "
            "(m) | within 2 sigma (%) | fit (s) | covariance (s) |\n"
            "|---|---|---|---|---|---|---|---|---|\n";
      for (const Row& r : rows) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%.3f,%d,%d,%.5f,%.5f,%.2f,%.3f,%.3f\n",
                      r.experiment.c_str(), r.spacing, r.control_points, r.samples, r.rms, r.max,
                      r.within, r.fit_s, r.cov_s);
        csv << line;
        std::snprintf(line, sizeof line,
                      "| %s | %.3f | %d | %d | %.4f | %.4f | %.1f | %.2f | %.2f |\n",
                      r.experiment.c_str(), r.spacing, r.control_points, r.samples, r.rms, r.max,
                      r.within, r.fit_s, r.cov_s);
        md << line;
      }
      std::ofstream lcsv(out + "/localization.csv");
      lcsv << "map_model,pos_rmse_m,ori_rmse_rad,anees,anees_lo,anees_hi,anees_left_out\n";
      md << "\nLocalization on the Experiment 2 map (" << c2.name
         << "):\n\n| map model | position RMSE (m) | orientation RMSE (rad) | ANEES [95 %] |\n"
            "|---|---|---|---|\n";
      for (const auto& r : loc) {
        char line[512];
        std::snprintf(line, sizeof line, "%s,%.5f,%.6f,%.3f,%.3f,%.3f,%zu\n", r.map_model.c_str(),
                      r.pos_rmse, r.ori_rmse, r.anees, r.anees_lo, r.anees_hi, r.anees_left_out);
        lcsv << line;
        std::snprintf(line, sizeof line, "| %s | %.4f | %.5f | %.2f [%.2f, %.2f]%s |\n",
                      r.map_model.c_str(), r.pos_rmse, r.ori_rmse, r.anees, r.anees_lo, r.anees_hi,
                      r.anees_note.empty() ? "" : (" (" + r.anees_note + ")").c_str());
        md << line;
      }
    }
    if (!data.empty() && std::filesystem::exists(data + "/intel-lab/intel.relations")) {
      study::intel_uncertain_map(data, out, intel);
    }
    std::printf("[done] %s/table.csv, %s/localization.csv\n", out.c_str(), out.c_str());
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
