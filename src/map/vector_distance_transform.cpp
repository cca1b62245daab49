#include "vdtnav/map/vector_distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "vdtnav/core/parallel.hpp"

namespace vdtnav {
namespace {

// Sentinels of the sweeps along the slowest axis: far enough that differences never win, small
// enough not to overflow int32 differences.
constexpr std::int32_t kBefore = std::numeric_limits<std::int32_t>::min() / 4;
constexpr std::int32_t kAfter = std::numeric_limits<std::int32_t>::max() / 4;

/// F (squared distance) of a position that holds no site, in the type Dist the squared distances
/// are carried in. It exceeds every squared distance inside the grids that use Dist, so such a
/// position is never nearest, and 4 kValue still fits Dist, so the pruning never overflows.
template <typename Dist>
struct NoSite;
template <>
struct NoSite<std::int32_t> {
  static constexpr std::int32_t kValue = (std::int32_t{1} << 29) - 1;
};
template <>
struct NoSite<std::int64_t> {
  static constexpr std::int64_t kValue = (std::int64_t{1} << 61) - 1;
};

/// Largest squared distance between two cells of a grid of the given size.
template <int Dim>
std::int64_t squared_diagonal(const typename SpaceTraits<Dim>::Index& size) {
  std::int64_t d2 = 0;
  for (int d = 0; d < Dim; ++d) d2 += std::int64_t{size[d] - 1} * (size[d] - 1);
  return d2;
}

/// Lower envelope of the parabolas y = (x - q)^2 + F(q) over integer sites q, added in increasing
/// q (Felzenszwalb & Huttenlocher), each carrying a payload (the feature it stands for). The
/// predicates are exact integer cross-multiplications: no rounding.
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

  /// Calls segment(begin, end, q, F(q), payload) for the run [begin, end) of x = 0 .. n-1 where
  /// the parabola of site q is the lowest, in order (not empty()). Parabola k+1 takes over from k
  /// at the first integer x with 2 x (v_{k+1} - v_k) >= A_{k+1} - A_k: an exact ceiling division.
  template <typename Segment>
  void for_each_segment(int n, Segment&& segment) const {
    const std::int32_t* v = site_.data();
    const std::int64_t* a = height_.data();
    const auto emit = [&](int k, int begin, int end) {
      segment(begin, end, v[k], a[k] - std::int64_t{v[k]} * v[k], payload_[k]);
    };
    int x = 0;
    for (int k = 0; k < top_ && x < n; ++k) {
      const std::int64_t num = a[k + 1] - a[k], den = 2 * std::int64_t{v[k + 1] - v[k]};
      const std::int64_t quotient = num / den;  // truncated: the ceiling when not exact and < 0
      const std::int64_t takes_over = quotient + static_cast<std::int64_t>(quotient * den < num);
      const int stop = static_cast<int>(std::min<std::int64_t>(takes_over, n));
      if (stop > x) {
        emit(k, x, stop);
        x = stop;
      }
    }
    if (x < n) emit(top_, x, n);
  }

