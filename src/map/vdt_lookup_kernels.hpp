#pragma once
// The SIMD kernels of VdtMap's batch lookup (vdt_lookup_kernels.cpp).

#include <cstddef>

#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav::detail {

/// Fills out[0..n) as VdtMap::evaluate(p[k]) does (only value and inside when !jacobian), with
/// the kernels of simd_level().
/// \return false, having done nothing, when no kernel applies (baseline level, or a map rotated
/// in the world): the caller evaluates point by point.
template <int Dim>
bool evaluate_simd(const VdtMap<Dim>& map, const typename SpaceTraits<Dim>::Vector* p,
                   std::size_t n, VdtSample<Dim>* out, bool jacobian);

}  // namespace vdtnav::detail
