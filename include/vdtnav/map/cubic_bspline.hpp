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
/// with first and second derivatives with respect to t. The four weights are cubic polynomials
/// in t evaluated together (Horner, packed):
///   w = ((1-t)^3, 3t^3 - 6t^2 + 4, -3t^3 + 3t^2 + 3t + 1, t^3) / 6.
struct CubicBSplineWeights {
  Eigen::Array4f w, dw, ddw;

  explicit CubicBSplineWeights(float t) {
    constexpr float k = 1.0F / 6.0F;
    const Eigen::Array4f a0(1 * k, 4 * k, 1 * k, 0), a1(-3 * k, 0, 3 * k, 0),
        a2(3 * k, -6 * k, 3 * k, 0), a3(-1 * k, 3 * k, -3 * k, 1 * k);
    w = ((a3 * t + a2) * t + a1) * t + a0;
    dw = (3.0F * a3 * t + 2.0F * a2) * t + a1;
    ddw = 6.0F * a3 * t + 2.0F * a2;
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

namespace detail {

/// A row of the 4^Dim support: 4 nodes x C channels = C packets of 4 floats (lane l of packet q
/// holds node (4q + l) / C, channel (4q + l) % C).
template <int C>
struct RowPackets {
  Eigen::Array4f p[C];

  static RowPackets zero() {
    RowPackets r;
    for (int q = 0; q < C; ++q) r.p[q].setZero();
    return r;
  }
  static RowPackets load(const float* src) {
    RowPackets r;
    for (int q = 0; q < C; ++q) r.p[q] = Eigen::Map<const Eigen::Array4f>(src + 4 * q);
    return r;
  }
  /// this += w * row
  void add(float w, const RowPackets& row) {
    for (int q = 0; q < C; ++q) p[q] += w * row.p[q];
  }
  /// Node weights spread over the lanes: lane l gets w[(4q + l) / C].
  static RowPackets spread(const Eigen::Array4f& w) {
    RowPackets r;
    for (int q = 0; q < C; ++q)
      for (int l = 0; l < 4; ++l) r.p[q][l] = w[(4 * q + l) / C];
    return r;
  }
  /// sum over nodes of weight(node) * this(node, c), per channel c.
  Eigen::Matrix<double, C, 1> dot(const RowPackets& weights) const {
    Eigen::Array4f prod[C];
    for (int q = 0; q < C; ++q) prod[q] = p[q] * weights.p[q];
    Eigen::Matrix<double, C, 1> out;
    if constexpr (C == 1) {
      out[0] = prod[0].sum();
    } else if constexpr (C == 2) {
      const Eigen::Array4f h = prod[0] + prod[1];
      out[0] = h[0] + h[2];
      out[1] = h[1] + h[3];
    } else {
      for (int c = 0; c < C; ++c) {
        float sum = 0.0F;
        for (int i = 0; i < 4; ++i) sum += prod[(i * C + c) / 4][(i * C + c) % 4];
        out[c] = sum;
      }
    }
    return out;
  }
};

}  // namespace detail

template <int Dim, int Channels>
template <bool kGradient, bool kHessian>
inline void CubicBSplineField<Dim, Channels>::evaluate_impl(const Vector& u, Values* value,
                                                            Jacobian* gradient,
                                                            Hessians* hessian) const {
  // The tensor-product sum  sum_ijk wx_i wy_j wz_k c_ijk  and its derivatives. A row of the
  // support (4 nodes x Channels floats) is contiguous: rows are accumulated as packets with their
  // y weights within a plane, planes with their z weights, and x is reduced once at the end.
  using Row = detail::RowPackets<Channels>;
  Index base;
  float t[Dim];
  for (int d = 0; d < Dim; ++d) {
    int i = static_cast<int>(u[d]);          // u >= 0 (clamped)
    if (i > size_[d] - 2) i = size_[d] - 2;  // u == n-1 uses the last span with t = 1
    base[d] = i;                             // node i-1 is padded node i
    t[d] = static_cast<float>(u[d] - i);
  }
  const float* c0 = coef_.data() + padded_offset(base);
  const CubicBSplineWeights wx(t[0]), wy(t[1]);
  const std::ptrdiff_t row_stride = static_cast<std::ptrdiff_t>(padded_[0]) * Channels;

  // Packet by packet (keeps the accumulators in registers): per plane, p = sum_j wy_j row_j and
  // its y derivatives; over planes, r = sum_k wz_k p and its z derivatives.
  Row r, ry, ryy, rz, rzz, ryz;
  const CubicBSplineWeights wz(Dim == 3 ? t[Dim - 1] : 0.0F);
  const std::ptrdiff_t plane_stride = row_stride * padded_[1];
  for (int q = 0; q < Channels; ++q) {
    Eigen::Array4f a = Eigen::Array4f::Zero(), ay = a, ayy = a, az = a, azz = a, ayz = a;
#pragma GCC unroll 4
    for (int k = 0; k < (Dim == 3 ? 4 : 1); ++k) {
      const float* plane = c0 + k * plane_stride + 4 * q;
      Eigen::Array4f p = Eigen::Array4f::Zero(), py = p, pyy = p;
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j) {
        const Eigen::Array4f row = Eigen::Map<const Eigen::Array4f>(plane + j * row_stride);
        p += wy.w[j] * row;
        if constexpr (kGradient) py += wy.dw[j] * row;
        if constexpr (kHessian) pyy += wy.ddw[j] * row;
      }
      if constexpr (Dim == 2) {
        a = p;
        ay = py;
        ayy = pyy;
      } else {
        a += wz.w[k] * p;
        if constexpr (kGradient) {
          ay += wz.w[k] * py;
          az += wz.dw[k] * p;
        }
        if constexpr (kHessian) {
          ayy += wz.w[k] * pyy;
          azz += wz.ddw[k] * p;
          ayz += wz.dw[k] * py;
        }
      }
    }
    r.p[q] = a;
    ry.p[q] = ay;
    ryy.p[q] = ayy;
    rz.p[q] = az;
    rzz.p[q] = azz;
    ryz.p[q] = ayz;
  }
  const Row ex = Row::spread(wx.w);
  if (value != nullptr) *value = r.dot(ex);
  if constexpr (kGradient) {
    const Row edx = Row::spread(wx.dw);
    gradient->col(0) = r.dot(edx);
    gradient->col(1) = ry.dot(ex);
    if constexpr (Dim == 3) gradient->col(2) = rz.dot(ex);
    if constexpr (kHessian) {
      const Eigen::Matrix<double, Channels, 1> xx = r.dot(Row::spread(wx.ddw)), xy = ry.dot(edx),
                                               yy = ryy.dot(ex);
      Eigen::Matrix<double, Channels, 1> xz, yz, zz;
      if constexpr (Dim == 3) {
        xz = rz.dot(edx);
        yz = ryz.dot(ex);
        zz = rzz.dot(ex);
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
}

}  // namespace vdtnav
