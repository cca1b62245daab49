#pragma once
/// \file
/// \brief Umbrella header of vdtnav/core.

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/core/traits.hpp"
