// Experiments 1 and 2: the uncertain map fitted to noisy map-building runs, its errors at the true
// boundary pooled over the runs; Experiment 2's corridor.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "uncertain_map_study.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/sim/route_planner.hpp"

namespace study {

using namespace vdtnav;
using Eigen::Vector2d;

void fit_experiment(const std::string& name, const sim::MappingScene& scene,
                    const sim::LidarOptions& lidar, const sim::MappingNoise& noise, double spacing,
                    std::unique_ptr<mapping::UncertainVdtMap>* keep, sim::MappingRun* keep_run,
                    int runs, double noise_scale, unsigned seed, const std::string& out,
                    std::vector<Row>& rows) {
  Row row;
  row.experiment = name;
  row.spacing = spacing;
  BoundaryErrors pooled;
  for (int r = 0; r < runs; ++r) {
    const sim::MappingNoise scaled{noise_scale * noise.sigma_xy, noise_scale * noise.sigma_phi,
                                   noise_scale * noise.sigma_range};
    const sim::MappingRun run = sim::simulate_mapping_run(scene.world, scene.poses, lidar, scaled,
                                                          seed * 1000u + static_cast<unsigned>(r));
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
}

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

}  // namespace study
