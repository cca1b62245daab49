#pragma once
/// \file
/// \brief A run of 3D scans on disk as users have it: a folder of point clouds, one per scan, in
/// name order, and a pose file giving each cloud's frame in the map frame — KITTI form (one 3x4
/// row-major matrix [R | t] a line, a line per cloud; Geiger et al., CVPR 2012) or TUM form
/// (`t x y z qx qy qz qw`, tum_trajectory.hpp) with stamps matched to the clouds' numeric names.
/// What `vdtnav map3d --scans` and `vdtnav localize3d --scans` read.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/io/tum_trajectory.hpp"

namespace vdtnav {

/// \return whether `path` names a point cloud file the PCL front end reads, by its extension
/// (.pcd .ply .vtk .csv .txt .xyz, any case).
[[nodiscard]] bool is_point_cloud_file(const std::string& path);

/// \brief The point cloud files of a folder (is_point_cloud_file), sorted by name.
/// \throws IoError when `dir` is not a readable folder.
/// \throws ConfigError when it holds no point cloud file.
[[nodiscard]] std::vector<std::string> point_cloud_files_in(const std::string& dir);

/// \return the time stamp a file name gives: its stem when that is a whole finite number (drivers
/// and bag exporters name clouds by their stamp, e.g. 1317357625.557814.pcd; KITTI's 000042.bin
/// reads 42), else nothing.
[[nodiscard]] std::optional<double> stamp_of_name(const std::string& path);

/// \brief Tolerance on a KITTI matrix's rotation: |RᵀR − I| per entry and |det R − 1| at most this
/// (files written with 6 significant digits are ~1e-6 off); R is then re-orthonormalised.
inline constexpr double kKittiRotationTolerance = 1e-3;

/// \brief Loads KITTI poses: one line per pose, 12 finite numbers r00 r01 r02 tx r10 r11 r12 ty
/// r20 r21 r22 tz (the top 3x4 of the 4x4 pose, row by row); blank and '#' lines are ignored.
/// \throws IoError when the file cannot be read.
/// \throws FormatError (`file:line: what was expected`) for a malformed line or a matrix whose
///         3x3 part is not a rotation within kKittiRotationTolerance.
[[nodiscard]] std::vector<Pose3> load_kitti_poses(const std::string& path);

/// \brief Loads a scan time file (KITTI's times.txt): one stamp per line and cloud, in name order,
/// seconds, strictly increasing; blank and '#' lines are ignored. For clouds whose names are not
/// their stamps (000042.pcd), what `vdtnav localize3d --scans DIR --times FILE` stamps them with.
/// \throws IoError when the file cannot be read, FormatError (`file:line: what was expected`) for
///         a line that is not one finite number or a stamp not after the one before.
[[nodiscard]] std::vector<double> load_scan_times(const std::string& path);

/// \brief The forms a scan pose file may take.
enum class ScanPoseFormat { kKitti, kTum };

/// \brief A pose file read by load_scan_poses(): its form and its poses in file order (KITTI
/// poses carry t = their index, which is not a time).
struct ScanPoseFile {
  std::string path;
  ScanPoseFormat format = ScanPoseFormat::kKitti;
  std::vector<StampedPose3> poses;
};

/// \brief Loads a pose file in either form, told apart by its first data line: 12 numbers are
/// KITTI, 8 are TUM; every other line must then have the same form.
/// \throws IoError, FormatError as load_kitti_poses() and load_tum_trajectory(), and FormatError
///         naming both forms when the first data line is neither, or the file has no pose.
[[nodiscard]] ScanPoseFile load_scan_poses(const std::string& path);

/// \brief The pose of each scan file, in the map frame. KITTI: the k-th pose is the k-th cloud's
/// (name order), and the file must hold one pose per cloud. TUM: each cloud's stamp_of_name()
/// is matched to the nearest pose stamp, which must lie within `stamp_tolerance` seconds.
/// \param scans every cloud of the run, in name order (before any selection: KITTI counts them).
/// \throws ConfigError naming the pose file and the cloud when a count differs, a cloud's name is
///         not a stamp (TUM), or no pose is close enough (with the nearest one's offset).
[[nodiscard]] std::vector<Pose3> poses_of_scans(const ScanPoseFile& poses,
                                                const std::vector<std::string>& scans,
                                                double stamp_tolerance = 0.01);

/// \brief Which scans of a run to take (e.g. half a run for the map, the other half to localize).
/// Scans are counted from 0 in name order, so the first is even.
struct ScanSelection {
  int every = 1;           ///< take scans 0, N, 2N, ... (>= 1)
  bool skip_odd = false;   ///< drop scans 1, 3, 5, ...
  bool skip_even = false;  ///< drop scans 0, 2, 4, ...
};

/// \return the indices in [0, count) the selection keeps, in order.
/// \throws ConfigError when `every` < 1, both parities are skipped, or nothing is kept.
[[nodiscard]] std::vector<std::size_t> select_scans(std::size_t count,
                                                    const ScanSelection& selection);

}  // namespace vdtnav
