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

SparseVdtMap3 sparse_vdt_map_from_point_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                              const PointCloudOccupancyOptions& options,
                                              const SparseVdtMapOptions& map_options) {
  const auto point_at = [&](std::size_t k) {
    const pcl::PointXYZ& p = cloud.points[k];
    return Eigen::Vector3d(p.x, p.y, p.z);
  };
  const detail::PointSource source{"sparse_vdt_map_from_point_cloud", false};
  const detail::CloudLattice l =
      detail::cloud_lattice(cloud.size(), point_at, options, source, 1e12);
  return SparseVdtMap3::build(
      detail::occupied_voxels(cloud.size(), point_at, l, options.thin_surfaces), l.frame, l.size,
      map_options);
}

}  // namespace vdtnav
