#pragma once
/// \file
/// \brief Umbrella header of vdtnav/io: map files (ROS map_server, floor-plan images, point sets,
/// the VdtMap binary format).

#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/point_set_map.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/io/vdt_map_file.hpp"
