#pragma once
/// \file
/// \brief vdtnav::octomap, the OctoMap front end: everything in vdtnav/octomap/.

#include "vdtnav/octomap/octree_conversion.hpp"
#include "vdtnav/octomap/octree_map.hpp"