 private:
  std::vector<std::int32_t> site_;
  std::vector<std::int64_t> height_;
  std::vector<std::int32_t> payload_;
  int top_ = -1;
};

/// Whether the parabola of site q is nowhere strictly below both those of l < q < r, at
/// distances d1 = q - l and d2 = r - q. With A = F + x^2, q is below l right of
/// (A_q - A_l) / (2 d1) and below r left of (A_r - A_q) / (2 d2); that interval is empty iff
/// (F_q - F_l) d2 - (F_r - F_q) d1 >= d1 d2 (d1 + d2).
template <int D1, int D2, typename Dist>
inline bool hidden_by(Dist left, Dist f, Dist right) {
  return (f - left) * D2 - (right - f) * D1 >= D1 * D2 * (D1 + D2);
}

/// The real sites of f[0, n) (F < NoSite) not hidden by a pair of sites at most two positions
/// away, written to sites[], their count returned; f is padded with NoSite at f[-2], f[-1], f[n],
/// f[n+1]. Leaving them all out keeps every minimum: at any x, the leftmost minimiser is strictly
/// below every site to its left and no higher than any to its right, so no pair hides it (pairs
/// with positions holding no site included, as NoSite exceeds every minimum). In BM_VdtBuild2D
/// this keeps 39 % of the sites of a line (60 % with the nearest neighbours only, 29 % with pairs
/// three positions away), and the pushes into the envelope are what costs. The mask is computed
/// first by a vectorisable loop, then the sites are compacted without branches (the mask is
/// unpredictable).
template <typename Dist>
int visible_sites(const Dist* f, int n, std::uint8_t* keep, std::int32_t* sites) {
  for (int x = 0; x < n; ++x) {
    const Dist l2 = f[x - 2], l1 = f[x - 1], q = f[x], r1 = f[x + 1], r2 = f[x + 2];
    const bool hidden = hidden_by<1, 1>(l1, q, r1) | hidden_by<1, 2>(l1, q, r2) |
                        hidden_by<2, 1>(l2, q, r1) | hidden_by<2, 2>(l2, q, r2);
    keep[x] = static_cast<std::uint8_t>((q != NoSite<Dist>::kValue) & !hidden);
  }
  int m = 0;
  for (int x = 0; x < n; ++x) {
    sites[m] = x;
    m += keep[x];
  }
  return m;
}

/// The exact transform of one line: F along it in, the lower envelope of its visible sites out.
template <typename Dist>
class LineTransform {
 public:
  explicit LineTransform(int n)
      : f_(static_cast<std::size_t>(n) + 4, NoSite<Dist>::kValue),
        keep_(static_cast<std::size_t>(n)),
        sites_(static_cast<std::size_t>(n)),
        envelope_(n) {}

  /// F of the line, to be filled at [0, n) (the two padding positions either side stay NoSite).
  [[nodiscard]] Dist* f() noexcept { return f_.data() + 2; }

  /// Builds the envelope of the n first positions of f(), payload(x) the feature of site x;
  /// returns false when the line holds no site.
  template <typename Payload>
  bool build(int n, Payload&& payload) {
    const Dist* f = this->f();
    f_[static_cast<std::size_t>(n) + 2] = f_[static_cast<std::size_t>(n) + 3] =
        NoSite<Dist>::kValue;
    const int m = visible_sites(f, n, keep_.data(), sites_.data());
    envelope_.reset();
    for (int i = 0; i < m; ++i) {
      const int x = sites_[static_cast<std::size_t>(i)];
      envelope_.push(x, f[x], payload(x));
    }
    return m > 0;
  }

  [[nodiscard]] const LowerEnvelope& envelope() const noexcept { return envelope_; }

