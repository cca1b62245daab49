#pragma once
/// \file
/// \brief Interpolating uniform cubic B-spline fields (C^2) with analytic gradient and Hessian.
///
/// Samples f_k on a regular grid are turned into coefficients c_k by the prefilter
///   (c_{k-1} + 4 c_k + c_{k+1}) / 6 = f_k            (interpolation at every node)
/// with natural ends (c_{-1} = 2 c_0 - c_1, c_n = 2 c_{n-1} - c_{n-2}), which make c_0 = f_0 and
/// reproduce linear fields exactly. Without the prefilter a cubic B-spline only smooths and
/// biases zero crossings (SPEC, Numerical notes). The prefilter is separable: one tridiagonal
/// solve per axis.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/traits.hpp"

namespace vdtnav {

/// \brief Cubic B-spline basis at fractional offset t in [0, 1] for nodes floor(u)-1 .. floor(u)+2,
/// with first and second derivatives with respect to t.
struct CubicBSplineWeights {
  float w[4];
  float dw[4];
  float ddw[4];

  explicit CubicBSplineWeights(float t) {
    const float s = 1.0F - t, t2 = t * t, t3 = t2 * t;
    constexpr float kSixth = 1.0F / 6.0F;
    w[0] = s * s * s * kSixth;
    w[1] = (3.0F * t3 - 6.0F * t2 + 4.0F) * kSixth;
    w[2] = (-3.0F * t3 + 3.0F * t2 + 3.0F * t + 1.0F) * kSixth;
    w[3] = t3 * kSixth;
    dw[0] = -0.5F * s * s;
    dw[1] = 1.5F * t2 - 2.0F * t;
    dw[2] = -1.5F * t2 + t + 0.5F;
    dw[3] = 0.5F * t2;
    ddw[0] = s;
    ddw[1] = 3.0F * t - 2.0F;
    ddw[2] = 1.0F - 3.0F * t;
    ddw[3] = t;
  }
};

/// \brief A Channels-valued C^2 field on a Dim-dimensional node lattice, in index coordinates u
/// (node k at u = k). Coefficients are stored with one ghost node on each side, channels
/// interleaved, x fastest.
template <int Dim, int Channels>
class CubicBSplineField {
 public:
  using Index = typename SpaceTraits<Dim>::Index;
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Values = Eigen::Matrix<double, Channels, 1>;
  /// Row c: gradient of channel c with respect to u.
  using Jacobian = Eigen::Matrix<double, Channels, Dim>;
  /// Hessian of each channel with respect to u.
  using Hessians = std::array<Eigen::Matrix<double, Dim, Dim>, Channels>;

  CubicBSplineField() : size_(Index::Zero()), padded_(Index::Zero()) {}

  /// \brief Prefilters samples (Channels floats per node, x fastest). Every axis needs >= 2 nodes.
  CubicBSplineField(const Index& size, std::vector<float> samples);

  /// \brief Adopts already prefiltered coefficients with their ghost nodes (for map files).
  static CubicBSplineField from_coefficients(const Index& size, std::vector<float> coefficients);

  [[nodiscard]] const Index& size() const noexcept { return size_; }
  [[nodiscard]] const std::vector<float>& coefficients() const noexcept { return coef_; }

  /// \brief Clamps u to the node hull [0, n-1]^Dim.
  /// \return true when u was inside (up to kHullTolerance, which absorbs rounding of points on
  /// the hull such as border cell centres).
  [[nodiscard]] bool clamp(Vector& u) const noexcept {
    constexpr double kHullTolerance = 1e-9;
    bool inside = true;
    for (int d = 0; d < Dim; ++d) {
      const double x = u[d], hi = hull_max_[d];
      inside &= (x >= -kHullTolerance) & (x <= hi + kHullTolerance);  // false for NaN
      const double lo_clamped = x >= 0.0 ? x : 0.0;                   // NaN -> 0
      u[d] = lo_clamped <= hi ? lo_clamped : hi;
    }
    return inside;
  }

  /// \brief Evaluates at u (must lie in the node hull; see clamp()). Any output may be null.
  void evaluate(const Vector& u, Values* value, Jacobian* gradient, Hessians* hessian) const {
    if (hessian != nullptr) {
      evaluate_impl<true, true>(u, value, gradient, hessian);
    } else if (gradient != nullptr) {
      evaluate_impl<true, false>(u, value, gradient, hessian);
    } else {
      evaluate_impl<false, false>(u, value, gradient, hessian);
    }
  }

 private:
  template <bool kGradient, bool kHessian>
  void evaluate_impl(const Vector& u, Values* value, Jacobian* gradient, Hessians* hessian) const;

  std::ptrdiff_t padded_offset(const Index& node) const noexcept {  // node of the padded lattice
    std::ptrdiff_t l = node[Dim - 1];
    for (int d = Dim - 2; d >= 0; --d) l = l * padded_[d] + node[d];
    return l * Channels;
  }

