#pragma once
/// \file
/// \brief vdtnav::pcl, the point cloud front end: everything in vdtnav/pcl/.

#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_file.hpp"
#include "vdtnav/pcl/point_cloud_map.hpp"
#include "vdtnav/pcl/registered_scans.hpp"
