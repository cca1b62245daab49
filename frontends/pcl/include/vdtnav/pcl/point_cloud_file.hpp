#pragma once
/// \file
/// \brief Point cloud files as pcl::PointCloud<pcl::PointXYZ>: the formats 3D LiDAR users have.

#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace vdtnav {

/// \brief Reads a point cloud file; the format follows the extension (case-insensitive):
/// - `.pcd`: ASCII, binary or binary_compressed, float32 or float64 fields x, y, z (others
///   ignored); the VIEWPOINT's position becomes the cloud's `sensor_origin_`;
/// - `.ply`: vertices with x, y, z (faces ignored);
/// - `.vtk`: legacy ASCII VTK, the POINTS section of any DATASET (libpointmatcher's files);
/// - `.csv`, `.txt`, `.xyz`: one point a line, fields separated by commas, semicolons or blanks;
///   x, y, z are the first three fields, or the columns named x, y, z by a header line
///   ("x,y,z,nx,ny,nz"); blank lines and lines starting with '#' are skipped.
/// Organized clouds come as one row per image row. Points with a NaN or infinite coordinate are
/// kept (observations_from_cloud() drops and counts them).
/// \throws IoError when the file cannot be opened or read.
/// \throws FormatError (`file:line: what was expected`) when the extension is unknown, the file
///         cannot be parsed, it has no x, y, z coordinates or no point.
[[nodiscard]] pcl::PointCloud<pcl::PointXYZ> read_point_cloud(const std::string& path);

/// \brief The per-point times a cloud file holds: a field (PCD, PLY) or a header-named column
/// (text) among core/point_time_fields.hpp's, read as it says.
struct PointTimes {
  std::vector<double> seconds;  ///< one per point, in the cloud's order; empty: no time field
  std::string field;            ///< the field read ("": none)
  bool absolute = false;  ///< seconds since an epoch (subtract the scan's stamp), else after it
};

/// \brief read_point_cloud() that also reads each point's time into `times` (if not null).
/// \throws as read_point_cloud(), and FormatError when the time field's type is unknown.
[[nodiscard]] pcl::PointCloud<pcl::PointXYZ> read_point_cloud(const std::string& path,
                                                              PointTimes* times);

}  // namespace vdtnav
