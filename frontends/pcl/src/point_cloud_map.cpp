#include "vdtnav/pcl/point_cloud_map.hpp"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>

#include "voxelize_points.hpp"

namespace vdtnav {
namespace {

std::string lower_extension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

/// Opens and reads the first byte, so that a missing, unreadable or directory path is an IoError
/// with errno's reason rather than a parser complaint.
void check_readable(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open point cloud: " + std::strerror(errno));
  in.peek();
  if (in.bad()) throw IoError(path + ": cannot read point cloud: " + std::strerror(errno));
}

/// The raw cloud as PCL reads it: every field, in the file's own types.
pcl::PCLPointCloud2 read_cloud(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply") {
    throw FormatError(path, 0,
                      "unknown point cloud format '" + ext + "'; expected a .pcd or .ply file");
  }
  check_readable(path);
  pcl::PCLPointCloud2 cloud;
  int rc = 0;
  try {
    if (ext == ".pcd") {
      pcl::PCDReader reader;
      // PCL 1.13's PCDReader::read dereferences an empty field list when the header has no
      // fields or no points (a garbage or empty file: segfault, PCL issue #5854), so the header is
      // checked first and such files never reach read().
      Eigen::Vector4f origin;
      Eigen::Quaternionf orientation;
      int version = 0, data_type = 0;
      unsigned int data_index = 0;
      rc = reader.readHeader(path, cloud, origin, orientation, version, data_type, data_index);
      if (rc < 0) {
        throw FormatError(path, 0,
                          "not a valid PCD file (no PCD header: PCL's reader failed with code " +
                              std::to_string(rc) + ")");
      }
      if (cloud.fields.empty())
        throw FormatError(path, 0, "not a valid PCD file: its header declares no FIELDS");
      if (static_cast<std::size_t>(cloud.width) * cloud.height == 0) {
        throw FormatError(path, 0, "the cloud has no points");
      }
      cloud = pcl::PCLPointCloud2();
      rc = reader.read(path, cloud);
    } else {
      pcl::PLYReader reader;
      rc = reader.read(path, cloud);
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // PCL throws pcl::IOException on some malformed files
    throw FormatError(
        path, 0,
        std::string("not a valid ") + (ext == ".pcd" ? "PCD" : "PLY") + " file: " + e.what());
  }
  if (rc < 0) {
    throw FormatError(path, 0,
                      std::string("not a valid ") + (ext == ".pcd" ? "PCD" : "PLY") +
                          " file (PCL's reader failed with code " + std::to_string(rc) + ")");
  }
  return cloud;
}

/// Reads coordinate `name` of the points from the raw bytes (float32 or float64).
class Coordinate {
 public:
  Coordinate(const pcl::PCLPointCloud2& cloud, const char* name, const std::string& path) {
    const auto it = std::find_if(cloud.fields.begin(), cloud.fields.end(),
                                 [&](const pcl::PCLPointField& f) { return f.name == name; });
    if (it == cloud.fields.end()) {
      throw FormatError(
          path, 0,
          std::string("the cloud has no '") + name + "' field; expected x, y, z coordinates");
    }
    offset_ = it->offset;
    if (it->datatype == pcl::PCLPointField::FLOAT32) {
      is_double_ = false;
    } else if (it->datatype == pcl::PCLPointField::FLOAT64) {
      is_double_ = true;
    } else {
      throw FormatError(path, 0,
                        std::string("field '") + name + "' has PCL datatype " +
                            std::to_string(static_cast<int>(it->datatype)) +
                            "; expected float32 or float64 coordinates");
    }
    if (offset_ + (is_double_ ? sizeof(double) : sizeof(float)) > cloud.point_step) {
      throw FormatError(path, 0, std::string("field '") + name + "' lies outside the point");
    }
  }

  [[nodiscard]] double operator()(const std::uint8_t* point) const {
    if (is_double_) {
      double v;
      std::memcpy(&v, point + offset_, sizeof v);
      return v;
    }
    float v;
    std::memcpy(&v, point + offset_, sizeof v);
    return static_cast<double>(v);
  }

 private:
  std::size_t offset_ = 0;
  bool is_double_ = false;
};

}  // namespace

PointCloudOccupancy load_point_cloud_occupancy(const std::string& path,
                                               const PointCloudOccupancyOptions& options) {
  const detail::PointSource source{path, true};
  detail::check_options(options, source);  // before touching the file
  const pcl::PCLPointCloud2 cloud = read_cloud(path);
  const Coordinate x(cloud, "x", path), y(cloud, "y", path), z(cloud, "z", path);
  const std::size_t width = cloud.width, height = cloud.height;
  const std::size_t point_step = cloud.point_step, row_step = cloud.row_step;
  if (width * height > 0 &&
      (row_step < width * point_step || cloud.data.size() < height * row_step)) {
    throw FormatError(path, 0, "the cloud's data is shorter than width x height points");
  }
  // Organized clouds (height > 1) are read row by row: point (r, c) at r row_step + c point_step.
  const std::uint8_t* data = cloud.data.data();
  const auto point_at = [&](std::size_t k) {
    const std::uint8_t* p = data + (k / width) * row_step + (k % width) * point_step;
    return Eigen::Vector3d(x(p), y(p), z(p));
  };
  return detail::voxelize_points(width * height, point_at, options, source);
}

VdtMap3 load_point_cloud_map(const std::string& path, const PointCloudOccupancyOptions& options) {
  return VdtMap3::build(load_point_cloud_occupancy(path, options).occupancy);
}

}  // namespace vdtnav
