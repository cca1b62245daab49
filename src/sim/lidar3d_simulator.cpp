#include "vdtnav/sim/lidar3d_simulator.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "vdtnav/core/error.hpp"

namespace vdtnav::sim {

int Lidar3dSpec::rays_per_ring() const {
  return static_cast<int>(std::lround(2.0 * 3.14159265358979323846 / azimuth_step));
}

namespace {

/// One turn; the rays of azimuth column j leave from pose_of(j) (world frame).
template <typename PoseOf>
Lidar3dScan cast_turn(const OccupancyGrid<3>& map, const PoseOf& pose_of, const Lidar3dSpec& spec,
                      std::mt19937& rng) {
  std::ostringstream bad;
  if (spec.rings < 1)
    bad << "rings must be >= 1, got " << spec.rings;
  else if (!(spec.max_elevation >= spec.min_elevation && std::abs(spec.min_elevation) < 1.6 &&
             std::abs(spec.max_elevation) < 1.6))
    bad << "elevations must satisfy -pi/2 < min <= max < pi/2";
  else if (!(spec.azimuth_step > 1e-4 && spec.azimuth_step <= 3.15))
    bad << "azimuth_step must be in (1e-4, pi] rad, got " << spec.azimuth_step;
  else if (!(spec.sigma_range >= 0.0 && std::isfinite(spec.sigma_range)))
    bad << "sigma_range must be finite and >= 0";
  else if (!(spec.range_min >= 0.0 && spec.range_max > spec.range_min))
    bad << "ranges must satisfy 0 <= range_min < range_max";
  if (!bad.str().empty()) throw ConfigError("simulate_lidar3d_scan: " + bad.str());

  const int n = spec.rays_per_ring();
  Lidar3dScan scan;
  scan.points.reserve(static_cast<std::size_t>(spec.rings) * static_cast<std::size_t>(n));
  std::normal_distribution<double> noise(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < spec.rings; ++k) {
    const double e =
        spec.rings == 1
            ? spec.min_elevation
            : spec.min_elevation + (spec.max_elevation - spec.min_elevation) * k / (spec.rings - 1);
    for (int j = 0; j < n; ++j) {
      const Pose3 sensor = pose_of(j);
      const double a = j * spec.azimuth_step;
      const Eigen::Vector3d u(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const double exact =
          cast_ray<3>(map, sensor.translation(), sensor.linear() * u, spec.range_max, spec.surface);
      const double range = exact + spec.sigma_range * noise(rng);  // the draw in every case
      if (!std::isfinite(exact) || range < spec.range_min || range >= spec.range_max) {
        scan.points.emplace_back(nan, nan, nan);
        continue;
      }
      scan.points.push_back(range * u);
      ++scan.returns;
    }
  }
  return scan;
}

}  // namespace

Lidar3dScan simulate_lidar3d_scan(const OccupancyGrid<3>& map, const Pose3& sensor_in_world,
                                  const Lidar3dSpec& spec, std::mt19937& rng) {
  return cast_turn(
      map, [&](int) { return sensor_in_world; }, spec, rng);
}

Lidar3dScan simulate_lidar3d_sweep(const OccupancyGrid<3>& map, const Pose3& sensor_at_stamp,
                                   const SweepMotion& motion, const Lidar3dSpec& spec,
                                   std::mt19937& rng) {
  VDTNAV_CHECK(std::isfinite(spec.rate_hz) && spec.rate_hz > 0.0,
               "simulate_lidar3d_sweep: rate_hz must be > 0");
  const double column_dt = 1.0 / (spec.rays_per_ring() * spec.rate_hz);
  Lidar3dScan scan = cast_turn(
      map, [&](int j) { return sensor_at_stamp * motion.at(j * column_dt); }, spec, rng);
  const int n = spec.rays_per_ring();
  scan.times.resize(scan.points.size());
  for (std::size_t k = 0; k < scan.points.size(); ++k)
    scan.times[k] = static_cast<double>(k % static_cast<std::size_t>(n)) * column_dt;
  return scan;
}

ObservationSet3 lidar3d_observations(const Lidar3dScan& scan, const Lidar3dSpec& spec) {
  ObservationSet3 obs;
  obs.sigma_range = spec.sigma_range;
  obs.range_max = spec.range_max;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!scan.points[i].allFinite()) {
      ++obs.dropped_out_of_range;  // no return within the sensor's range
      continue;
    }
    const double r = scan.points[i].norm();
    obs.add(Eigen::Vector3d::Zero(), scan.points[i] / r, r, i);
    if (!scan.times.empty()) obs.times.push_back(scan.times[i]);
  }
  return obs;
}

}  // namespace vdtnav::sim
