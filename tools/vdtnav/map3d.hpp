#pragma once
/// \file
/// \brief The 3D maps `vdtnav localize3d` and `vdtnav map3d` read: a point cloud (PCD, PLY, VTK,
/// text), an OctoMap (.bt, .ot) or a saved VDT map (.vdt dense, .svdt sparse), by the extension;
/// clouds and octrees become dense maps, or sparse ones (bricks near the surfaces, no dense grid:
/// building-sized maps) with `sparse`.

#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav::tools {

/// \brief A box in the map's frame, metres: only cloud points inside it are voxelized.
struct CropBox {
  Eigen::Vector3d min, max;
};

/// \brief Parses "xmin,ymin,zmin,xmax,ymax,zmax". \throws ConfigError naming `what`.
[[nodiscard]] CropBox parse_crop(const std::string& text, const std::string& what);

/// \brief How a 3D map file becomes a VDT map.
struct Map3dOptions {
  /// Voxel edge, metres; 0: the default of the source (clouds 0.1 m; an octree its own leaf
  /// size; a .vdt map is used as saved and refuses another).
  double resolution = 0.0;
  double margin = 1.0;  ///< free border around a cloud's or an octree's occupied space, metres
  std::optional<CropBox> crop;  ///< clouds only: the points kept
  bool sparse = false;          ///< clouds and octrees: build a SparseVdtMap3
  /// Clouds only: thin walls to their surfaces (PointCloudOccupancyOptions::thin_surfaces).
  bool thin_surfaces = true;
  bool quiet = false;
};

/// \brief A loaded (or built) map and how long it took.
struct Map3d {
  std::unique_ptr<VdtMap3> dense;  ///< one of the two
  std::unique_ptr<SparseVdtMap3> sparse;
  double seconds = 0.0;
  std::string source;  ///< "point cloud", "octree", "vdt map file", ... (", sparse")

  [[nodiscard]] const VdtField3& field() const {
    return dense ? static_cast<const VdtField3&>(*dense) : *sparse;
  }
  [[nodiscard]] std::size_t memory_bytes() const;
};

/// \brief A mapping run to build a map from (`map3d --scans DIR --poses FILE`): the clouds of
/// `dir` in name order, each moved into the map frame by its pose in `poses` (KITTI or TUM,
/// io/scan_run.hpp) composed with `lidar_pose`.
struct ScanRun {
  std::string dir, poses;
  ScanSelection selection;        ///< which clouds (--every, --skip-odd, --skip-even)
  double stamp_tolerance = 0.01;  ///< TUM: seconds between a cloud's name and its pose's stamp
  /// The clouds' frame in the frame whose poses the file gives (e.g. KITTI's camera poses and a
  /// Velodyne's clouds: the camera-from-Velodyne calibration).
  Pose3 lidar_pose = Pose3::Identity();
};

/// \brief Builds the map of a mapping run: the selected clouds merged in the map frame
/// (RegisteredScans, cells of a quarter voxel), then voxelized as a map cloud file is
/// (`options`: resolution, margin, crop in the map frame, thinning, sparse), saying on stderr
/// what it reads.
/// \throws vdtnav::Error (file, what was expected) for a bad folder, pose file, cloud or option.
[[nodiscard]] Map3d build_map3d_from_scans(const ScanRun& run, const Map3dOptions& options);

/// \brief Loads or builds the VDT map of `path`, saying on stderr what it does (the grid's size
/// and memory first: a dense 3D grid grows with the box, see `--crop`).
/// \throws vdtnav::Error (file, what was expected) for a bad file or option.
[[nodiscard]] Map3d load_map3d(const std::string& path, const Map3dOptions& options);

}  // namespace vdtnav::tools
