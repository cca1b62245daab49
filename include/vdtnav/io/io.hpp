#pragma once
/// \file
/// \brief Umbrella header of vdtnav/io: map files (ROS map_server, floor-plan images, point sets,
/// the VdtMap binary format), CARMEN logs, benchmark relations, TUM trajectories and
/// runs of 3D scans with their poses (KITTI or TUM).

#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/point_set_map.hpp"
#include "vdtnav/io/relations.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/scan_run.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
