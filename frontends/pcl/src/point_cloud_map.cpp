#include "vdtnav/pcl/point_cloud_map.hpp"

#include "raw_cloud.hpp"
#include "voxelize_points.hpp"

namespace vdtnav {

PointCloudOccupancy load_point_cloud_occupancy(const std::string& path,
                                               const PointCloudOccupancyOptions& options) {
  const detail::PointSource source{path, true};
  detail::check_options(options, source);  // before touching the file
  const detail::RawCloud raw = detail::read_raw_cloud(path);
  const detail::PointAccessor point_at(raw.cloud, path);
  return detail::voxelize_points(point_at.size(), point_at, options, source);
}

VdtMap3 load_point_cloud_map(const std::string& path, const PointCloudOccupancyOptions& options) {
  return VdtMap3::build(load_point_cloud_occupancy(path, options).occupancy);
}

SparseVdtMap3 load_point_cloud_sparse_map(const std::string& path,
                                          const PointCloudOccupancyOptions& options,
                                          const SparseVdtMapOptions& map_options) {
  const detail::PointSource source{path, true};
  detail::check_options(options, source);  // before touching the file
  const detail::RawCloud raw = detail::read_raw_cloud(path);
  const detail::PointAccessor point_at(raw.cloud, path);
  const detail::CloudLattice l =
      detail::cloud_lattice(point_at.size(), point_at, options, source, 1e12);
  return SparseVdtMap3::build(
      detail::occupied_voxels(point_at.size(), point_at, l, options.thin_surfaces), l.frame, l.size,
      map_options);
}

}  // namespace vdtnav