 private:
  std::vector<Dist> f_;
  std::vector<std::uint8_t> keep_;
  std::vector<std::int32_t> sites_;
  LowerEnvelope envelope_;
};

/// Forward sweep along the slowest axis over planes [j0, j1), vectorised across the contiguous
/// planes below it: out[c] = index along that axis of the last occupied cell at or before c in
/// c's line; `mark` holds, per line, the last one before j0 (kBefore if none) and is advanced.
void previous_occupied(const std::uint8_t* occ, std::int32_t* out, std::ptrdiff_t plane, int j0,
                       int j1, std::int32_t* mark) {
  for (int j = j0; j < j1; ++j) {
    const std::uint8_t* o = occ + j * plane;
    std::int32_t* r = out + j * plane;
    for (std::ptrdiff_t i = 0; i < plane; ++i) {
      mark[i] = o[i] ? j : mark[i];
      r[i] = mark[i];
    }
  }
}

/// Backward sweep along the slowest axis at plane j (planes are visited from the last one, so the
/// rest of the transform of plane j runs while it is in cache): next[i] <- the next occupied
/// index at or after j, out[i] <- the nearest occupied index (previous_occupied in, kAfter when
/// the line has none), f[i] <- its squared distance (NoSite when none).
template <typename Dist>
void nearest_occupied_at(const std::uint8_t* occ, int j, std::int32_t* next, std::int32_t* out,
                         Dist* f, std::ptrdiff_t plane) {
  for (std::ptrdiff_t i = 0; i < plane; ++i) {
    next[i] = occ[i] ? j : next[i];
    const std::int32_t nearest = (next[i] - j < j - out[i]) ? next[i] : out[i];
    const bool found = nearest != kAfter;
    const Dist d = found ? Dist{j - nearest} : Dist{0};
    out[i] = nearest;
    f[i] = found ? d * d : NoSite<Dist>::kValue;
  }
}

/// Fills row[begin, end) of a row of n cells with value. The runs of a lower envelope are a few
/// cells long (8 on average in BM_VdtBuild2D), too short for std::fill to pay: blocks of 4 are
/// stored instead, spilling up to 3 cells past end, which the next run overwrites.
inline void fill_run(std::int32_t* row, int begin, int end, int n, std::int32_t value) {
  if (end + 3 >= n) {
    std::fill(row + begin, row + end, value);
    return;
  }
  for (int x = begin; x < end; x += 4) {
    row[x] = value;
    row[x + 1] = value;
    row[x + 2] = value;
    row[x + 3] = value;
  }
}

/// Scratch of one block of planes: the line transform, and (3D) the squared distances of a plane
/// (2D: those of a row are the line's own f()).
template <typename Dist>
struct BlockScratch {
  BlockScratch(std::ptrdiff_t plane, int line_length, bool own_f)
      : f(own_f ? static_cast<std::size_t>(plane) : 0), line(line_length) {}
  [[nodiscard]] Dist* squared() noexcept { return f.empty() ? line.f() : f.data(); }
  std::vector<Dist> f;
  LineTransform<Dist> line;
};

/// Pass 1 and the passes of each plane over a grid of n planes of `plane` cells along its slowest
/// axis, in blocks of consecutive planes that the pool's threads finish independently (one block
/// with one thread: the sweeps as written). Pass 1 of a block needs, per line along the slowest
/// axis, the last occupied index before the block, and its backward sweep the first one after
/// it: each block finds its own first and last, then a block's seeds are its neighbours'. Every
/// pass is exact, so the transform is the same for any blocks. slab_pass(slab, scratch) finishes
/// a plane: its nearest cells along the slowest axis in, its features out (scratch.squared():
/// their squared distances).
template <typename Dist, typename SlabPass>
void transform_in_blocks(const std::uint8_t* occ, std::int32_t* out, std::ptrdiff_t plane, int n,
                         int line_length, bool own_f, SlabPass&& slab_pass) {
  constexpr int kMinPlanes = 16;  // per block: the seeds cost a plane each
  constexpr std::int64_t kMinCells = std::int64_t{1} << 16;  // below: not worth a wake-up
  const int t = threads();
  const int blocks = t > 1 && std::int64_t{n} * plane >= kMinCells
                         ? std::max(1, std::min(4 * t, n / kMinPlanes))
                         : 1;
  const auto begin = [n, blocks](std::size_t b) {
    return static_cast<int>(std::int64_t{n} * static_cast<std::int64_t>(b) / blocks);
  };
  const std::size_t plane_size = static_cast<std::size_t>(plane);
  // before[b]: per line, the last occupied index before block b; after[b]: the first after it.
  std::vector<std::int32_t> before(blocks * plane_size, kBefore),
      after(blocks * plane_size, kAfter);
  if (blocks > 1) {
    std::vector<std::int32_t> last(blocks * plane_size, kBefore),
        first(blocks * plane_size, kAfter);
    parallel_for(static_cast<std::size_t>(blocks), [&](std::size_t b) {
      std::int32_t* l = last.data() + b * plane_size;
      std::int32_t* f = first.data() + b * plane_size;
      for (int j = begin(b); j < begin(b + 1); ++j) {
        const std::uint8_t* o = occ + j * plane;
        for (std::ptrdiff_t i = 0; i < plane; ++i) l[i] = o[i] ? j : l[i];
      }
      for (int j = begin(b + 1) - 1; j >= begin(b); --j) {
        const std::uint8_t* o = occ + j * plane;
        for (std::ptrdiff_t i = 0; i < plane; ++i) f[i] = o[i] ? j : f[i];
      }
    });
    for (std::size_t b = 1; b < static_cast<std::size_t>(blocks); ++b) {
      for (std::size_t i = 0; i < plane_size; ++i) {  // kBefore < every index < kAfter
        before[b * plane_size + i] =
            std::max(before[(b - 1) * plane_size + i], last[(b - 1) * plane_size + i]);
      }
    }
    for (std::size_t b = static_cast<std::size_t>(blocks) - 1; b-- > 0;) {
      for (std::size_t i = 0; i < plane_size; ++i) {
        after[b * plane_size + i] =
            std::min(after[(b + 1) * plane_size + i], first[(b + 1) * plane_size + i]);
      }
    }
  }
  parallel_for(static_cast<std::size_t>(blocks), [&](std::size_t b) {
    const int j0 = begin(b), j1 = begin(b + 1);
    BlockScratch<Dist> scratch(plane, line_length, own_f);
    previous_occupied(occ, out, plane, j0, j1, before.data() + b * plane_size);
    std::int32_t* next = after.data() + b * plane_size;
    for (int j = j1 - 1; j >= j0; --j) {
      std::int32_t* slab = out + j * plane;
      nearest_occupied_at(occ + j * plane, j, next, slab, scratch.squared(), plane);
      slab_pass(slab, scratch);
    }
  });
}

template <typename Dist>
Grid<std::int32_t, 2> feature_transform_2d(const OccupancyGrid<2>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1];
  Grid<std::int32_t, 2> nearest(occ.size(), occ.frame());
  // Pass 1 (along y): row of the nearest occupied cell in the same column, finished row by row.
  // Pass 2 (along x, contiguous rows): lower envelope over the columns, in place.
  transform_in_blocks<Dist>(
      occ.data(), nearest.data(), nx, ny, nx, /*own_f=*/false,
      [nx](std::int32_t* row, BlockScratch<Dist>& scratch) {
        LineTransform<Dist>& line = scratch.line;
        if (!line.build(nx, [row, nx](int x) { return x + nx * row[x]; })) {
          std::fill(row, row + nx, kNoFeature);
          return;
        }
        line.envelope().for_each_segment(
            nx, [row, nx](int begin, int end, int, std::int64_t, std::int32_t feature) {
              fill_run(row, begin, end, nx, feature);
            });
      });
  return nearest;
}

