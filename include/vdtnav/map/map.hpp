#pragma once
/// \file
/// \brief Umbrella header of vdtnav/map.

#include "vdtnav/map/cubic_bspline.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
