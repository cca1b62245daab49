// The five localizers of the Table 3.3 study run side by side on one simulated run: vdt-opt,
// vdt-ekf, udt-opt, udt-ekf and the particle filter, each from the true start.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "turtlebot_study.hpp"
#include "vdtnav/estimation/particle_filter.hpp"
#include "vdtnav/estimation/udt_localizers.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"

namespace turtlebot_study {

using namespace vdtnav;

namespace {

using Clock = std::chrono::steady_clock;

void progress(const std::string& what, std::size_t done, std::size_t total) {
  const int width = 30, filled = static_cast<int>(width * done / std::max<std::size_t>(total, 1));
  std::printf("\r  %-8s [%s%s] %3zu%%", what.c_str(), std::string(filled, '#').c_str(),
              std::string(width - filled, '.').c_str(),
              100 * done / std::max<std::size_t>(total, 1));
  std::fflush(stdout);
}

}  // namespace

std::vector<Trace> run_localizers(const VdtMap2& vdt, const OccupancyGrid<2>& occ,
                                  const sim::NoiseProfile& noise,
                                  const std::vector<std::string>& methods,
                                  const sim::SimulatedRun& run, std::uint32_t run_seed,
                                  std::vector<std::vector<Metrics>>& per_method) {
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
  std::vector<std::unique_ptr<Localizer2D>> locs;
  VdtEkfOptions eo;
  eo.noise.sigma_v = noise.sigma_v;
  eo.noise.sigma_w = noise.sigma_w;
  UdtOptions uo;
  uo.noise = eo.noise;
  ParticleFilterOptions po;
  po.seed = run_seed;
  locs.push_back(std::make_unique<VdtOptimizationLocalizer>(vdt, VdtOptimizerOptions{}));
  locs.push_back(std::make_unique<VdtEkfLocalizer>(vdt, eo));
  locs.push_back(std::make_unique<UdtOptimizationLocalizer>(occ, uo));
  locs.push_back(std::make_unique<UdtEkfLocalizer>(occ, uo));
  locs.push_back(std::make_unique<ParticleFilterLocalizer>(occ, po));
  std::vector<Trace> traces(methods.size());
  for (std::size_t m = 0; m < locs.size(); ++m) {
    Trace& t = traces[m];
    locs[m]->reset(run.truth[0], p0);
    t.estimate.assign(1, run.truth[0]);
    t.covariance.assign(1, p0);
    t.has_cov.assign(1, 1);
    for (std::size_t k = 1; k < run.size(); ++k) {
      const auto t0 = Clock::now();
      const LocalizationResult res = locs[m]->update(run.odometry[k], run.scans[k]);
      t.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      t.estimate.push_back(res.pose);
      t.covariance.push_back(res.covariance);
      t.has_cov.push_back(res.has_covariance ? 1 : 0);
      if (k % 50 == 0 || k + 1 == run.size()) progress(methods[m], k + 1, run.size());
    }
    std::printf("\n");
    per_method[m].push_back(evaluate(t, run));
  }
  return traces;
}

}  // namespace turtlebot_study
