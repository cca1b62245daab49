#include "vdtnav/map/vdt_map.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "vdt_lookup_kernels.hpp"
#include "vdtnav/core/parallel.hpp"

namespace vdtnav {
namespace {

/// In-place natural-end cubic B-spline prefilter along one axis of a compact array laid out as
/// [outer][n][inner]: solves (c_{k-1} + 4 c_k + c_{k+1}) / 6 = f_k, c_0 = f_0, c_{n-1} = f_{n-1}
/// (Thomas algorithm; the inner loop runs across lines so it vectorises).
void prefilter_axis(float* data, std::ptrdiff_t outer, int n, std::ptrdiff_t inner) {
  if (n < 3) return;                                         // c = f
  std::vector<float> cp(static_cast<std::size_t>(n), 0.0F);  // c'_k = 1 / (4 - c'_{k-1}), c'_0 = 0
  for (int k = 1; k < n - 1; ++k) cp[k] = 1.0F / (4.0F - cp[k - 1]);
  // The lines are independent: the pool's threads take pieces of ~kWork floats, ranges of the
  // inner lines of one block (the last axis: one block) or of whole blocks (the first: 1-3 lines
  // a block). Each line's arithmetic is the same in any piece.
  constexpr std::ptrdiff_t kWork = std::ptrdiff_t{1} << 16;
  const std::ptrdiff_t inner_piece =
      std::min<std::ptrdiff_t>(inner, std::max<std::ptrdiff_t>(1024, kWork / n));
  const std::ptrdiff_t inner_pieces = (inner + inner_piece - 1) / inner_piece;
  const std::ptrdiff_t outer_piece = std::max<std::ptrdiff_t>(1, kWork / (inner_piece * n));
  const std::ptrdiff_t outer_pieces = (outer + outer_piece - 1) / outer_piece;
  parallel_for(static_cast<std::size_t>(outer_pieces * inner_pieces), [&](std::size_t piece) {
    const std::ptrdiff_t p = static_cast<std::ptrdiff_t>(piece);
    const std::ptrdiff_t o0 = (p / inner_pieces) * outer_piece;
    const std::ptrdiff_t o1 = std::min(outer, o0 + outer_piece);
    const std::ptrdiff_t i0 = (p % inner_pieces) * inner_piece;
    const std::ptrdiff_t i1 = std::min(inner, i0 + inner_piece);
    for (std::ptrdiff_t o = o0; o < o1; ++o) {
      float* block = data + o * n * inner;
      for (int k = 1; k < n - 1; ++k) {
        float* cur = block + k * inner;
        const float* prev = cur - inner;
        for (std::ptrdiff_t i = i0; i < i1; ++i) cur[i] = (6.0F * cur[i] - prev[i]) * cp[k];
      }
      for (int k = n - 2; k >= 1; --k) {
        float* cur = block + k * inner;
        const float* next = cur + inner;
        for (std::ptrdiff_t i = i0; i < i1; ++i) cur[i] -= cp[k] * next[i];
      }
    }
  });
}

/// Fills the ghost layer along `axis` of a padded array [outer][n+2][inner] by linear
/// extrapolation (natural ends): c_{-1} = 2 c_0 - c_1, c_n = 2 c_{n-1} - c_{n-2}.
void fill_ghosts(float* data, std::ptrdiff_t outer, int n, std::ptrdiff_t inner) {
  for (std::ptrdiff_t o = 0; o < outer; ++o) {
    float* b = data + o * (n + 2) * inner;
    for (std::ptrdiff_t i = 0; i < inner; ++i) {
      b[i] = 2.0F * b[inner + i] - b[2 * inner + i];
      b[(n + 1) * inner + i] = 2.0F * b[n * inner + i] - b[(n - 1) * inner + i];
    }
  }
}

}  // namespace

template <int Dim, int Channels>
CubicBSplineField<Dim, Channels>::CubicBSplineField(const Index& size, std::vector<float> samples)
    : size_(size),
      padded_(size + Index::Constant(2)),
      hull_max_((size.array() - 1).template cast<double>()) {
  std::ptrdiff_t n = 1;
  for (int d = 0; d < Dim; ++d) {
    VDTNAV_CHECK(size[d] >= 2, "a cubic B-spline field needs at least 2 nodes along every axis");
    n *= size[d];
  }
  VDTNAV_CHECK(static_cast<std::ptrdiff_t>(samples.size()) == n * Channels,
               "cubic B-spline field: sample count does not match the lattice size");
  // Prefilter each axis on the compact array.
  std::ptrdiff_t inner = Channels;
  for (int d = 0; d < Dim; ++d) {
    const std::ptrdiff_t outer = n * Channels / (inner * size[d]);
    prefilter_axis(samples.data(), outer, size[d], inner);
    inner *= size[d];
  }
  // Copy into the padded lattice, then extrapolate the ghosts axis by axis.
  std::ptrdiff_t np = 1;
  for (int d = 0; d < Dim; ++d) np *= padded_[d];
  coef_.assign(static_cast<std::size_t>(np * Channels), 0.0F);
  const std::ptrdiff_t line = static_cast<std::ptrdiff_t>(size[0]) * Channels;
  const std::ptrdiff_t lines = n / size[0];
  parallel_for_ranges(static_cast<std::size_t>(lines), 256, [&](std::size_t l0, std::size_t l1) {
    for (std::ptrdiff_t l = static_cast<std::ptrdiff_t>(l0); l < static_cast<std::ptrdiff_t>(l1);
         ++l) {
      Index node = Index::Ones();  // padded node of (0, l...)
      std::ptrdiff_t rest = l;
      for (int d = 1; d < Dim; ++d) {
        node[d] = static_cast<int>(rest % size[d]) + 1;
        rest /= size[d];
      }
      std::copy(samples.begin() + l * line, samples.begin() + (l + 1) * line,
                coef_.begin() + padded_offset(node));
    }
  });
  inner = Channels;
  for (int d = 0; d < Dim; ++d) {
    const std::ptrdiff_t outer = np * Channels / (inner * padded_[d]);
    fill_ghosts(coef_.data(), outer, size[d], inner);
    inner *= padded_[d];
  }
}

template <int Dim, int Channels>
CubicBSplineField<Dim, Channels> CubicBSplineField<Dim, Channels>::from_coefficients(
    const Index& size, std::vector<float> coefficients) {
  CubicBSplineField f;
  std::ptrdiff_t np = 1;
  for (int d = 0; d < Dim; ++d) {
    VDTNAV_CHECK(size[d] >= 2, "a cubic B-spline field needs at least 2 nodes along every axis");
    np *= size[d] + 2;
  }
  VDTNAV_CHECK(static_cast<std::ptrdiff_t>(coefficients.size()) == np * Channels,
               "cubic B-spline field: coefficient count does not match the lattice size");
  f.size_ = size;
  f.padded_ = size + Index::Constant(2);
  f.hull_max_ = (size.array() - 1).template cast<double>();
  f.coef_ = std::move(coefficients);
  return f;
}

template <int Dim>
VdtMap<Dim>::VdtMap(Grid<std::int32_t, Dim> nearest, Field field)
    : nearest_(std::move(nearest)), field_(std::move(field)) {
  VDTNAV_CHECK(nearest_.size() == field_.size(), "VdtMap: feature grid and field sizes differ");
}

template <int Dim>
VdtMap<Dim> VdtMap<Dim>::build(const OccupancyGrid<Dim>& occupied, bool all_occupied_cells) {
  for (int d = 0; d < Dim; ++d) {
    VDTNAV_CHECK(occupied.size()[d] >= 2,
                 "VdtMap: the map needs at least 2 cells along every axis");
  }
  Grid<std::int32_t, Dim> nearest =
      nearest_occupied_cells(all_occupied_cells ? occupied : surface_cells(occupied));
  VDTNAV_CHECK(nearest[0] != kNoFeature,
               "VdtMap: the map has no occupied cell, so its distance transform is undefined");
  // Samples of DT_v at the cell centres, in the grid's own axes (metres).
  std::vector<float> samples(nearest.num_cells() * Dim);
  const float res = static_cast<float>(occupied.resolution());
  parallel_for_ranges(nearest.num_cells(), std::size_t{1} << 15,
                      [&](std::size_t c0, std::size_t c1) {
                        Index i = nearest.index_of(static_cast<std::ptrdiff_t>(c0));
                        for (std::size_t c = c0; c < c1; ++c) {
                          const Index j = nearest.index_of(nearest[c]);
                          for (int d = 0; d < Dim; ++d)
                            samples[c * Dim + d] = static_cast<float>(i[d] - j[d]) * res;
                          for (int d = 0; d < Dim; ++d) {  // advance i (x fastest)
                            if (++i[d] < occupied.size()[d]) break;
                            i[d] = 0;
                          }
                        }
                      });
  Field field(occupied.size(), std::move(samples));
  return VdtMap(std::move(nearest), std::move(field));
}

template <int Dim>
void VdtMap<Dim>::evaluate(const Vector* p, std::size_t n, VdtSample<Dim>* out,
                           bool jacobian) const {
  if (detail::evaluate_simd(*this, p, n, out, jacobian)) return;
  for (std::size_t k = 0; k < n; ++k) out[k] = evaluate_portable(p[k], jacobian);
}

template <int Dim>
VdtSampleWithHessian<Dim> VdtMap<Dim>::evaluate_with_hessian(const Vector& p) const {
  VdtSampleWithHessian<Dim> s;
  typename Field::Hessians h;
  Vector u = frame().continuous_index(p);
  s.inside = field_.clamp(u);
  field_.evaluate(u, &s.value, &s.jacobian, &h);
  to_world(s);
  const double inv_res2 = frame().inv_resolution() * frame().inv_resolution();
  if (frame().axis_aligned()) {
    for (int c = 0; c < Dim; ++c) s.hessian[c] = h[c] * inv_res2;
  } else {
    // World component c = sum_a R(c,a) * grid component a; each grid Hessian transforms as
    // R H R^T / res^2.
    const Matrix& r = frame().rotation();
    for (int c = 0; c < Dim; ++c) {
      s.hessian[c].setZero();
      for (int a = 0; a < Dim; ++a) s.hessian[c] += r(c, a) * (r * h[a] * r.transpose());
      s.hessian[c] *= inv_res2;
    }
  }
  return s;
}

template <int Dim>
typename VdtMap<Dim>::Vector VdtMap<Dim>::nearest_occupied_point(const Vector& p) const {
  Index cell = nearest_.cell_of(p);
  cell = cell.cwiseMax(Index::Zero()).cwiseMin(size() - Index::Ones());
  return nearest_.cell_center(nearest_.index_of(nearest_(cell)));
}

template <int Dim>
VdtSample<Dim> VdtMap<Dim>::nearest_point_query(const Vector& p) const {
  VdtSample<Dim> s;
  s.inside = nearest_.contains(nearest_.cell_of(p));
  s.value = p - nearest_occupied_point(p);
  s.jacobian.setIdentity();
  return s;
}

template <int Dim>
DistanceFieldMap<Dim>::DistanceFieldMap(const Grid<float, Dim>& samples) : frame_(samples.frame()) {
  for (float v : samples.values()) {
    VDTNAV_CHECK(std::isfinite(v), "DistanceFieldMap: every sample must be finite (empty map?)");
  }
  field_ = Field(samples.size(), samples.values());
}

template <int Dim>
typename DistanceFieldMap<Dim>::Sample DistanceFieldMap<Dim>::evaluate(const Vector& p,
                                                                       bool with_hessian) const {
  Sample s;
  Vector u = frame_.continuous_index(p);
  s.inside = field_.clamp(u);
  typename Field::Values v;
  typename Field::Jacobian j;
  typename Field::Hessians h;
  field_.evaluate(u, &v, &j, with_hessian ? &h : nullptr);
  const double inv_res = frame_.inv_resolution();
  s.value = v[0];
  const Vector g_grid = j.transpose() * inv_res;
  s.gradient = frame_.axis_aligned() ? g_grid : Vector(frame_.rotation() * g_grid);
  if (with_hessian) {
    const Matrix hg = h[0] * inv_res * inv_res;
    s.hessian =
        frame_.axis_aligned() ? hg : Matrix(frame_.rotation() * hg * frame_.rotation().transpose());
  }
  return s;
}

template class CubicBSplineField<2, 1>;
template class CubicBSplineField<3, 1>;
template class CubicBSplineField<2, 2>;
template class CubicBSplineField<3, 3>;
template class VdtMap<2>;
template class VdtMap<3>;
template class DistanceFieldMap<2>;
template class DistanceFieldMap<3>;

}  // namespace vdtnav
