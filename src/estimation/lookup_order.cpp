// The Morton (Z-order) ordering of the readings of an observation set for cache-coherent 3D map
// lookups (see lookup_order.hpp).
#include "lookup_order.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace vdtnav::detail {
namespace {

/// Spreads the low 21 bits of v to every third bit (a Morton code component).
std::uint64_t spread_bits3(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

template <int Dim>
std::vector<int> lookup_order(const VdtField<Dim>& map, const ObservationSet<Dim>& scan,
                              const typename PoseTraits<Dim>::Pose& pose) {
  using Traits = PoseTraits<Dim>;
  std::vector<int> order(scan.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  if constexpr (Dim == 3) {
    const typename Traits::Rotation r = Traits::rotation(pose);
    const typename Traits::Vector t = Traits::translation(pose);
    std::vector<std::uint64_t> key(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector3i c = map.frame().cell_of(r * scan.points[i] + t).cwiseMax(0);
      key[i] = spread_bits3(static_cast<std::uint64_t>(c.x())) |
               spread_bits3(static_cast<std::uint64_t>(c.y())) << 1 |
               spread_bits3(static_cast<std::uint64_t>(c.z())) << 2;
    }
    std::sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  }
  return order;
}

template std::vector<int> lookup_order<2>(const VdtField<2>&, const ObservationSet<2>&,
                                          const PoseTraits<2>::Pose&);
template std::vector<int> lookup_order<3>(const VdtField<3>&, const ObservationSet<3>&,
                                          const PoseTraits<3>::Pose&);

}  // namespace vdtnav::detail
