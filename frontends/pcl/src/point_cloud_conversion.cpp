#include "vdtnav/pcl/point_cloud_conversion.hpp"

#include "voxelize_points.hpp"

namespace vdtnav {

PointCloudOccupancy occupancy_from_point_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                               const PointCloudOccupancyOptions& options) {
  const auto point_at = [&](std::size_t k) {
    const pcl::PointXYZ& p = cloud.points[k];
    return Eigen::Vector3d(p.x, p.y, p.z);
  };
  return detail::voxelize_points(cloud.size(), point_at, options,
                                 detail::PointSource{"occupancy_from_point_cloud", false});
}

VdtMap3 vdt_map_from_point_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                 const PointCloudOccupancyOptions& options) {
  return VdtMap3::build(occupancy_from_point_cloud(cloud, options).occupancy);
}

}  // namespace vdtnav
