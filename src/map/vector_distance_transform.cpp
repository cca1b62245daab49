#include "vdtnav/map/vector_distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace vdtnav {
namespace {

// Sentinels for the first pass: far enough that differences never win, small enough not to
// overflow int32 differences.
constexpr std::int32_t kBefore = std::numeric_limits<std::int32_t>::min() / 4;
constexpr std::int32_t kAfter = std::numeric_limits<std::int32_t>::max() / 4;

/// Lower envelope of the parabolas y = (x - q)^2 + F(q) over integer sites q, added in increasing
/// q (Felzenszwalb & Huttenlocher), each carrying a payload (the feature it stands for). The
/// predicates are exact integer cross-multiplications: no division, no rounding.
class LowerEnvelope {
 public:
  explicit LowerEnvelope(int n)
      : site_(static_cast<std::size_t>(n)),
        height_(static_cast<std::size_t>(n)),
        payload_(static_cast<std::size_t>(n)) {}

  void reset() noexcept { top_ = -1; }
  [[nodiscard]] bool empty() const noexcept { return top_ < 0; }

  /// Adds site q with F(q) = f. Pops the top while it is nowhere strictly below both neighbours:
  /// the intersection of (top, q) is left of (or at) that of (top-1, top). With A = F + q^2,
  /// the intersection of (u, w) is (A_w - A_u) / (2 (w - u)).
  void push(int q, std::int64_t f, std::int32_t payload) noexcept {
    const std::int64_t aq = f + std::int64_t{q} * q;
    std::int32_t* v = site_.data();
    std::int64_t* a = height_.data();
    int k = top_;
    const auto hidden = [&](int i) {
      return (aq - a[i]) * (v[i] - v[i - 1]) <= (a[i] - a[i - 1]) * (q - v[i]);
    };
    if (k >= 1) {
      // About half the pushes pop once and a fifth more than once: the first pop is taken
      // without a branch, so the loop below usually exits at once (a predictable branch).
      k -= static_cast<int>(hidden(k));
      while (k >= 1 && hidden(k)) --k;
    }
    ++k;
    v[k] = q;
    a[k] = aq;
    payload_[k] = payload;
    top_ = k;
  }

  /// Calls out(x, payload, squared distance) for x = 0 .. n-1 in order (not empty()).
  template <typename Out>
  void sweep(int n, Out&& out) const {
    const std::int32_t* v = site_.data();
    const std::int64_t* a = height_.data();
    int k = 0;
    for (int x = 0; x < n; ++x) {
      // Parabola k+1 takes over once it is no higher: A_{k+1} - 2 x v_{k+1} <= A_k - 2 x v_k.
      while (k < top_ &&
             a[k + 1] - 2 * std::int64_t{x} * v[k + 1] <= a[k] - 2 * std::int64_t{x} * v[k])
        ++k;
      const std::int64_t dx = x - v[k];
      out(x, payload_[k], dx * dx + a[k] - std::int64_t{v[k]} * v[k]);
    }
  }

  /// Writes the payload of the lowest parabola at every x = 0 .. n-1 to dst[x] (not empty()).
  /// Segment by segment: parabola k+1 takes over from k at the first integer x with
  /// 2 x (v_{k+1} - v_k) >= A_{k+1} - A_k, found by a division and made exact by integer checks.
  void fill_payloads(int n, std::int32_t* dst) const {
    const std::int32_t* v = site_.data();
    const std::int64_t* a = height_.data();
    int x = 0;
    for (int k = 0; k < top_ && x < n; ++k) {
      const std::int64_t num = a[k + 1] - a[k], den = 2 * std::int64_t{v[k + 1] - v[k]};
      auto takes_over = [&](std::int64_t at) { return at * den >= num; };
      std::int64_t end =
          static_cast<std::int64_t>(std::ceil(static_cast<double>(num) / static_cast<double>(den)));
      while (end > x && takes_over(end - 1)) --end;
      while (!takes_over(end)) ++end;
      const int stop = static_cast<int>(std::min<std::int64_t>(end, n));
      if (stop > x) {
        std::fill(dst + x, dst + stop, payload_[k]);
        x = stop;
      }
    }
    std::fill(dst + x, dst + n, payload_[top_]);
  }

