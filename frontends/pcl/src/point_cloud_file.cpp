#include "vdtnav/pcl/point_cloud_file.hpp"

#include "raw_cloud.hpp"

namespace vdtnav {

pcl::PointCloud<pcl::PointXYZ> read_point_cloud(const std::string& path) {
  const detail::RawCloud raw = detail::read_raw_cloud(path);
  const detail::PointAccessor point_at(raw.cloud, path);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize(point_at.size());
  bool dense = true;
  for (std::size_t k = 0; k < point_at.size(); ++k) {
    const Eigen::Vector3f p = point_at(k).cast<float>();
    cloud[k] = pcl::PointXYZ(p.x(), p.y(), p.z());
    dense = dense && p.allFinite();
  }
  if (raw.cloud.height > 1) {  // keep the organization
    cloud.width = raw.cloud.width;
    cloud.height = raw.cloud.height;
  }
  cloud.is_dense = dense;
  cloud.sensor_origin_.head<3>() = raw.origin.cast<float>();
  cloud.sensor_origin_.w() = 0.0F;
  return cloud;
}

}  // namespace vdtnav
