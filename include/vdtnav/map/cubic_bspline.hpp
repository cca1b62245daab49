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
    w[0] = s * s * s / 6.0F;
    w[1] = (3.0F * t3 - 6.0F * t2 + 4.0F) / 6.0F;
    w[2] = (-3.0F * t3 + 3.0F * t2 + 3.0F * t + 1.0F) / 6.0F;
    w[3] = t3 / 6.0F;
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
      const double hi = static_cast<double>(size_[d] - 1);
      if (!(u[d] >= 0.0)) {  // also catches NaN
        inside = inside && u[d] >= -kHullTolerance;
        u[d] = 0.0;
      } else if (u[d] > hi) {
        inside = inside && u[d] <= hi + kHullTolerance;
        u[d] = hi;
      }
    }
    return inside;
  }

  /// \brief Evaluates at u (must lie in the node hull; see clamp()). Any output may be null.
  void evaluate(const Vector& u, Values* value, Jacobian* gradient, Hessians* hessian) const;

 private:
  std::ptrdiff_t padded_offset(const Index& node) const noexcept {  // node of the padded lattice
    std::ptrdiff_t l = node[Dim - 1];
    for (int d = Dim - 2; d >= 0; --d) l = l * padded_[d] + node[d];
    return l * Channels;
  }

  Index size_;
  Index padded_;
  std::vector<float> coef_;
};

// ---------------------------------------------------------------- inline evaluation (hot path)

template <int Dim, int Channels>
inline void CubicBSplineField<Dim, Channels>::evaluate(const Vector& u, Values* value,
                                                       Jacobian* gradient,
                                                       Hessians* hessian) const {
  Index base;
  float t[Dim];
  for (int d = 0; d < Dim; ++d) {
    int i = static_cast<int>(u[d]);          // u >= 0
    if (i > size_[d] - 2) i = size_[d] - 2;  // u == n-1 uses the last span with t = 1
    base[d] = i;                             // node i-1 is padded node i
    t[d] = static_cast<float>(u[d] - i);
  }
  const float* c0 = coef_.data() + padded_offset(base);
  const CubicBSplineWeights wx(t[0]), wy(t[1]), wz(t[Dim - 1]);
  const std::ptrdiff_t row_stride = static_cast<std::ptrdiff_t>(padded_[0]) * Channels;

  // Accumulators: value, first and second derivatives per channel (index coordinates).
  float v[Channels] = {}, g[Channels][Dim] = {}, h[Channels][Dim][Dim] = {};
  const bool want_g = gradient != nullptr, want_h = hessian != nullptr;

  const int planes = Dim == 3 ? 4 : 1;
  for (int k = 0; k < planes; ++k) {
    float pv[Channels] = {}, pgx[Channels] = {}, pgy[Channels] = {};
    float phxx[Channels] = {}, phxy[Channels] = {}, phyy[Channels] = {};
    const float* plane = c0;
    if constexpr (Dim == 3) plane += k * row_stride * padded_[1];
    for (int j = 0; j < 4; ++j) {
      const float* row = plane + j * row_stride;
      for (int c = 0; c < Channels; ++c) {
        const float r0 = row[c], r1 = row[Channels + c], r2 = row[2 * Channels + c],
                    r3 = row[3 * Channels + c];
        const float s = wx.w[0] * r0 + wx.w[1] * r1 + wx.w[2] * r2 + wx.w[3] * r3;
        pv[c] += wy.w[j] * s;
        if (want_g) {
          const float sd = wx.dw[0] * r0 + wx.dw[1] * r1 + wx.dw[2] * r2 + wx.dw[3] * r3;
          pgx[c] += wy.w[j] * sd;
          pgy[c] += wy.dw[j] * s;
          if (want_h) {
            const float sdd = wx.ddw[0] * r0 + wx.ddw[1] * r1 + wx.ddw[2] * r2 + wx.ddw[3] * r3;
            phxx[c] += wy.w[j] * sdd;
            phxy[c] += wy.dw[j] * sd;
            phyy[c] += wy.ddw[j] * s;
          }
        }
      }
    }
    if constexpr (Dim == 2) {
      for (int c = 0; c < Channels; ++c) {
        v[c] = pv[c];
        g[c][0] = pgx[c];
        g[c][1] = pgy[c];
        h[c][0][0] = phxx[c];
        h[c][0][1] = phxy[c];
        h[c][1][1] = phyy[c];
      }
    } else {
      for (int c = 0; c < Channels; ++c) {
        v[c] += wz.w[k] * pv[c];
        if (want_g) {
          g[c][0] += wz.w[k] * pgx[c];
          g[c][1] += wz.w[k] * pgy[c];
          g[c][2] += wz.dw[k] * pv[c];
          if (want_h) {
            h[c][0][0] += wz.w[k] * phxx[c];
            h[c][0][1] += wz.w[k] * phxy[c];
            h[c][1][1] += wz.w[k] * phyy[c];
            h[c][0][2] += wz.dw[k] * pgx[c];
            h[c][1][2] += wz.dw[k] * pgy[c];
            h[c][2][2] += wz.ddw[k] * pv[c];
          }
        }
      }
    }
  }
  if (value != nullptr) {
    for (int c = 0; c < Channels; ++c) (*value)[c] = v[c];
  }
  if (want_g) {
    for (int c = 0; c < Channels; ++c)
      for (int d = 0; d < Dim; ++d) (*gradient)(c, d) = g[c][d];
  }
  if (want_h) {
    for (int c = 0; c < Channels; ++c) {
      for (int a = 0; a < Dim; ++a) {
        for (int b = a; b < Dim; ++b) {
          (*hessian)[c](a, b) = h[c][a][b];
          (*hessian)[c](b, a) = h[c][a][b];
        }
      }
    }
  }
}

}  // namespace vdtnav