 private:
  std::vector<std::int32_t> site_;
  std::vector<std::int64_t> height_;
  std::vector<std::int32_t> payload_;
  int top_ = -1;
};

/// F of a position that holds no site: large enough that no neighbour is ever hidden by it,
/// small enough that 2 F never overflows.
constexpr std::int64_t kNoSite = std::int64_t{1} << 60;

/// Whether the parabola of site q is never strictly below both of its neighbours' parabolas
/// (q - 1 and q + 1), so it can be left out of the envelope without changing any minimum:
/// q is strictly lowest only for (F_q - F_{q-1} - 1) / 2 < x - q < (F_{q+1} - F_q + 1) / 2, an
/// empty interval iff 2 F_q - F_{q-1} - F_{q+1} >= 2. The leftmost minimiser at any x is never
/// hidden, so leaving out every hidden site at once is exact.
inline bool hidden_by_neighbours(std::int64_t left, std::int64_t f, std::int64_t right) {
  return 2 * f - left - right >= 2;
}

/// First pass along the slowest axis, vectorised across the contiguous planes below it:
/// out[c] = index along that axis of the nearest occupied cell in c's line, or kBefore if none.
void nearest_along_slowest_axis(const std::uint8_t* occ, std::int32_t* out, std::ptrdiff_t plane,
                                int n) {
  std::vector<std::int32_t> mark(static_cast<std::size_t>(plane), kBefore);
  for (int j = 0; j < n; ++j) {
    const std::uint8_t* o = occ + j * plane;
    std::int32_t* r = out + j * plane;
    for (std::ptrdiff_t i = 0; i < plane; ++i) {
      mark[i] = o[i] ? j : mark[i];
      r[i] = mark[i];
    }
  }
  std::fill(mark.begin(), mark.end(), kAfter);
  for (int j = n - 1; j >= 0; --j) {
    const std::uint8_t* o = occ + j * plane;
    std::int32_t* r = out + j * plane;
    for (std::ptrdiff_t i = 0; i < plane; ++i) {
      mark[i] = o[i] ? j : mark[i];
      const std::int32_t before = r[i];
      const std::int32_t nearest = (mark[i] - j < j - before) ? mark[i] : before;
      r[i] = nearest == kAfter ? kBefore : nearest;  // a line without occupied cells: kBefore
    }
  }
}

Grid<std::int32_t, 2> feature_transform_2d(const OccupancyGrid<2>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1];
  Grid<std::int32_t, 2> nearest(occ.size(), occ.frame());
  std::int32_t* out = nearest.data();
  // Pass 1 (along y): row of the nearest occupied cell in the same column.
  nearest_along_slowest_axis(occ.data(), out, nx, ny);
  // Pass 2 (along x, contiguous rows): lower envelope over the columns, in place.
  LowerEnvelope envelope(nx);
  std::vector<std::int64_t> f(static_cast<std::size_t>(nx) + 2, kNoSite);  // f[x + 1], padded
  std::vector<int> candidates(static_cast<std::size_t>(nx));
  for (int y = 0; y < ny; ++y) {
    std::int32_t* line = out + static_cast<std::ptrdiff_t>(y) * nx;
    for (int x = 0; x < nx; ++x) {
      const std::int64_t dy = y - line[x];
      f[x + 1] = line[x] == kBefore ? kNoSite : dy * dy;
    }
    // Candidate sites, compacted without branches (the filter is unpredictable).
    int m = 0;
    for (int x = 0; x < nx; ++x) {
      candidates[m] = x;
      m += (f[x + 1] != kNoSite) & !hidden_by_neighbours(f[x], f[x + 1], f[x + 2]);
    }
    if (m == 0) {
      std::fill(line, line + nx, kNoFeature);
      continue;
    }
    envelope.reset();
    for (int i = 0; i < m; ++i) {
      const int x = candidates[i];
      envelope.push(x, f[x + 1], x + nx * line[x]);
    }
    envelope.fill_payloads(nx, line);
  }
  return nearest;
}