template <typename Dist>
Grid<std::int32_t, 3> feature_transform_3d(const OccupancyGrid<3>& occ) {
  const int nx = occ.size()[0], ny = occ.size()[1], nz = occ.size()[2];
  const std::ptrdiff_t plane = static_cast<std::ptrdiff_t>(nx) * ny;
  Grid<std::int32_t, 3> nearest(occ.size(), occ.frame());
  // Pass 1 (along z): z of the nearest occupied cell in the same (x, y) column, finished slab by
  // slab; passes 2 and 3 then complete that slab while it is in cache.
  transform_in_blocks<Dist>(
      occ.data(), nearest.data(), plane, nz, std::max(nx, ny), /*own_f=*/true,
      [nx, ny, plane](std::int32_t* slab, BlockScratch<Dist>& scratch) {
        LineTransform<Dist>& line = scratch.line;
        Dist* f = line.f();
        Dist* slab_f = scratch.f.data();  // squared distances of the slab
        // Pass 2 (along y): slab <- feature nearest in the (y, z) plane, slab_f <- its squared
        // distance. The column is strided, but a slab's column stays in L1 for the next x.
        for (int x = 0; x < nx; ++x) {
          const auto at = [x, nx](int y) { return x + static_cast<std::ptrdiff_t>(y) * nx; };
          for (int y = 0; y < ny; ++y) f[y] = slab_f[at(y)];
          const bool any = line.build(
              ny, [&](int y) { return static_cast<std::int32_t>(at(y) + slab[at(y)] * plane); });
          if (!any) {
            for (int y = 0; y < ny; ++y) slab[at(y)] = kNoFeature;  // slab_f stays NoSite
            continue;
          }
          line.envelope().for_each_segment(
              ny, [&](int begin, int end, int q, std::int64_t fq, std::int32_t feature) {
                for (int y = begin; y < end; ++y) {
                  slab[at(y)] = feature;
                  const std::int64_t dy = y - q;
                  slab_f[at(y)] = static_cast<Dist>(dy * dy + fq);
                }
              });
        }
        // Pass 3 (along x, contiguous): lower envelope over the squared distances of pass 2.
        for (int y = 0; y < ny; ++y) {
          std::int32_t* row = slab + static_cast<std::ptrdiff_t>(y) * nx;
          std::copy_n(slab_f + static_cast<std::ptrdiff_t>(y) * nx, nx, f);
          if (!line.build(nx, [row](int x) { return row[x]; })) continue;  // stays kNoFeature
          line.envelope().for_each_segment(
              nx, [row, nx](int begin, int end, int, std::int64_t, std::int32_t feature) {
                fill_run(row, begin, end, nx, feature);
              });
        }
      });
  return nearest;
}

