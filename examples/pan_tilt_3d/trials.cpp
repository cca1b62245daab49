// vdtnav_pan_tilt_3d: the localization trials, every scenario x downsampling factor at every
// location x range-noise seed, on a pool of threads (pan_tilt_study.hpp).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "pan_tilt_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"

namespace pan_tilt_study {
namespace {

/// \return the initial guess of scenario s: Table 3.4's offsets added to x, y, z and to the ZYX
/// roll, pitch, yaw of the truth. In the 4-DOF mode roll and pitch are the true (IMU) ones.
Pose3 initial_guess(const Pose3& truth, const Scenario& s, bool four_dof) {
  const Eigen::Vector3d t = truth.translation() + Eigen::Vector3d::Constant(s.dt);
  Eigen::Vector3d rpy = rpy_of(truth.linear());
  rpy[2] += s.dr;
  if (!four_dof) {
    rpy[0] += s.dr;
    rpy[1] += s.dr;
  }
  return pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0], rpy[1], rpy[2]);
}

/// \return the observation set of every k-th reading of the sweep (k = 1: all of them), readings
/// without a return included in the count, as the thesis downsamples the recorded sweep.
ObservationSet3 every_kth_reading(const sim::PointLaserSweep& sweep,
                                  const sim::PointLaserSimOptions& sim, int k) {
  std::vector<PanTiltReading> kept;
  kept.reserve(sweep.readings.size() / static_cast<std::size_t>(k) + 1);
  for (std::size_t i = 0; i < sweep.readings.size(); i += static_cast<std::size_t>(k))
    kept.push_back(sweep.readings[i]);
  ObservationSet3 set = point_laser_observations(kept, sim.calibration, sim.spec);
  for (std::size_t& b : set.beam) b *= static_cast<std::size_t>(k);  // index in the whole sweep
  return set;
}

}  // namespace

TrialRuns run_trials(const World& world, const VdtOptimizer3& optimizer,
                     const sim::PointLaserSimOptions& sim_options,
                     const MultiStartOptions& multi_start, unsigned seed, int seeds, bool four_dof,
                     bool verbose, int threads) {
  const std::size_t n_loc = world.locations.size();
  const std::size_t n_seeds = static_cast<std::size_t>(seeds);
  const std::size_t n_jobs = n_loc * n_seeds;
  const std::size_t per_job = kScenarios.size() * kFactors.size();
  // trials[job][scenario * factors + factor], job = location * seeds + seed
  std::vector<std::vector<Trial>> trials(n_jobs, std::vector<Trial>(per_job));
  std::vector<std::size_t> sweep_returns(n_jobs, 0);
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::string failure;
  std::mutex failure_mutex;
  const auto work = [&] {
    for (std::size_t job = next++; job < n_jobs && !failed; job = next++) {
      try {
        const std::size_t loc = job / n_seeds, s = job % n_seeds;
        std::seed_seq seq{seed, static_cast<unsigned>(loc), static_cast<unsigned>(s)};
        std::uint32_t noise_seed = 0;
        seq.generate(&noise_seed, &noise_seed + 1);
        const Pose3& truth = world.locations[loc];
        const sim::PointLaserSweep sweep =
            sim::simulate_point_laser_sweep(world.occupancy, truth, sim_options, noise_seed);
        for (std::size_t f = 0; f < kFactors.size(); ++f) {
          const ObservationSet3 obs = every_kth_reading(sweep, sim_options, kFactors[f]);
          if (f == 0) sweep_returns[job] = obs.size();
          for (std::size_t c = 0; c < kScenarios.size(); ++c) {
            const Pose3 guess = initial_guess(truth, kScenarios[c], four_dof);
            const auto t0 = Clock::now();
            const LocalizationResult3 r = solve_multi_start(optimizer, obs, guess, multi_start);
            Trial& t = trials[job][c * kFactors.size() + f];
            t.ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            t.status = r.status;
            t.position_error = (r.pose.translation() - truth.translation()).norm();
            t.attitude_error = attitude_error(r.pose, truth);
            t.observations = static_cast<int>(obs.size());
            t.inliers = r.inliers;
            t.final_cost = r.final_cost;
            if (verbose) {
              const MultiStartOptions& m = multi_start;
              t.tvcd_estimate = truncated_vcd(optimizer.sensor_model(), obs, r.pose, m.truncation);
              t.tvcd_truth = truncated_vcd(optimizer.sensor_model(), obs, truth, m.truncation);
            }
          }
        }
      } catch (const std::exception& e) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failed) failure = e.what();
        failed = true;
      }
      ++done;
    }
  };
  std::fprintf(stderr,
               "[trials] %zu locations x %d seeds x %zu scenarios x %zu factors = %zu solves "
               "(%s, %d threads)\n",
               n_loc, seeds, kScenarios.size(), kFactors.size(), n_jobs * per_job,
               four_dof ? "4-DOF" : "6-DOF", threads);
  const auto t_trials = Clock::now();
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(work);
  for (std::size_t shown = 0; shown < n_jobs && !failed;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const std::size_t d = done.load();
    if (d == shown && d < n_jobs) continue;
    shown = d;
    const double el = std::chrono::duration<double>(Clock::now() - t_trials).count();
    std::fprintf(stderr, "\r  sweeps %zu/%zu  solves %zu/%zu  %.1f s (eta %.0f s)   ", d, n_jobs,
                 d * per_job, n_jobs * per_job, el,
                 d ? el * static_cast<double>(n_jobs - d) / static_cast<double>(d) : 0.0);
  }
  for (auto& t : pool) t.join();
  std::fprintf(stderr, "\n");
  if (failed) throw Error(failure);
  const double trials_s = std::chrono::duration<double>(Clock::now() - t_trials).count();
  return {std::move(trials), std::move(sweep_returns), trials_s};
}

}  // namespace pan_tilt_study
