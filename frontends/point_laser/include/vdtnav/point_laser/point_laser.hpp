#pragma once
/// \file
/// \brief Umbrella header of vdtnav::point_laser: the pan-tilt point laser of Dataset 4 (thesis
/// 3.4.4) — its geometry and observation set (vdtnav::sensor) and its CSV readings (PCL clouds of
/// pan-tilt points: vdtnav::pcl, vdtnav/pcl/point_laser_cloud.hpp).

#include "vdtnav/point_laser/pan_tilt_csv.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"
