#include "vdtnav/map/vector_distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vdtnav {
namespace {

constexpr std::int64_t kInfinite = std::numeric_limits<std::int64_t>::max();
// Sentinels for the first pass: far enough that differences never win, small enough not to
// overflow int32 differences.
constexpr std::int32_t kBefore = std::numeric_limits<std::int32_t>::min() / 4;
constexpr std::int32_t kAfter = std::numeric_limits<std::int32_t>::max() / 4;

/// Scratch space of the 1D lower envelope, reused across lines.
struct EnvelopeScratch {
  std::vector<std::int32_t> site;
  std::vector<std::int64_t> height;  // A(v) = F(v) + v^2
  explicit EnvelopeScratch(int n)
      : site(static_cast<std::size_t>(n)), height(static_cast<std::size_t>(n)) {}
};

/// 1D squared-distance transform of sampled function F (kInfinite = no site) with argmin:
/// best[x] = argmin_v (x - v)^2 + F(v), d2[x] = that minimum; best = -1 when F has no site.
/// Felzenszwalb & Huttenlocher's lower envelope with exact integer predicates (no division).
/// d2 may be null when only the argmin is wanted.
/// \return whether the line had any site.
bool lower_envelope(int n, const std::int64_t* f, std::int32_t* best, std::int64_t* d2,
                    EnvelopeScratch& s) {
  std::int32_t* v = s.site.data();
  std::int64_t* a = s.height.data();
  int k = -1;  // top of the stack
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInfinite) continue;
    const std::int64_t aq = f[q] + std::int64_t{q} * q;
    // Pop v[k] while it is nowhere strictly below both neighbours: the intersection of
    // (v[k], q) is left of (or at) the intersection of (v[k-1], v[k]).
    while (k >= 1 && (aq - a[k]) * (v[k] - v[k - 1]) <= (a[k] - a[k - 1]) * (q - v[k])) --k;
    ++k;
    v[k] = q;
    a[k] = aq;
  }
  if (k < 0) {
    std::fill(best, best + n, -1);
    if (d2 != nullptr) std::fill(d2, d2 + n, kInfinite);
    return false;
  }
  const int top = k;
  k = 0;
  for (int x = 0; x < n; ++x) {
    // Parabola k+1 takes over once it is no higher: A_{k+1} - 2 x v_{k+1} <= A_k - 2 x v_k.
    while (k < top &&
           a[k + 1] - 2 * std::int64_t{x} * v[k + 1] <= a[k] - 2 * std::int64_t{x} * v[k])
      ++k;
    best[x] = v[k];
    if (d2 != nullptr) {
      const std::int64_t dx = x - v[k];
      d2[x] = dx * dx + (a[k] - std::int64_t{v[k]} * v[k]);
    }
  }
  return true;
}

/// First pass along the slowest axis, vectorised across the contiguous planes below it:
/// out[c] = index along that axis of the nearest occupied cell in c's line, or kBefore if none.
void nearest_along_slowest_axis(const std::uint8_t* occ, std::int32_t* out, int plane, int n) {
  std::vector<std::int32_t> mark(static_cast<std::size_t>(plane), kBefore);
  for (int j = 0; j < n; ++j) {
    const std::uint8_t* o = occ + static_cast<std::ptrdiff_t>(j) * plane;
    std::int32_t* r = out + static_cast<std::ptrdiff_t>(j) * plane;
    for (int i = 0; i < plane; ++i) {
      mark[i] = o[i] ? j : mark[i];
      r[i] = mark[i];
    }
  }
  std::fill(mark.begin(), mark.end(), kAfter);
  for (int j = n - 1; j >= 0; --j) {
    const std::uint8_t* o = occ + static_cast<std::ptrdiff_t>(j) * plane;
    std::int32_t* r = out + static_cast<std::ptrdiff_t>(j) * plane;
    for (int i = 0; i < plane; ++i) {
      mark[i] = o[i] ? j : mark[i];
      const std::int32_t before = r[i];
      r[i] = (mark[i] - j < j - before) ? mark[i] : before;
    }
  }
  // Lines without any occupied cell keep kAfter or kBefore; normalise to kBefore.
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(plane) * n; ++c) {
    if (out[c] == kAfter) out[c] = kBefore;
  }
}

