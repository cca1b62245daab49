#pragma once
/// \file
/// \brief The map cloud of a mapping run: scans moved into the map frame by their poses and
/// merged, one point per small cell (the centroid of the points that fell in it), so the cloud
/// grows with the area of the surfaces seen, not with the number of scans. `vdtnav map3d --scans`
/// voxelizes it as it does a map cloud file.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief Accumulates registered scans (see the file comment).
class RegisteredScans {
 public:
  /// \param cell edge of the merging cells, metres (finite, > 0); a quarter of the map's voxel
  ///        keeps the spread of the points inside a voxel, which the thinning of walls reads
  ///        (PointCloudOccupancyOptions::thin_surfaces). Cells are counted from the map frame's
  ///        origin; a point more than 2^20 cells from it is refused.
  /// \throws ConfigError for a bad cell size.
  explicit RegisteredScans(double cell);

  /// \brief Adds a scan whose frame has pose `pose` in the map frame (a map point is
  /// pose * p). Points with a NaN or infinite coordinate are dropped and counted.
  /// \throws ConfigError when a point lands beyond the cell index range (saying where: a pose or
  ///         a cloud not in metres).
  void add(const pcl::PointCloud<pcl::PointXYZ>& scan, const Pose3& pose);

  /// \return one point per occupied cell, the centroid of its points, in cell order.
  [[nodiscard]] pcl::PointCloud<pcl::PointXYZ> cloud() const;

  [[nodiscard]] std::size_t scans() const noexcept { return scans_; }
  [[nodiscard]] std::size_t points_added() const noexcept { return added_; }
  [[nodiscard]] std::size_t points_dropped() const noexcept { return dropped_; }
  [[nodiscard]] std::size_t cells() const noexcept { return cells_.size(); }

 private:
  struct Sum {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double n = 0.0;
  };
  double cell_;
  std::unordered_map<std::uint64_t, Sum> cells_;
  std::size_t scans_ = 0, added_ = 0, dropped_ = 0;
};

/// \brief The map cloud of a mapping run's files: each read (read_point_cloud(), any format it
/// takes) and added at its pose, `poses[k]` for `files[k]`; `on_scan(k, merged)` after each one
/// when set (progress).
/// \throws what read_point_cloud() and RegisteredScans throw, ConfigError when the counts differ
///         or no finite point was read.
[[nodiscard]] pcl::PointCloud<pcl::PointXYZ> merge_scan_files(
    const std::vector<std::string>& files, const std::vector<Pose3>& poses, double cell,
    const std::function<void(std::size_t, const RegisteredScans&)>& on_scan = {});

}  // namespace vdtnav
