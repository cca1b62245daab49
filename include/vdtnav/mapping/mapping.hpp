#pragma once
/// \file
/// \brief Umbrella header of vdtnav/mapping: occupancy maps from known poses and scans
/// (vdtnav::core), and uncertain VDT maps fitted to noisy scans (thesis ch. 5; link
/// vdtnav::localization).

#include "vdtnav/mapping/eikonal_residuals.hpp"
#include "vdtnav/mapping/map_scan.hpp"
#include "vdtnav/mapping/marginal_covariance.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
