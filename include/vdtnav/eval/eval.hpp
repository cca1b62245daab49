#pragma once
/// \file
/// \brief Umbrella header of vdtnav/eval: trajectory and consistency metrics.

#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/eval/umeyama.hpp"
