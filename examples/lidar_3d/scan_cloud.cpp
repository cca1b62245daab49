// The simulated scans as the point clouds a driver writes, and the voxel edge that thins them to
// about --points readings.
#include <cmath>
#include <cstdint>

#include "lidar_3d_study.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"

namespace lidar3d {

using namespace vdtnav;

pcl::PointCloud<pcl::PointXYZ> to_pcl(const sim::Lidar3dScan& scan, int rings) {
  pcl::PointCloud<pcl::PointXYZ> c;
  c.reserve(scan.points.size());
  for (const Eigen::Vector3d& p : scan.points)
    c.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                              static_cast<float>(p.z())));
  c.width = static_cast<std::uint32_t>(scan.points.size() / static_cast<std::size_t>(rings));
  c.height = static_cast<std::uint32_t>(rings);  // organized, as a driver writes it
  c.is_dense = false;
  return c;
}

double voxel_for(const pcl::PointCloud<pcl::PointXYZ>& cloud, std::size_t target) {
  CloudObservationOptions o;
  double lo = 0.01, hi = 5.0;
  for (int it = 0; it < 30; ++it) {
    o.voxel = std::sqrt(lo * hi);
    (observations_from_cloud(cloud, o).size() > target ? lo : hi) = o.voxel;
  }
  return std::sqrt(lo * hi);
}

}  // namespace lidar3d
