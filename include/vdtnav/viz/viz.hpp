#pragma once
/// \file
/// \brief Umbrella header of vdtnav/viz: PNG figures without Python.

#include "vdtnav/viz/colormap.hpp"
#include "vdtnav/viz/image.hpp"
#include "vdtnav/viz/plot.hpp"
