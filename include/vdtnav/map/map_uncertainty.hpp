#pragma once
/// \file
/// \brief A map that knows its own error: the covariance of DT_v, jointly over points (thesis
/// ch. 5).
///
/// The estimators read it through VdtSensorModelOptions::map_uncertainty. The errors of DT_v at
/// two endpoints are correlated (a wall fitted a few centimetres off is off along its length, and
/// one pose error of the scans it was built from moves all it saw), so a pose estimate's map term
/// is not a sum of independent per-reading terms: it is cov(sum_i s_i e(q_i)), what propagate()
/// returns. An uncertain VDT map fitted to noisy scans (mapping/uncertain_vdt_map.hpp) is one.

#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/traits.hpp"

namespace vdtnav {

/// \brief The covariance of a map's DT_v (aliases MapUncertainty2, MapUncertainty3).
template <int Dim>
class MapUncertainty {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  using Covariance = typename PoseTraits<Dim>::Covariance;
  /// ds/de: how an estimate (pose) moves with the map's error e(q) of DT_v at one point.
  using Sensitivity = Eigen::Matrix<double, PoseTraits<Dim>::kDoF, Dim>;

  virtual ~MapUncertainty() = default;

  /// \brief Dim x Dim covariance of DT_v at world point p, metres^2.
  /// \return false where the map does not know it (outside the part it was fitted on).
  [[nodiscard]] virtual bool dt_covariance(const Vector& p, Matrix* cov) const = 0;

  /// \brief cov(sum_i s_i e(q_i)): the covariance an estimate gets from the map's errors e(q_i)
  /// at the world points q_i, with every correlation between them the map knows.
  /// \param known when not null, resized to q.size(): whether the map knows its error at q_i;
  /// the other points are left out of the sum (the caller models them).
  [[nodiscard]] virtual Covariance propagate(const std::vector<Vector>& q,
                                             const std::vector<Sensitivity>& s,
                                             std::vector<char>* known) const = 0;

 protected:
  MapUncertainty() = default;
  MapUncertainty(const MapUncertainty&) = default;
  MapUncertainty& operator=(const MapUncertainty&) = default;
  MapUncertainty(MapUncertainty&&) noexcept = default;
  MapUncertainty& operator=(MapUncertainty&&) noexcept = default;
};

using MapUncertainty2 = MapUncertainty<2>;
using MapUncertainty3 = MapUncertainty<3>;

}  // namespace vdtnav
