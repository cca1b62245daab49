#pragma once
/// \file
/// \brief `VdtField<Dim>`: what the estimators need of a continuous VDT map — DT_v, its Jacobian
/// and Hessians at any point, the exact nearest-point alternative, the grid's placement — whatever
/// stores it: the dense VdtMap (vdt_map.hpp) or the sparse, bricked SparseVdtMap3
/// (sparse_vdt_map.hpp). One virtual call per batch of points.

#include <array>
#include <cstddef>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// \brief DT_v and its Jacobian at a query point.
template <int Dim>
struct VdtSample {
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  Vector value = Vector::Zero();     ///< DT_v(p) = p - c(p), world axes, metres
  Matrix jacobian = Matrix::Zero();  ///< dDT_v/dp; row c is the gradient of component c
  bool inside = false;  ///< false: p is outside the map and the values belong to the clamped point
};

/// \brief DT_v, its Jacobian, and the Hessian of every component.
template <int Dim>
struct VdtSampleWithHessian : VdtSample<Dim> {
  std::array<typename SpaceTraits<Dim>::Matrix, Dim>
      hessian{};  ///< d^2 DT_c / dp^2 per component c
};

/// \brief The lookup interface of a continuous VDT map (see the file comment).
template <int Dim>
class VdtField {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Index = typename SpaceTraits<Dim>::Index;

  virtual ~VdtField() = default;

  /// \brief DT_v (and, with `jacobian`, dDT_v/dp) at n points, out[k] for p[k], world frame.
  virtual void evaluate(const Vector* p, std::size_t n, VdtSample<Dim>* out,
                        bool jacobian = true) const = 0;
  /// \brief DT_v, its Jacobian and the Hessian of every component at p.
  [[nodiscard]] virtual VdtSampleWithHessian<Dim> evaluate_with_hessian(const Vector& p) const = 0;
  /// \brief The exact alternative to interpolation: p - c(cell(p)), Jacobian the identity.
  [[nodiscard]] virtual VdtSample<Dim> nearest_point_query(const Vector& p) const = 0;
  [[nodiscard]] virtual const GridFrame<Dim>& frame() const noexcept = 0;
  [[nodiscard]] virtual const Index& size() const noexcept = 0;

  [[nodiscard]] double resolution() const noexcept { return frame().resolution(); }
  /// \brief DT_v and its Jacobian at one point.
  [[nodiscard]] VdtSample<Dim> evaluate(const Vector& p) const {
    VdtSample<Dim> s;
    evaluate(&p, 1, &s);
    return s;
  }
  /// \brief DT_v only at one point (the cheaper lookup).
  [[nodiscard]] Vector value(const Vector& p, bool* inside = nullptr) const {
    VdtSample<Dim> s;
    evaluate(&p, 1, &s, /*jacobian=*/false);
    if (inside != nullptr) *inside = s.inside;
    return s.value;
  }

 protected:
  VdtField() = default;
  VdtField(const VdtField&) = default;
  VdtField(VdtField&&) noexcept = default;
  VdtField& operator=(const VdtField&) = default;
  VdtField& operator=(VdtField&&) noexcept = default;
};

using VdtField2 = VdtField<2>;
using VdtField3 = VdtField<3>;

}  // namespace vdtnav
