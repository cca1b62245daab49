// vdtnav_active_beam: the localization of a drive with one reading per step, the beam pointed by
// one strategy (active_beam_study.hpp).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "active_beam_study.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace active_beam_study {

Run localize(const Dataset& ds, const VdtMap2& map, BeamStrategy strategy,
             const std::vector<OdometryStep>& odo, std::uint32_t seed) {
  Run run;
  run.strategy = strategy;
  VdtEkfOptions eo;
  eo.min_inliers = 1;                  // one reading per step
  eo.search.enabled = false;           // no window search on one reading
  eo.sensor.map_sigma = ds.map_sigma;  // the map's measured roughness (surface_roughness.hpp)
  const ActiveBeamSelector selector(map, ds.beam, eo.sensor);
  RotatingBeamController beam(ds.beam, strategy);
  VdtEkfLocalizer ekf(map, eo);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
  ekf.reset(ds.drive.front().pose, p0);
  std::mt19937_64 rng(seed);  // the same range noise for every strategy
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<double> nees;
  double se_x = 0, se_y = 0, se_phi = 0, select_ms = 0;
  int lost = 0;
  Eigen::Matrix3d last_cov = p0;
  for (std::size_t k = 0; k < ds.drive.size(); ++k) {
    if (k > 0) beam.advance(odo[k].dt);
    const Pose2& truth = ds.drive[k].pose;
    const double theta = beam.bearing();
    const double eps = n01(rng);
    ScanPoints pts;
    pts.sigma_range = ds.beam.sigma_range;
    pts.range_max = ds.beam.range_max;
    const Vector2d u(std::cos(truth[2] + theta), std::sin(truth[2] + theta));
    const double r0 = sim::cast_ray<2>(ds.world, truth.head<2>(), u, ds.beam.range_max,
                                       sim::RaySurface::kCellCentre);
    const auto step_start = Clock::now();
    bool gated = false;
    if (k > 0 && std::isfinite(r0) && r0 >= ds.beam.range_min) {
      // Data association as ActiveBeamLocalizer does it: against the ray cast from the prediction.
      gated = !selector.consistent(compose(run.estimate.back(), odo[k].delta), last_cov, theta,
                                   r0 + ds.beam.sigma_range * eps);
      run.gated += gated ? 1 : 0;
    }
    if (!gated && std::isfinite(r0) && r0 >= ds.beam.range_min) {
      pts.add(Vector2d::Zero(), Vector2d(std::cos(theta), std::sin(theta)),
              r0 + ds.beam.sigma_range * eps, 0);
    }
    const LocalizationResult res = ekf.update(odo[k], pts);
    double step_ms = std::chrono::duration<double, std::milli>(Clock::now() - step_start).count();
    last_cov = res.covariance;
    const Eigen::Vector3d e = pose_error(res.pose, truth);
    se_x += e[0] * e[0];
    se_y += e[1] * e[1];
    se_phi += e[2] * e[2];
    if (e.head<2>().norm() > 0.5) ++lost;
    nees.push_back(eval::nees(res.pose, truth, res.covariance));
    run.t.push_back(ds.drive[k].t);
    run.ex.push_back(e[0]);
    run.ey.push_back(e[1]);
    run.ephi.push_back(e[2]);
    run.sx.push_back(std::sqrt(res.covariance(0, 0)));
    run.sy.push_back(std::sqrt(res.covariance(1, 1)));
    run.sphi.push_back(std::sqrt(res.covariance(2, 2)));
    run.bearing.push_back(theta);
    run.estimate.push_back(res.pose);
    if (beam.needs_goal()) {
      const auto t0 = Clock::now();
      const BeamSelection s =
          selector.select(res.pose, res.covariance, selector.segment_of(theta), strategy);
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      select_ms += ms;
      step_ms += ms;
      ++run.selections;
      beam.set_goal(s.segment, selector);
    }
    run.goal.push_back(beam.goal());
    run.step_ms.push_back(step_ms);
  }
  const double n = static_cast<double>(ds.drive.size());
  run.rmse_x = std::sqrt(se_x / n);
  run.rmse_y = std::sqrt(se_y / n);
  run.rmse_phi = std::sqrt(se_phi / n);
  run.lost_pct = 100.0 * lost / n;
  run.anees = eval::anees(nees, 3);
  run.ms_select = run.selections > 0 ? select_ms / run.selections : 0.0;
  return run;
}

}  // namespace active_beam_study
