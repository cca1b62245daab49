#include "vdtnav/pcl/cloud_observations.hpp"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

void check(const CloudObservationOptions& o) {
  std::ostringstream s;
  if (!(std::isfinite(o.sigma_range) && o.sigma_range >= 0.0))
    s << "sigma_range must be finite and >= 0, got " << o.sigma_range;
  else if (!(std::isfinite(o.range_min) && o.range_min >= 0.0))
    s << "range_min must be finite and >= 0, got " << o.range_min;
  else if (!(o.range_max > o.range_min))
    s << "range_max must be > range_min (" << o.range_min << "), got " << o.range_max;
  else if (!(std::isfinite(o.voxel) && o.voxel >= 0.0))
    s << "voxel must be finite and >= 0, got " << o.voxel;
  else if (!o.sensor_in_robot.matrix().allFinite())
    s << "sensor_in_robot must be finite";
  if (!s.str().empty()) throw ConfigError("observations_from_cloud: " + s.str());
}

/// Index of the cube of edge `voxel` holding q: three 21-bit signed cube coordinates packed in one
/// key (+-1e6 cubes per axis: +-100 km at 0.1 m; farther points share the edge cubes).
std::uint64_t cube_key(const Eigen::Vector3d& q, double inv_voxel) {
  std::uint64_t key = 0;
  for (int c = 0; c < 3; ++c) {
    const double i = std::floor(q[c] * inv_voxel);
    const double clamped = std::min(std::max(i, -1048576.0), 1048575.0);
    key = (key << 21) |
          (static_cast<std::uint64_t>(static_cast<std::int64_t>(clamped) + 1048576) & 0x1FFFFFu);
  }
  return key;
}

}  // namespace

ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                        const CloudObservationOptions& options) {
  return observations_from_cloud(cloud, options, {});
}

ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                        const CloudObservationOptions& options,
                                        const std::vector<double>& times) {
  check(options);
  VDTNAV_CHECK(times.empty() || times.size() == cloud.size(),
               "observations_from_cloud: " + std::to_string(times.size()) + " times for " +
                   std::to_string(cloud.size()) + " points");
  ObservationSet3 out;
  out.sigma_range = options.sigma_range;
  out.range_max = options.range_max;
  const Eigen::Vector3d origin = cloud.sensor_origin_.head<3>().cast<double>();

  // The valid readings, in cloud order.
  std::vector<std::size_t> valid;
  valid.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d q = cloud[i].getVector3fMap().cast<double>();
    if (!q.allFinite() || (!times.empty() && !std::isfinite(times[i]))) {
      ++out.dropped_not_finite;
      continue;
    }
    const double range = (q - origin).norm();
    if (!(range >= options.range_min && range < options.range_max) || range == 0.0) {
      ++out.dropped_out_of_range;
      continue;
    }
    valid.push_back(i);
  }

  if (options.voxel > 0.0) {  // one reading per cube: the one nearest the cube's centroid
    struct Cube {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      int count = 0;
      std::size_t best = 0;
      double best_d2 = std::numeric_limits<double>::infinity();
    };
    const double inv = 1.0 / options.voxel;
    std::unordered_map<std::uint64_t, std::size_t> slot;
    slot.reserve(valid.size());
    std::vector<Cube> cubes;
    std::vector<std::size_t> cube_of(valid.size());
    for (std::size_t k = 0; k < valid.size(); ++k) {
      const Eigen::Vector3d q = cloud[valid[k]].getVector3fMap().cast<double>();
      const auto [it, added] = slot.emplace(cube_key(q, inv), cubes.size());
      if (added) cubes.emplace_back();
      cube_of[k] = it->second;
      cubes[it->second].sum += q;
      ++cubes[it->second].count;
    }
    for (std::size_t k = 0; k < valid.size(); ++k) {
      Cube& c = cubes[cube_of[k]];
      const Eigen::Vector3d q = cloud[valid[k]].getVector3fMap().cast<double>();
      const double d2 = (q - c.sum / c.count).squaredNorm();
      if (d2 < c.best_d2) {
        c.best_d2 = d2;
        c.best = valid[k];
      }
    }
    valid.clear();
    for (const Cube& c : cubes) valid.push_back(c.best);
  }

  const Eigen::Matrix3d& rotation = options.sensor_in_robot.linear();
  out.points.reserve(valid.size());
  out.directions.reserve(valid.size());
  out.ranges.reserve(valid.size());
  out.beam.reserve(valid.size());
  for (std::size_t i : valid) {
    const Eigen::Vector3d q = cloud[i].getVector3fMap().cast<double>();
    const Eigen::Vector3d ray = q - origin;
    const double range = ray.norm();
    out.points.push_back(options.sensor_in_robot * q);
    out.directions.push_back(rotation * (ray / range));
    out.ranges.push_back(range);
    out.beam.push_back(i);
    if (!times.empty()) out.times.push_back(times[i]);
  }
  return out;
}

pcl::PointCloud<pcl::PointXYZ> to_cloud(const ObservationSet3& observations) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(observations.size());
  for (const Eigen::Vector3d& p : observations.points)
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  return cloud;
}

}  // namespace vdtnav
