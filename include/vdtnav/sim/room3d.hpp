#pragma once
/// \file
/// \brief A seeded, procedurally generated indoor 3D scene: the embedded default world of the
/// pan-tilt point-laser study (thesis 3.4.4, the CAS lab) when no real 3D map is given, and the
/// "uneven floor" robot poses of 3.4.4.2.
///
/// A box room (floor, ceiling, four walls) split by a partition wall with a doorway, furnished
/// with boxes, tables (a top on four legs, so beams pass underneath) and floor-to-ceiling pillars.
/// Every solid is an axis-aligned box whose faces lie on cell-centre planes, so the surfaces that
/// cast_ray(..., RaySurface::kCellCentre) reports, the zero set of the grid's VDT and the listed
/// boxes all agree: the floor surface is z = 0, the walls' inner faces are x = 0, x = length,
/// y = 0, y = width, and the ceiling is z = height. The same seed always gives the same scene.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/map/grid.hpp"

namespace vdtnav::sim {

/// \brief Parameters of the generated room (lengths are snapped to the resolution).
struct Room3dOptions {
  double length = 12.0;          ///< metres along x, between the walls' inner faces
  double width = 10.0;           ///< metres along y
  double height = 3.5;           ///< metres, floor surface to ceiling surface
  double resolution = 0.05;      ///< metres per cell
  double wall_thickness = 0.15;  ///< metres, walls, floor and ceiling (at least 2 cells' worth)
  double partition_x = 8.0;      ///< x of the partition wall's near face (<= 0: no partition)
  double door_width = 1.0;       ///< metres, doorway in the partition
  double door_height = 2.1;      ///< metres
  int boxes = 4;                 ///< crates/cabinets standing on the floor (at most)
  int tables = 3;                ///< tables (at most)
  int pillars = 2;               ///< floor-to-ceiling pillars (at most)
  std::uint32_t seed = 1;
};

/// \brief The generated scene.
struct Room3d {
  OccupancyGrid<3> occupancy;  ///< 1 = solid
  /// Every solid as a closed box in metres (overlaps allowed); their union is the occupied set
  /// (a cell is occupied iff its centre lies in one of them).
  std::vector<Eigen::AlignedBox3d> solids;
  Eigen::Vector3d interior_min = Eigen::Vector3d::Zero();  ///< (0, 0, 0)
  Eigen::Vector3d interior_max = Eigen::Vector3d::Zero();  ///< (length, width, height)
  Eigen::AlignedBox3d doorway;  ///< the free opening in the partition (empty without one)
};

/// \brief Generates the room. \throws ConfigError for sizes the layout cannot hold.
[[nodiscard]] Room3d generate_room3d(const Room3dOptions& options = {});

/// \brief Where and how the robot stands for the point-laser sweeps (thesis 3.4.4.2: "driven to a
/// location and then rolled and pitched to simulate uneven floor").
struct UnevenFloorOptions {
  int count = 3;                                         ///< locations
  double min_tilt = 1.0 * 3.14159265358979323846 / 180;  ///< |roll|, |pitch| at least, radians
  double max_tilt = 5.0 * 3.14159265358979323846 / 180;  ///< |roll|, |pitch| at most, radians
  double max_base_height = 0.05;  ///< robot origin this far above the floor at most (a bump)
  double clearance = 0.5;         ///< metres of free space around the robot's vertical axis
  double clearance_height = 1.0;  ///< up to this height above the floor
  double min_separation = 2.0;    ///< metres between locations
  std::uint32_t seed = 1;
};

/// \brief Robot poses on the room's floor: (x, y) uniform over places with `clearance` free space
/// around the robot up to `clearance_height`, at least `min_separation` apart; yaw uniform;
/// roll and pitch each of magnitude uniform in [min_tilt, max_tilt] with a random sign; z, the
/// robot origin's height above the floor surface, uniform in [0, max_base_height]. With the
/// default point-laser mount (PanTiltCalibration::turtlebot_example) the beam starts about
/// 0.4-0.5 m above the floor.
/// \throws ConfigError for invalid options or when the locations do not fit.
[[nodiscard]] std::vector<Pose3> uneven_floor_poses(const Room3d& room,
                                                    const UnevenFloorOptions& options = {});

}  // namespace vdtnav::sim
