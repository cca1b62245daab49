#pragma once
// The SIMD kernels of VdtMap's and SparseVdtMap3's batch lookups (vdt_lookup_kernels.cpp).

#include <cstddef>

#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav::detail {

/// Fills out[0..n) as VdtMap::evaluate(p[k]) does (only value and inside when !jacobian), with
/// the kernels of simd_level().
/// \return false, having done nothing, when no kernel applies (baseline level, or a map rotated
/// in the world): the caller evaluates point by point.
template <int Dim>
bool evaluate_simd(const VdtMap<Dim>& map, const typename SpaceTraits<Dim>::Vector* p,
                   std::size_t n, VdtSample<Dim>* out, bool jacobian);

/// A sparse map's lookup of one point (world in and out) by its portable path: the kernel hands
/// it the points whose support reaches an unallocated brick (the coarse level).
using SparseFallback = VdtSample<3> (*)(const SparseVdtMap3& map, const Eigen::Vector3d& p,
                                        bool jacobian);

/// As above for SparseVdtMap3::evaluate; points answered by the coarse level go to `fallback`.
bool evaluate_simd(const SparseVdtMap3& map, const Eigen::Vector3d* p, std::size_t n,
                   VdtSample<3>* out, bool jacobian, SparseFallback fallback);

}  // namespace vdtnav::detail
