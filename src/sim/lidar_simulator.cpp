#include "vdtnav/sim/lidar_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <string>
#include <utility>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {

int LidarOptions::num_beams() const {
  // The small slack makes 270 deg / 0.25 deg count 1080 intervals despite rounding.
  return static_cast<int>(std::floor(fov / angular_resolution + 1e-9)) + 1;
}

NoiseProfile NoiseProfile::table_3_2_variance() {
  return {std::sqrt(0.02), std::sqrt(0.05), std::sqrt(0.01)};
}

SimulatedRun simulate_run(const OccupancyGrid<2>& map, const std::vector<TimedPose>& trajectory,
                          const LidarOptions& lidar, const NoiseProfile& noise,
                          std::uint32_t seed) {
  constexpr double kTwoPi = 2.0 * 3.14159265358979323846;
  VDTNAV_CHECK(std::isfinite(lidar.fov) && lidar.fov > 0.0 && lidar.fov <= kTwoPi,
               "simulate_run: lidar fov must be in (0, 2 pi]");
  VDTNAV_CHECK(std::isfinite(lidar.angular_resolution) && lidar.angular_resolution > 0.0,
               "simulate_run: lidar angular_resolution must be > 0");
  VDTNAV_CHECK(
      lidar.range_min >= 0.0 && lidar.range_max > lidar.range_min && std::isfinite(lidar.range_max),
      "simulate_run: lidar ranges must satisfy 0 <= range_min < range_max < inf");
  VDTNAV_CHECK(lidar.mount.allFinite(), "simulate_run: lidar mount must be finite");
  for (double s : {lidar.sigma_range, noise.sigma_range, noise.sigma_v, noise.sigma_w})
    VDTNAV_CHECK(std::isfinite(s) && s >= 0.0, "simulate_run: noise sigmas must be >= 0");
  VDTNAV_CHECK(!trajectory.empty(), "simulate_run: the trajectory is empty");

  const int beams = lidar.num_beams();
  const double angle_min = -0.5 * lidar.fov;
  // Beam directions in the sensor frame, rotated per scan (no trigonometry per beam).
  std::vector<Eigen::Vector2d> beam_dir(static_cast<std::size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double a = angle_min + i * lidar.angular_resolution;
    beam_dir[i] = {std::cos(a), std::sin(a)};
  }

  // Separate streams: the odometry noise does not depend on the number of beams.
  std::seed_seq range_seq{seed, 0x52414e47u}, odometry_seq{seed, 0x4f444f4du};
  std::mt19937_64 range_rng(range_seq), odometry_rng(odometry_seq);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr double kInf = std::numeric_limits<double>::infinity();

  SimulatedRun run;
  const std::size_t n = trajectory.size();
  run.times.reserve(n);
  run.truth.reserve(n);
  run.odometry.reserve(n);
  run.scans.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const TimedPose& s = trajectory[k];
    VDTNAV_CHECK(s.pose.allFinite() && std::isfinite(s.t) && std::isfinite(s.v) &&
                     std::isfinite(s.w) && (k == 0 || s.t >= trajectory[k - 1].t),
                 "simulate_run: trajectory sample " + std::to_string(k) +
                     " is not finite or goes back in time");
    run.times.push_back(s.t);
    run.truth.push_back(s.pose);

    OdometryStep odo;
    if (k > 0) {
      odo.dt = s.t - trajectory[k - 1].t;
      odo.v = s.v + noise.sigma_v * normal(odometry_rng);
      odo.w = s.w + noise.sigma_w * normal(odometry_rng);
      odo.delta = unicycle_increment(odo.v, odo.w, odo.dt);
    }
    run.odometry.push_back(odo);

    LaserScan scan;
    scan.time = s.t;
    scan.angle_min = angle_min;
    scan.angle_increment = lidar.angular_resolution;
    scan.range_min = lidar.range_min;
    scan.range_max = lidar.range_max;
    scan.mount = lidar.mount;
    scan.sigma_range = noise.sigma_range > 0.0 ? noise.sigma_range : lidar.sigma_range;
    scan.ranges.resize(static_cast<std::size_t>(beams));
    const Pose2 sensor = compose(s.pose, lidar.mount);
    const double c = std::cos(sensor[2]), sn = std::sin(sensor[2]);
    const Eigen::Vector2d origin = sensor.head<2>();
    for (int i = 0; i < beams; ++i) {
      const Eigen::Vector2d d(c * beam_dir[i].x() - sn * beam_dir[i].y(),
                              sn * beam_dir[i].x() + c * beam_dir[i].y());
      const double exact = cast_ray<2>(map, origin, d, lidar.range_max, lidar.surface);
      const double z = normal(range_rng);  // drawn for every beam: same draws for every profile
      scan.ranges[i] =
          exact < lidar.range_max ? std::max(0.0, exact + noise.sigma_range * z) : kInf;
    }
    run.scans.push_back(std::move(scan));
  }
  return run;
}

SimulatedRun simulate_default_run(const OccupancyGrid<2>& map,
                                  const std::vector<Eigen::Vector2d>& path, int min_scans,
                                  std::uint32_t seed) {
  TrajectoryOptions options;
  options.min_steps = min_scans;
  return simulate_run(map, follow_path(path, map, options), LidarOptions{},
                      NoiseProfile::table_3_2_sigma(), seed);
}

}  // namespace vdtnav::sim