Grid<std::int32_t, 2> feature_transform_2d(const OccupancyGrid<2>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1];
  Grid<std::int32_t, 2> nearest(occ.size(), occ.frame());
  std::int32_t* out = nearest.data();
  // Pass 1 (along y): row of the nearest occupied cell in the same column.
  nearest_along_slowest_axis(occ.data(), out, nx, ny);
  // Pass 2 (along x, contiguous rows): lower envelope over the columns.
  std::vector<std::int64_t> f(static_cast<std::size_t>(nx));
  std::vector<std::int32_t> best(static_cast<std::size_t>(nx)), rows(static_cast<std::size_t>(nx));
  EnvelopeScratch scratch(nx);
  for (int y = 0; y < ny; ++y) {
    std::int32_t* line = out + static_cast<std::ptrdiff_t>(y) * nx;
    for (int x = 0; x < nx; ++x) {
      rows[x] = line[x];
      const std::int64_t dy = y - line[x];
      f[x] = line[x] == kBefore ? kInfinite : dy * dy;
    }
    if (!lower_envelope(nx, f.data(), best.data(), nullptr, scratch)) {
      std::fill(line, line + nx, kNoFeature);
      continue;
    }
    for (int x = 0; x < nx; ++x) line[x] = best[x] + nx * rows[best[x]];
  }
  return nearest;
}

Grid<std::int32_t, 3> feature_transform_3d(const OccupancyGrid<3>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1], nz = occ.size()[2];
  const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(nx) * ny;
  Grid<std::int32_t, 3> nearest(occ.size(), occ.frame());
  std::int32_t* out = nearest.data();
  // Pass 1 (along z): z of the nearest occupied cell in the same (x, y) column.
  nearest_along_slowest_axis(occ.data(), out, static_cast<int>(plane), nz);
  // Pass 2 (along y, within each z slab): out <- linear index of the nearest in the (y,z) plane,
  // dist2 <- its squared distance.
  std::vector<std::int32_t> dist2(static_cast<std::size_t>(plane) * nz);
  const int n_max = std::max(nx, ny);
  std::vector<std::int64_t> f(static_cast<std::size_t>(n_max)), d2(static_cast<std::size_t>(n_max));
  std::vector<std::int32_t> best(static_cast<std::size_t>(n_max)),
      feat(static_cast<std::size_t>(n_max));
  EnvelopeScratch scratch(n_max);
  constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
  for (int z = 0; z < nz; ++z) {
    std::int32_t* slab = out + z * plane;
    std::int32_t* slab_d2 = dist2.data() + z * plane;
    for (int x = 0; x < nx; ++x) {
      for (int y = 0; y < ny; ++y) {
        const std::int32_t zf = slab[x + static_cast<std::ptrdiff_t>(y) * nx];
        feat[y] = zf;
        const std::int64_t dz = z - zf;
        f[y] = zf == kBefore ? kInfinite : dz * dz;
      }
      const bool any = lower_envelope(ny, f.data(), best.data(), d2.data(), scratch);
      for (int y = 0; y < ny; ++y) {
        const std::ptrdiff_t c = x + static_cast<std::ptrdiff_t>(y) * nx;
        if (!any) {
          slab[c] = kNoFeature;
          slab_d2[c] = kFar;
          continue;
        }
        const std::int32_t yb = best[y];
        slab[c] =
            static_cast<std::int32_t>(x + static_cast<std::ptrdiff_t>(yb) * nx + feat[yb] * plane);
        slab_d2[c] = static_cast<std::int32_t>(d2[y]);
      }
    }
  }
  // Pass 3 (along x, contiguous): lower envelope over the squared distances of pass 2.
  for (std::ptrdiff_t l = 0; l < plane / nx * nz; ++l) {
    std::int32_t* line = out + l * nx;
    const std::int32_t* line_d2 = dist2.data() + l * nx;
    for (int x = 0; x < nx; ++x) {
      feat[x] = line[x];
      f[x] = line_d2[x] == kFar ? kInfinite : line_d2[x];
    }
    if (!lower_envelope(nx, f.data(), best.data(), nullptr, scratch)) continue;  // stays kNoFeature
    for (int x = 0; x < nx; ++x) line[x] = feat[best[x]];
  }
  return nearest;
}

}  // namespace

