#pragma once
/// \file
/// \brief Occupancy grids and VDT maps from an in-memory pcl::PointCloud<pcl::PointXYZ>.

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "vdtnav/pcl/point_cloud_map.hpp"

namespace vdtnav {

/// \brief Voxelizes a cloud in place (no copy of its points), by the rule of PointCloudOccupancy.
/// Points with a NaN or infinite coordinate are dropped and counted in `num_dropped`.
/// \throws ConfigError when an option is out of its domain, the cloud is empty or has no finite
///         point, or the grid would have 2^31 voxels or more.
[[nodiscard]] PointCloudOccupancy occupancy_from_point_cloud(
    const pcl::PointCloud<pcl::PointXYZ>& cloud, const PointCloudOccupancyOptions& options);

/// \brief occupancy_from_point_cloud() followed by VdtMap3::build().
/// \throws ConfigError as occupancy_from_point_cloud(), and when an axis of the grid has fewer
///         than 2 voxels.
[[nodiscard]] VdtMap3 vdt_map_from_point_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                               const PointCloudOccupancyOptions& options);

/// \brief load_point_cloud_sparse_map() for a cloud in memory.
[[nodiscard]] SparseVdtMap3 sparse_vdt_map_from_point_cloud(
    const pcl::PointCloud<pcl::PointXYZ>& cloud, const PointCloudOccupancyOptions& options,
    const SparseVdtMapOptions& map_options = {});

}  // namespace vdtnav
