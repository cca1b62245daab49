#pragma once
/// \file
/// \brief `VdtMap<Dim>`: the continuous vector distance transform map (thesis ch. 2).
///
/// Holds the exact feature transform (nearest occupied cell of every cell) and an interpolating
/// cubic B-spline of each DT_v component, so that DT_v(p), dDT_v/dp and the Hessians of every
/// component are available analytically at any p (Algorithm 1's "Require" list). Memory:
/// 4 B/cell for the features + 4*Dim B/cell for the coefficients (12 B/cell in 2D, 16 B/voxel in
/// 3D, plus one ghost layer).

#include <array>
#include <cstddef>
#include <cstdint>

#include "vdtnav/map/cubic_bspline.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav {

/// \brief Instruction sets of the batch lookup (VdtMap::evaluate over many points).
enum class SimdLevel {
  kBaseline,  ///< the portable evaluation (SSE2 on x86-64)
  kAvx2Fma,   ///< AVX2 + FMA kernels
};

/// \return the instruction set of the batch lookup: the best the CPU has, chosen at run time
/// (the library and its headers are compiled for the baseline ISA). The environment variable
/// VDTNAV_SIMD=baseline selects the portable kernels, whose results repeat bit for bit on every
/// x86-64 machine (the AVX2 kernels round the float coefficients' sums differently).
[[nodiscard]] SimdLevel simd_level() noexcept;

/// \brief Chooses the batch lookup's instruction set (tests and benchmarks compare them); a level
/// the CPU lacks falls back to kBaseline. \return the level now in use.
SimdLevel set_simd_level(SimdLevel level) noexcept;

/// \brief Continuous VDT map of dimension Dim (aliases VdtMap2, VdtMap3), dense: every cell of
/// the box. The estimators take any VdtField (vdt_field.hpp); this is the one they are fastest on.
template <int Dim>
class VdtMap final : public VdtField<Dim> {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  using Index = typename SpaceTraits<Dim>::Index;
  using Field = CubicBSplineField<Dim, Dim>;

  VdtMap() = default;
  /// \brief Assembles a map from its parts (map files); checks that they agree.
  VdtMap(Grid<std::int32_t, Dim> nearest, Field field);

  /// \brief Builds the exact VDT of an occupancy grid and its interpolant.
  ///
  /// The features are the surface cells (surface_cells()): outside obstacles DT_v is exactly
  /// p - c(p) with c the nearest occupied cell; inside thick obstacles it points to the nearest
  /// surface cell rather than being zero (set all_occupied_cells to keep the plain definition).
  /// \throws ConfigError when no cell is occupied or an axis has fewer than 2 cells.
  [[nodiscard]] static VdtMap build(const OccupancyGrid<Dim>& occupied,
                                    bool all_occupied_cells = false);

  /// \brief Interpolated DT_v and Jacobian at world point p (the batch lookup for one point).
  [[nodiscard]] VdtSample<Dim> evaluate(const Vector& p) const {
    VdtSample<Dim> s;
    evaluate(&p, 1, &s);
    return s;
  }

  /// \brief evaluate() at n points (out[k] for p[k]), the batch form the estimators use: the
  /// SIMD kernels of simd_level(), no call per point. The AVX2 kernels sum in another order with
  /// fused multiply-adds: results differ from evaluate()'s by float rounding of the coefficients.
  /// Without `jacobian`, only the values and the inside flags are written (about half the work).
  void evaluate(const Vector* p, std::size_t n, VdtSample<Dim>* out,
                bool jacobian = true) const override;

  /// \brief Interpolated DT_v, Jacobian and Hessians at world point p.
  [[nodiscard]] VdtSampleWithHessian<Dim> evaluate_with_hessian(const Vector& p) const override;

  /// \brief Interpolated DT_v only (the batch lookup for one point, without the Jacobian).
  [[nodiscard]] Vector value(const Vector& p, bool* inside = nullptr) const {
    VdtSample<Dim> s;
    evaluate(&p, 1, &s, /*jacobian=*/false);
    if (inside != nullptr) *inside = s.inside;
    return s.value;
  }

  /// \brief The exact alternative to interpolation (SPEC, Numerical notes): the residual from the
  /// stored nearest occupied cell of the cell containing p, DT_v(p) = p - c(cell(p)). Its Jacobian
  /// is the identity: no averaging across a cut locus, at the price of a piecewise model.
  [[nodiscard]] VdtSample<Dim> nearest_point_query(const Vector& p) const override;

  /// \return the centre of the occupied cell nearest to the cell containing p (clamped into the
  /// map).
  [[nodiscard]] Vector nearest_occupied_point(const Vector& p) const;

  [[nodiscard]] const GridFrame<Dim>& frame() const noexcept override { return nearest_.frame(); }
  [[nodiscard]] const Index& size() const noexcept override { return nearest_.size(); }
  [[nodiscard]] double resolution() const noexcept { return nearest_.resolution(); }
  [[nodiscard]] const Grid<std::int32_t, Dim>& nearest_cells() const noexcept { return nearest_; }
  [[nodiscard]] const Field& field() const noexcept { return field_; }
  /// \return bytes held by the map (features + coefficients).
  [[nodiscard]] std::size_t memory_bytes() const noexcept {
    return nearest_.num_cells() * sizeof(std::int32_t) +
           field_.coefficients().size() * sizeof(float);
  }

 private:
  /// The portable lookup of one point (the batch lookup's baseline kernel).
  [[nodiscard]] VdtSample<Dim> evaluate_portable(const Vector& p, bool jacobian) const {
    VdtSample<Dim> s;
    Vector u = frame().continuous_index(p);
    s.inside = field_.clamp(u);
    field_.evaluate(u, &s.value, jacobian ? &s.jacobian : nullptr, nullptr);  // grid axes
    to_world(s);
    return s;
  }

  /// Turns a sample in grid axes per unit of u into world axes per metre:
  /// du/dp = R^T / resolution, so DT_v -> R DT_v and J -> R J R^T / resolution.
  template <typename Sample>
  void to_world(Sample& s) const {
    s.jacobian *= frame().inv_resolution();
    if (!frame().axis_aligned()) {
      const Matrix& r = frame().rotation();
      s.value = r * s.value;
      s.jacobian = r * s.jacobian * r.transpose();
    }
  }

  Grid<std::int32_t, Dim> nearest_;
  Field field_;
};

using VdtMap2 = VdtMap<2>;
using VdtMap3 = VdtMap<3>;

/// \brief A continuous scalar distance transform (UDT or SDT) for the baselines, same spline.
template <int Dim>
class DistanceFieldMap {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  using Field = CubicBSplineField<Dim, 1>;

  /// \brief Value, gradient and Hessian at a query point.
  struct Sample {
    double value = 0.0;
    Vector gradient = Vector::Zero();
    Matrix hessian = Matrix::Zero();
    bool inside = false;
  };

  DistanceFieldMap() = default;
  /// \throws ConfigError when a sample is not finite or an axis has fewer than 2 cells.
  explicit DistanceFieldMap(const Grid<float, Dim>& samples);

  /// \brief Value and gradient (and Hessian when with_hessian) at world point p.
  [[nodiscard]] Sample evaluate(const Vector& p, bool with_hessian = false) const;

  [[nodiscard]] const GridFrame<Dim>& frame() const noexcept { return frame_; }

 private:
  GridFrame<Dim> frame_;
  Field field_;
};

}  // namespace vdtnav