template <>
Grid<std::int32_t, 2> nearest_occupied_cells<2>(const OccupancyGrid<2>& occupied) {
  return feature_transform_2d(occupied);
}
template <>
Grid<std::int32_t, 3> nearest_occupied_cells<3>(const OccupancyGrid<3>& occupied) {
  return feature_transform_3d(occupied);
}

template <int Dim>
Grid<Eigen::Matrix<float, Dim, 1>, Dim> vector_distance_transform(
    const Grid<std::int32_t, Dim>& nearest) {
  using V = Eigen::Matrix<float, Dim, 1>;
  Grid<V, Dim> dt(nearest.size(), nearest.frame(), V::Zero());
  const float res = static_cast<float>(nearest.resolution());
  for (std::size_t c = 0; c < nearest.num_cells(); ++c) {
    const std::int32_t f = nearest[c];
    if (f == kNoFeature) {
      dt[c] = V::Constant(std::numeric_limits<float>::quiet_NaN());
      continue;
    }
    const auto i = nearest.index_of(static_cast<std::ptrdiff_t>(c));
    const auto j = nearest.index_of(f);
    dt[c] = (i - j).template cast<float>() * res;
  }
  return dt;
}

template <int Dim>
Grid<float, Dim> unsigned_distance_transform(const Grid<std::int32_t, Dim>& nearest) {
  Grid<float, Dim> dt(nearest.size(), nearest.frame(), 0.0F);
  const double res = nearest.resolution();
  for (std::size_t c = 0; c < nearest.num_cells(); ++c) {
    const std::int32_t f = nearest[c];
    if (f == kNoFeature) {
      dt[c] = std::numeric_limits<float>::infinity();
      continue;
    }
    const typename SpaceTraits<Dim>::Index d =
        nearest.index_of(static_cast<std::ptrdiff_t>(c)) - nearest.index_of(f);
    dt[c] = static_cast<float>(std::sqrt(static_cast<double>(d.squaredNorm())) * res);
  }
  return dt;
}

template <int Dim>
Grid<float, Dim> signed_distance_transform(const OccupancyGrid<Dim>& occupied) {
  OccupancyGrid<Dim> free_space(occupied.size(), occupied.frame());
  for (std::size_t c = 0; c < occupied.num_cells(); ++c) free_space[c] = occupied[c] ? 0 : 1;
  const Grid<float, Dim> d_occ = unsigned_distance_transform(nearest_occupied_cells(occupied));
  const Grid<float, Dim> d_free = unsigned_distance_transform(nearest_occupied_cells(free_space));
  const float half = static_cast<float>(occupied.resolution() / 2.0);
  Grid<float, Dim> sdt(occupied.size(), occupied.frame(), 0.0F);
  for (std::size_t c = 0; c < occupied.num_cells(); ++c) {
    sdt[c] = occupied[c] ? -(d_free[c] - half) : d_occ[c] - half;
  }
  return sdt;
}

template Grid<Eigen::Matrix<float, 2, 1>, 2> vector_distance_transform<2>(
    const Grid<std::int32_t, 2>&);
template Grid<Eigen::Matrix<float, 3, 1>, 3> vector_distance_transform<3>(
    const Grid<std::int32_t, 3>&);
template Grid<float, 2> unsigned_distance_transform<2>(const Grid<std::int32_t, 2>&);
template Grid<float, 3> unsigned_distance_transform<3>(const Grid<std::int32_t, 3>&);
template Grid<float, 2> signed_distance_transform<2>(const OccupancyGrid<2>&);
template Grid<float, 3> signed_distance_transform<3>(const OccupancyGrid<3>&);

}  // namespace vdtnav
