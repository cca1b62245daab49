#pragma once
// The order in which VdtOptimizerT looks up the readings of an observation set: as given in 2D,
// along a Z-order (Morton) curve through the map cells of the endpoints in 3D.

#include <vector>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav::detail {

/// The order in which the readings are looked up. 2D: as given (a scan is already coherent and
/// its lookups compute-bound). 3D: along a Z-order curve through the map cells of the endpoints
/// at `pose`, so that consecutive lookups share the cache lines of their 4 x 4 x 4 spline
/// support; a 3D lookup is memory-bound and a pan-tilt sweep jumps between surfaces.
template <int Dim>
std::vector<int> lookup_order(const VdtField<Dim>& map, const ObservationSet<Dim>& scan,
                              const typename PoseTraits<Dim>::Pose& pose);

}  // namespace vdtnav::detail