  Index size_;
  Index padded_;
  Vector hull_max_ = Vector::Zero();  // n - 1 per axis, as double
  std::vector<float> coef_;
};

// ---------------------------------------------------------------- inline evaluation (hot path)

template <int Dim, int Channels>
template <bool kGradient, bool kHessian>
inline void CubicBSplineField<Dim, Channels>::evaluate_impl(const Vector& u, Values* value,
                                                            Jacobian* gradient,
                                                            Hessians* hessian) const {
  // A row of the 4^Dim support is 4 nodes x Channels floats, contiguous: accumulate whole rows
  // weighted by their y (and z) weights as packed arrays, and reduce across x once at the end.
  // This is the tensor-product sum  sum_ijk wx_i wy_j wz_k c_ijk  and its derivatives.
  using Row = Eigen::Array<float, 4 * Channels, 1>;
  Index base;
  float t[Dim];
  for (int d = 0; d < Dim; ++d) {
    int i = static_cast<int>(u[d]);          // u >= 0 (clamped)
    if (i > size_[d] - 2) i = size_[d] - 2;  // u == n-1 uses the last span with t = 1
    base[d] = i;                             // node i-1 is padded node i
    t[d] = static_cast<float>(u[d] - i);
  }
  const float* c0 = coef_.data() + padded_offset(base);
  const CubicBSplineWeights wx(t[0]), wy(t[1]), wz(Dim == 3 ? t[Dim - 1] : 0.0F);
  const std::ptrdiff_t row_stride = static_cast<std::ptrdiff_t>(padded_[0]) * Channels;
  const std::ptrdiff_t plane_stride = Dim == 3 ? row_stride * padded_[1] : 0;
  // Row sums: r = sum over rows of (y,z weight) * row, and its y/z derivative variants.
  Row r = Row::Zero(), ry = Row::Zero(), rz = Row::Zero();
  Row ryy = Row::Zero(), rzz = Row::Zero(), ryz = Row::Zero();
  constexpr int kPlanes = Dim == 3 ? 4 : 1;
  for (int k = 0; k < kPlanes; ++k) {
    const float z0 = Dim == 3 ? wz.w[k] : 1.0F;
    const float z1 = Dim == 3 ? wz.dw[k] : 0.0F;
    const float z2 = Dim == 3 ? wz.ddw[k] : 0.0F;
    const float* plane = c0 + k * plane_stride;
    for (int j = 0; j < 4; ++j) {
      const Eigen::Map<const Row> row(plane + j * row_stride);
      r += (wy.w[j] * z0) * row;
      if constexpr (kGradient) {
        ry += (wy.dw[j] * z0) * row;
        if constexpr (Dim == 3) rz += (wy.w[j] * z1) * row;
        if constexpr (kHessian) {
          ryy += (wy.ddw[j] * z0) * row;
          if constexpr (Dim == 3) {
            rzz += (wy.w[j] * z2) * row;
            ryz += (wy.dw[j] * z1) * row;
          }
        }
      }
    }
  }
  // x weights expanded to the interleaved row layout (lane i * Channels + c has weight of node i):
  // a Channels x 4 matrix with every row equal to the weights, read column-major.
  const auto expand = [](const float* w) -> Row {
    const Eigen::Map<const Eigen::Matrix<float, 1, 4>> w4(w);
    const Eigen::Matrix<float, Channels, 4> m = w4.replicate<Channels, 1>();
    return Eigen::Map<const Row>(m.data());
  };
  const Row ex = expand(wx.w);
  const Row edx = kGradient ? expand(wx.dw) : Row::Zero().eval();
  const Row eddx = kHessian ? expand(wx.ddw) : Row::Zero().eval();
  // Sum the lanes of each channel: lanes form a Channels x 4 column-major matrix.
  const auto reduce = [](const Row& a) -> Eigen::Matrix<float, Channels, 1> {
    return Eigen::Map<const Eigen::Matrix<float, Channels, 4>>(a.data()).rowwise().sum();
  };
  if (value != nullptr) *value = reduce(r * ex).template cast<double>();
  if constexpr (kGradient) {
    gradient->col(0) = reduce(r * edx).template cast<double>();
    gradient->col(1) = reduce(ry * ex).template cast<double>();
    if constexpr (Dim == 3) gradient->col(2) = reduce(rz * ex).template cast<double>();
  }
  if constexpr (kHessian) {
    const auto xx = reduce(r * eddx), xy = reduce(ry * edx), yy = reduce(ryy * ex);
    Eigen::Matrix<float, Channels, 1> xz, yz, zz;
    if constexpr (Dim == 3) {
      xz = reduce(rz * edx);
      yz = reduce(ryz * ex);
      zz = reduce(rzz * ex);
    }
    for (int c = 0; c < Channels; ++c) {
      auto& h = (*hessian)[c];
      h(0, 0) = xx[c];
      h(0, 1) = h(1, 0) = xy[c];
      h(1, 1) = yy[c];
      if constexpr (Dim == 3) {
        h(0, 2) = h(2, 0) = xz[c];
        h(1, 2) = h(2, 1) = yz[c];
        h(2, 2) = zz[c];
      }
    }
  }
}

}  // namespace vdtnav
