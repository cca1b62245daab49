#pragma once
/// \file
/// \brief Umbrella header of vdtnav/mapping: occupancy maps from known poses and scans.

#include "vdtnav/mapping/occupancy_mapper.hpp"
