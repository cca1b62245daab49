#include "vdtnav/pcl/point_laser_cloud.hpp"

#include "vdtnav/pcl/point_cloud_file.hpp"

namespace vdtnav::point_laser {

ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                        const Pose3& sensor_in_robot, const PointLaserSpec& spec) {
  CloudObservationOptions options;
  options.sensor_in_robot = sensor_in_robot;
  options.sigma_range = spec.sigma_range;
  options.range_min = spec.range_min;
  options.range_max = spec.range_max;
  return vdtnav::observations_from_cloud(cloud, options);
}

ObservationSet3 read_point_laser_pcd(const std::string& path, const Pose3& sensor_in_robot,
                                     const PointLaserSpec& spec) {
  return observations_from_cloud(read_point_cloud(path), sensor_in_robot, spec);
}

}  // namespace vdtnav::point_laser
