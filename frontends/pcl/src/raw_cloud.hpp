#pragma once
// Internal to vdtnav::pcl: every point cloud file format as one raw PCL cloud (the fields in the
// file's own types), and the reader of one float32/float64 coordinate of its points. Shared by
// the voxelization of files (point_cloud_map.cpp) and read_point_cloud (point_cloud_file.cpp).

#include <cstddef>
#include <cstdint>
#include <string>

#include <pcl/PCLPointCloud2.h>

#include <Eigen/Core>
#include "vdtnav/core/file_extension.hpp"

namespace vdtnav::detail {

/// A cloud as a file holds it, with the sensor's position in the cloud's frame (a PCD file's
/// VIEWPOINT; zero for the other formats).
struct RawCloud {
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};

/// Reads .pcd, .ply, text (.csv, .txt, .xyz) or legacy ASCII VTK (.vtk) by the extension; text and
/// VTK points come as float64 fields x, y, z.
/// \throws IoError (cannot open/read), FormatError (file[:line]: what was expected).
[[nodiscard]] RawCloud read_raw_cloud(const std::string& path);

/// Reads coordinate `name` of the points from the raw bytes (float32 or float64).
class Coordinate {
 public:
  /// \throws FormatError when the cloud lacks the field or it is not float32/float64.
  Coordinate(const pcl::PCLPointCloud2& cloud, const char* name, const std::string& path);
  [[nodiscard]] double operator()(const std::uint8_t* point) const;

 private:
  std::size_t offset_ = 0;
  bool is_double_ = false;
};

/// The points of a raw cloud by index (organized clouds row by row), as Eigen::Vector3d (possibly
/// non-finite).
class PointAccessor {
 public:
  /// \throws FormatError when the cloud lacks x, y, z or its data is shorter than its header says.
  PointAccessor(const pcl::PCLPointCloud2& cloud, const std::string& path);
  [[nodiscard]] std::size_t size() const noexcept { return width_ * height_; }
  [[nodiscard]] Eigen::Vector3d operator()(std::size_t k) const {
    const std::uint8_t* p = data_ + (k / width_) * row_step_ + (k % width_) * point_step_;
    return {x_(p), y_(p), z_(p)};
  }

 private:
  Coordinate x_, y_, z_;
  const std::uint8_t* data_;
  std::size_t width_, height_, point_step_, row_step_;
};

}  // namespace vdtnav::detail