Grid<std::int32_t, 3> feature_transform_3d(const OccupancyGrid<3>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1], nz = occ.size()[2];
  const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(nx) * ny;
  Grid<std::int32_t, 3> nearest(occ.size(), occ.frame());
  std::int32_t* out = nearest.data();
  // Pass 1 (along z): z of the nearest occupied cell in the same (x, y) column.
  nearest_along_slowest_axis(occ.data(), out, plane, nz);
  // Pass 2 (along y, within each z slab): out <- linear index of the nearest in the (y,z) plane,
  // dist2 <- its squared distance.
  std::vector<std::int32_t> dist2(static_cast<std::size_t>(plane) * nz);
  LowerEnvelope envelope(std::max(nx, ny));
  constexpr std::int32_t kFar = std::numeric_limits<std::int32_t>::max();
  for (int z = 0; z < nz; ++z) {
    std::int32_t* slab = out + z * plane;
    std::int32_t* slab_d2 = dist2.data() + z * plane;
    for (int x = 0; x < nx; ++x) {
      envelope.reset();
      for (int y = 0; y < ny; ++y) {
        const std::int32_t zf = slab[x + static_cast<std::ptrdiff_t>(y) * nx];
        if (zf == kBefore) continue;
        const std::int64_t dz = z - zf;
        envelope.push(
            y, dz * dz,
            static_cast<std::int32_t>(x + static_cast<std::ptrdiff_t>(y) * nx + zf * plane));
      }
      if (envelope.empty()) {
        for (int y = 0; y < ny; ++y) {
          slab[x + static_cast<std::ptrdiff_t>(y) * nx] = kNoFeature;
          slab_d2[x + static_cast<std::ptrdiff_t>(y) * nx] = kFar;
        }
        continue;
      }
      envelope.sweep(ny, [&](int y, std::int32_t feature, std::int64_t d2) {
        slab[x + static_cast<std::ptrdiff_t>(y) * nx] = feature;
        slab_d2[x + static_cast<std::ptrdiff_t>(y) * nx] = static_cast<std::int32_t>(d2);
      });
    }
  }
  // Pass 3 (along x, contiguous): lower envelope over the squared distances of pass 2.
  for (std::ptrdiff_t l = 0; l < plane / nx * nz; ++l) {
    std::int32_t* line = out + l * nx;
    const std::int32_t* line_d2 = dist2.data() + l * nx;
    envelope.reset();
    for (int x = 0; x < nx; ++x) {
      if (line_d2[x] != kFar) envelope.push(x, line_d2[x], line[x]);
    }
    if (envelope.empty()) continue;  // stays kNoFeature
    envelope.sweep(nx, [line](int x, std::int32_t feature, std::int64_t) { line[x] = feature; });
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

template <int Dim>
OccupancyGrid<Dim> surface_cells(const OccupancyGrid<Dim>& occupied) {
  OccupancyGrid<Dim> surface(occupied.size(), occupied.frame(), 0);
  bool any = false;
  for (std::size_t c = 0; c < occupied.num_cells(); ++c) {
    if (!occupied[c]) continue;
    const auto i = occupied.index_of(static_cast<std::ptrdiff_t>(c));
    bool exposed = false;
    for (int d = 0; d < Dim && !exposed; ++d) {
      for (int step : {-1, 1}) {
        auto j = i;
        j[d] += step;
        if (occupied.contains(j) && !occupied(j)) exposed = true;
      }
    }
    surface[c] = exposed ? 1 : 0;
    any |= exposed;
  }
  return any ? surface : occupied;
}

template OccupancyGrid<2> surface_cells<2>(const OccupancyGrid<2>&);
template OccupancyGrid<3> surface_cells<3>(const OccupancyGrid<3>&);
template Grid<Eigen::Matrix<float, 2, 1>, 2> vector_distance_transform<2>(
    const Grid<std::int32_t, 2>&);
template Grid<Eigen::Matrix<float, 3, 1>, 3> vector_distance_transform<3>(
    const Grid<std::int32_t, 3>&);
template Grid<float, 2> unsigned_distance_transform<2>(const Grid<std::int32_t, 2>&);
template Grid<float, 3> unsigned_distance_transform<3>(const Grid<std::int32_t, 3>&);
template Grid<float, 2> signed_distance_transform<2>(const OccupancyGrid<2>&);
template Grid<float, 3> signed_distance_transform<3>(const OccupancyGrid<3>&);

}  // namespace vdtnav
