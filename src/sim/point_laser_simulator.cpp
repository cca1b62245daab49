#include "vdtnav/sim/point_laser_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "vdtnav/core/error.hpp"

namespace vdtnav::sim {
namespace {

void check(const PointLaserSimOptions& o) {
  const PointLaserSpec& s = o.spec;
  VDTNAV_CHECK(s.range_min >= 0.0 && s.range_max > s.range_min && std::isfinite(s.range_max),
               "point laser simulator: ranges must satisfy 0 <= range_min < range_max < inf");
  VDTNAV_CHECK(std::isfinite(s.sigma_range) && s.sigma_range >= 0.0,
               "point laser simulator: sigma_range must be finite and >= 0");
  VDTNAV_CHECK(std::isfinite(o.reading_period) && o.reading_period >= 0.0,
               "point laser simulator: reading_period must be finite and >= 0");
  const PanTiltCalibration& c = o.calibration;
  VDTNAV_CHECK(
      c.mount.matrix().allFinite() && c.pan_to_tilt.allFinite() && c.tilt_to_laser.allFinite(),
      "point laser simulator: the calibration must be finite");
}

}  // namespace

std::size_t PanTiltPattern::size() const {
  if (!angles.empty()) return angles.size();
  return static_cast<std::size_t>(std::max(0, pan_steps)) *
         static_cast<std::size_t>(std::max(0, tilt_steps));
}

std::vector<Eigen::Vector2d> PanTiltPattern::pan_tilt_angles() const {
  if (!angles.empty()) {
    for (std::size_t k = 0; k < angles.size(); ++k)
      VDTNAV_CHECK(angles[k].allFinite(),
                   "pan-tilt pattern: angle pair " + std::to_string(k) + " is not finite");
    return angles;
  }
  VDTNAV_CHECK(pan_steps >= 1 && tilt_steps >= 1, "pan-tilt pattern: steps must be >= 1");
  VDTNAV_CHECK(std::isfinite(pan_min) && std::isfinite(pan_max) && pan_max >= pan_min &&
                   std::isfinite(tilt_min) && std::isfinite(tilt_max) && tilt_max >= tilt_min,
               "pan-tilt pattern: need finite pan_min <= pan_max and tilt_min <= tilt_max");
  std::vector<Eigen::Vector2d> out;
  out.reserve(size());
  const double pan_step = (pan_max - pan_min) / pan_steps;
  const double tilt_step = tilt_steps > 1 ? (tilt_max - tilt_min) / (tilt_steps - 1) : 0.0;
  for (int i = 0; i < pan_steps; ++i)
    for (int j = 0; j < tilt_steps; ++j)
      out.emplace_back(pan_min + i * pan_step, tilt_min + j * tilt_step);
  return out;
}

PointLaserSweep simulate_point_laser_sweep(const OccupancyGrid<3>& map, const Pose3& robot_pose,
                                           const PointLaserSimOptions& options,
                                           std::uint32_t seed) {
  check(options);
  VDTNAV_CHECK(robot_pose.matrix().allFinite(), "point laser simulator: the pose is not finite");
  const std::vector<Eigen::Vector2d> angles = options.pattern.pan_tilt_angles();
  std::seed_seq seq{seed, 0x50544c52u};  // "PTLR"
  std::mt19937_64 rng(seq);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double sigma = options.noisy ? options.spec.sigma_range : 0.0;

  PointLaserSweep sweep;
  sweep.truth = robot_pose;
  sweep.sigma_range = options.spec.sigma_range;
  sweep.readings.reserve(angles.size());
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const double pan = angles[k].x(), tilt = angles[k].y();
    const Pose3 laser = robot_pose * pan_tilt_laser_pose(options.calibration, pan, tilt);
    const Eigen::Vector3d dir = laser.linear().col(0);
    const double exact =
        cast_ray<3>(map, laser.translation(), dir, options.spec.range_max, options.surface);
    const double z = normal(rng);  // drawn for every reading: same draws noisy or not
    PanTiltReading reading;
    reading.pan = pan;
    reading.tilt = tilt;
    reading.range = exact < options.spec.range_max ? std::max(0.0, exact + sigma * z) : kInf;
    reading.time = static_cast<double>(k) * options.reading_period;
    sweep.readings.push_back(reading);
  }
  return sweep;
}

std::vector<PointLaserSweep> simulate_point_laser_sweeps(const OccupancyGrid<3>& map,
                                                         const std::vector<Pose3>& robot_poses,
                                                         const PointLaserSimOptions& options,
                                                         std::uint32_t seed) {
  std::vector<PointLaserSweep> sweeps;
  sweeps.reserve(robot_poses.size());
  std::seed_seq seq{seed, 0x53574550u};  // "SWEP": one derived seed per location
  std::vector<std::uint32_t> seeds(robot_poses.size());
  seq.generate(seeds.begin(), seeds.end());
  for (std::size_t k = 0; k < robot_poses.size(); ++k)
    sweeps.push_back(simulate_point_laser_sweep(map, robot_poses[k], options, seeds[k]));
  return sweeps;
}

}  // namespace vdtnav::sim
