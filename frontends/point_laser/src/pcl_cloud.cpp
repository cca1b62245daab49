#include "vdtnav/point_laser/pcl_cloud.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/io/pcd_io.h>

#include "vdtnav/core/error.hpp"

namespace vdtnav::point_laser {

PointLaserObservations observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                               const Pose3& sensor_in_robot,
                                               const PointLaserSpec& spec) {
  PointLaserObservations out;
  out.sigma_range = spec.sigma_range;
  const Eigen::Vector3d origin = cloud.sensor_origin_.head<3>().cast<double>();
  const Eigen::Matrix3d& rotation = sensor_in_robot.linear();
  out.points.reserve(cloud.size());
  out.d_point_d_range.reserve(cloud.size());
  out.ranges.reserve(cloud.size());
  out.reading.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const pcl::PointXYZ& p = cloud[i];
    const Eigen::Vector3d q(p.x, p.y, p.z);
    if (!q.allFinite()) {
      ++out.dropped_not_finite;
      continue;
    }
    const Eigen::Vector3d ray = q - origin;
    const double range = ray.norm();
    if (!(range >= spec.range_min && range < spec.range_max) || range == 0.0) {
      ++out.dropped_out_of_range;
      continue;
    }
    out.points.push_back(sensor_in_robot * q);
    out.d_point_d_range.push_back(rotation * (ray / range));
    out.ranges.push_back(range);
    out.reading.push_back(i);
  }
  return out;
}

PointLaserObservations read_point_laser_pcd(const std::string& path, const Pose3& sensor_in_robot,
                                            const PointLaserSpec& spec) {
  if (!std::ifstream(path)) throw IoError(path + ": cannot open PCD file: " + std::strerror(errno));
  // Check the header first: PCL 1.13's reader crashes on a file whose header declares no fields.
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 header;
  constexpr const char* kExpected = "expected a PCD point cloud with x, y and z fields";
  if (reader.readHeader(path, header) < 0) throw FormatError(path, 0, kExpected);
  for (const char* field : {"x", "y", "z"})
    if (pcl::getFieldIndex(header, field) < 0)
      throw FormatError(path, 0, std::string(kExpected) + ", field '" + field + "' is missing");
  pcl::PointCloud<pcl::PointXYZ> cloud;
  if (reader.read(path, cloud) < 0) throw FormatError(path, 0, kExpected);
  return observations_from_cloud(cloud, sensor_in_robot, spec);
}

pcl::PointCloud<pcl::PointXYZ> to_cloud(const PointLaserObservations& observations) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.reserve(observations.size());
  for (const Eigen::Vector3d& p : observations.points)
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  return cloud;
}

}  // namespace vdtnav::point_laser
