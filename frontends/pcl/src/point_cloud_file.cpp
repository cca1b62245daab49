#include "vdtnav/pcl/point_cloud_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "raw_cloud.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/point_field.hpp"
#include "vdtnav/core/point_time_fields.hpp"

namespace vdtnav {

namespace {

void read_times(const pcl::PCLPointCloud2& c, const std::string& path, PointTimes& out) {
  out = PointTimes{};
  for (const PointTimeField& tf : kPointTimeFields) {
    const auto it = std::find_if(c.fields.begin(), c.fields.end(),
                                 [&](const pcl::PCLPointField& f) { return f.name == tf.name; });
    if (it == c.fields.end()) continue;
    if (point_field::size_of(it->datatype) == 0 ||
        it->offset + point_field::size_of(it->datatype) > c.point_step) {
      throw FormatError(path, 0,
                        std::string("time field '") + tf.name + "' has PCL datatype " +
                            std::to_string(static_cast<int>(it->datatype)) +
                            " or lies outside the point; expected a number");
    }
    const bool integer =
        it->datatype != pcl::PCLPointField::FLOAT32 && it->datatype != pcl::PCLPointField::FLOAT64;
    out.field = tf.name;
    out.absolute = tf.absolute;
    out.seconds.reserve(static_cast<std::size_t>(c.width) * c.height);
    for (std::size_t row = 0; row < c.height; ++row)
      for (std::size_t col = 0; col < c.width; ++col) {
        const std::uint8_t* p = c.data.data() + row * c.row_step + col * c.point_step + it->offset;
        out.seconds.push_back(
            point_time_seconds(point_field::value(p, it->datatype), integer, tf.absolute));
      }
    return;
  }
}

}  // namespace

pcl::PointCloud<pcl::PointXYZ> read_point_cloud(const std::string& path) {
  return read_point_cloud(path, nullptr);
}

pcl::PointCloud<pcl::PointXYZ> read_point_cloud(const std::string& path, PointTimes* times) {
  const detail::RawCloud raw = detail::read_raw_cloud(path);
  if (times != nullptr) read_times(raw.cloud, path, *times);
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
