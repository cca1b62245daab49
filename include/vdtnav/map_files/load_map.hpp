#pragma once
/// \file
/// \brief One loader for every map file vdtnav reads, 2D and 3D, by the extension: what the CLI,
/// the Python module and the ROS node load a map with (issue 58).
///
///  - 2D: a map_server map (.yaml, .yml), an uncertain map file (`vdtnav map --uncertain`,
///    thesis ch. 5: its occupancy rendering and the fitted field sampled at its resolution), a
///    saved 2D VDT map (.vdt, its occupancy the cells that are their own nearest occupied cell);
///  - 3D: a saved VDT map (.vdt dense, .svdt sparse and memory-mapped), an OctoMap (.bt, .ot;
///    with vdtnav::octomap) or a point cloud (.pcd, .ply, .vtk, .txt; with vdtnav::pcl), the last
///    two voxelized into a dense map, or a sparse one (bricks near the surfaces, no dense grid:
///    building-sized maps) with `sparse`.
/// A format whose front end this vdtnav was built without is refused with the package to install.

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/mapping/uncertain_map_file.hpp"

namespace vdtnav {

/// \brief A box in the map's frame, metres: only cloud points inside it are voxelized.
struct CropBox {
  Eigen::Vector3d min, max;
};

/// \brief How a map file becomes a VDT map (the 3D sources' settings; a 2D file has none).
struct MapLoadOptions {
  /// Voxel edge, metres; 0: the default of the source (clouds 0.1 m; an octree its own leaf
  /// size; a saved map is used as saved and refuses another).
  double resolution = 0.0;
  double margin = 1.0;          ///< free border around a cloud's or an octree's occupied space, m
  std::optional<CropBox> crop;  ///< clouds only: the points kept
  bool sparse = false;          ///< clouds and octrees: build a SparseVdtMap3
  /// Clouds only: thin walls to their surfaces (PointCloudOccupancyOptions::thin_surfaces).
  bool thin_surfaces = true;
  /// Where the loader says what it does (the grid's size and memory first: a dense 3D grid grows
  /// with the box, see `crop`); empty: silent. The CLI prints the lines on stderr.
  std::function<void(const std::string&)> say;
};

/// \brief A loaded map: 2D (vdt set) or 3D (dense or sparse set).
struct LoadedMap {
  int dimension = 2;
  std::string source;    ///< "ros map", "uncertain map file", "octree, sparse", ...
  double seconds = 0.0;  ///< time to read and build it
  // 2D
  RosMap ros;  ///< the map_server map; for other 2D files their occupancy as ROS cell values
  OccupancyGrid<2> occupancy;
  std::unique_ptr<VdtMap2> vdt;
  /// An uncertain map file's map; null otherwise.
  std::shared_ptr<const mapping::UncertainMapFile> uncertain;
  // 3D
  std::unique_ptr<VdtMap3> dense;
  std::unique_ptr<SparseVdtMap3> sparse;

  /// \return the 3D map, dense or sparse (dimension 3 only).
  [[nodiscard]] const VdtField3& field3() const {
    return dense ? static_cast<const VdtField3&>(*dense) : *sparse;
  }
  /// \return the bytes of the VDT map held.
  [[nodiscard]] std::size_t memory_bytes() const;
};

/// \brief An option of MapLoadOptions out of its domain, or one the file's format does not take
/// (the CLI reports it as bad usage, exit 2).
class MapOptionError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

/// \brief Parses "xmin,ymin,zmin,xmax,ymax,zmax". \throws MapOptionError naming `what`.
[[nodiscard]] CropBox parse_crop_box(const std::string& text, const std::string& what);

/// \brief Loads (and builds) the VDT map of `path` (see the file comment).
/// \param dimension 2 or 3: the dimension expected (a file of the other is refused, naming it);
/// 0: either.
/// \throws vdtnav::Error (file, what was expected) for a bad file, MapOptionError for a bad
/// option, ConfigError for a format this build cannot read.
[[nodiscard]] LoadedMap load_map(const std::string& path, const MapLoadOptions& options = {},
                                 int dimension = 0);

/// \brief A mapping run to build a map from (`vdtnav map3d --scans DIR --poses FILE`): the
/// clouds of `dir` in name order, each moved into the map frame by its pose in `poses` (KITTI or
/// TUM, io/scan_run.hpp) composed with `lidar_pose`.
struct MapScanRun {
  std::string dir, poses;
  ScanSelection selection;        ///< which clouds (--every, --skip-odd, --skip-even)
  double stamp_tolerance = 0.01;  ///< TUM: seconds between a cloud's name and its pose's stamp
  /// The clouds' frame in the frame whose poses the file gives (e.g. KITTI's camera poses and a
  /// Velodyne's clouds: the camera-from-Velodyne calibration).
  Pose3 lidar_pose = Pose3::Identity();
};

/// \brief Builds the 3D map of a mapping run: the selected clouds merged in the map frame
/// (RegisteredScans, cells of a quarter voxel), then voxelized as a map cloud file is
/// (`options`: resolution, margin, crop in the map frame, thinning, sparse). Needs vdtnav::pcl.
/// \throws vdtnav::Error (file, what was expected) for a bad folder, pose file, cloud or option;
/// ConfigError when this vdtnav was built without vdtnav::pcl.
[[nodiscard]] LoadedMap build_map_from_scans(const MapScanRun& run, const MapLoadOptions& options);

}  // namespace vdtnav