/// Whether every squared distance inside a grid of this size fits the int32 pruning.
template <int Dim>
bool fits_int32(const typename SpaceTraits<Dim>::Index& size) {
  return squared_diagonal<Dim>(size) < NoSite<std::int32_t>::kValue;
}

/// Checks that the int64 arithmetic holds: the envelope's cross-products stay below 2 D n < 2^63
/// (D the squared diagonal, n the longest side), which also keeps D below NoSite and the sides
/// below 2^21, far from the sweeps' sentinels. Only very long thin grids (a line of 2^21 cells)
/// fail it.
template <int Dim>
void check_int64_range(const typename SpaceTraits<Dim>::Index& size) {
  const std::int64_t longest = size.maxCoeff();
  VDTNAV_CHECK(squared_diagonal<Dim>(size) < ((std::int64_t{1} << 62) - 1) / longest,
               "nearest_occupied_cells: the grid is too long for exact int64 arithmetic");
}

}  // namespace

template <>
Grid<std::int32_t, 2> nearest_occupied_cells<2>(const OccupancyGrid<2>& occupied) {
  if (fits_int32<2>(occupied.size())) return feature_transform_2d<std::int32_t>(occupied);
  check_int64_range<2>(occupied.size());
  return feature_transform_2d<std::int64_t>(occupied);
}
template <>
Grid<std::int32_t, 3> nearest_occupied_cells<3>(const OccupancyGrid<3>& occupied) {
  if (fits_int32<3>(occupied.size())) return feature_transform_3d<std::int32_t>(occupied);
  check_int64_range<3>(occupied.size());
  return feature_transform_3d<std::int64_t>(occupied);
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
  constexpr std::size_t kGrain = std::size_t{1} << 15;
  std::vector<std::uint8_t> any((occupied.num_cells() + kGrain - 1) / kGrain, 0);
  parallel_for_ranges(occupied.num_cells(), kGrain, [&](std::size_t c0, std::size_t c1) {
    bool found = false;
    for (std::size_t c = c0; c < c1; ++c) {
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
      found |= exposed;
    }
    any[c0 / kGrain] = found ? 1 : 0;
  });
  return std::find(any.begin(), any.end(), 1) != any.end() ? surface : occupied;
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
