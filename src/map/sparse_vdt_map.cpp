#include "vdtnav/map/sparse_vdt_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <utility>

#include "vdt_lookup_kernels.hpp"
#include "vdtnav/core/parallel.hpp"
#include "vdtnav/map/cubic_bspline.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav {
namespace {

using Index = Eigen::Vector3i;
constexpr int kB = SparseVdtMap3::kBrick;

/// A sparse voxel set: a 512-bit mask (word z, bit 8 y + x) per brick that holds a voxel.
class VoxelSet {
 public:
  explicit VoxelSet(const Index& bricks)
      : bricks_(bricks), slot_(static_cast<std::size_t>(bricks.prod()), -1) {}

  void insert(const Index& v) {
    std::int32_t& s = slot_[linear(brick_of(v))];
    if (s < 0) {
      s = static_cast<std::int32_t>(masks_.size());
      masks_.push_back({});
      coords_.push_back(brick_of(v));
    }
    masks_[static_cast<std::size_t>(s)][v.z() & 7] |= bit(v);
  }
  /// v must lie in the brick lattice.
  [[nodiscard]] bool contains(const Index& v) const {
    const std::int32_t s = slot_[linear(brick_of(v))];
    return s >= 0 && (masks_[static_cast<std::size_t>(s)][v.z() & 7] & bit(v)) != 0;
  }
  [[nodiscard]] std::int32_t slot(const Index& brick) const { return slot_[linear(brick)]; }
  [[nodiscard]] std::size_t num_bricks() const { return masks_.size(); }
  [[nodiscard]] const Index& coord(std::size_t s) const { return coords_[s]; }
  /// Calls f(voxel) for every voxel of slot s.
  template <typename F>
  void for_each(std::size_t s, F&& f) const {
    const Index o = coords_[s] * kB;
    for (int z = 0; z < kB; ++z)
      for (std::uint64_t m = masks_[s][z]; m != 0; m &= m - 1) {
        const int b = __builtin_ctzll(m);
        f(Index(o.x() + (b & 7), o.y() + (b >> 3), o.z() + z));
      }
  }

 private:
  static Index brick_of(const Index& v) { return Index(v.x() >> 3, v.y() >> 3, v.z() >> 3); }
  static std::uint64_t bit(const Index& v) {
    return std::uint64_t{1} << (8 * (v.y() & 7) + (v.x() & 7));
  }
  [[nodiscard]] std::size_t linear(const Index& b) const {
    return (static_cast<std::size_t>(b.z()) * bricks_.y() + b.y()) * bricks_.x() + b.x();
  }

  Index bricks_;
  std::vector<std::int32_t> slot_;
  std::vector<std::array<std::uint64_t, 8>> masks_;
  std::vector<Index> coords_;
};

/// Per-axis weights of the 4 nodes s .. s+3 of a query's support, the natural-end ghosts folded
/// in: c_{-1} = 2 c_0 - c_1 and c_n = 2 c_{n-1} - c_{n-2} (CubicBSplineField's ghost layer) are
/// linear in the real nodes, so a support that reaches a ghost moves one node inwards and carries
/// the ghost's weight on its two neighbours. Needs n >= 4.
struct AxisSupport {
  int start;
  Eigen::Array4f w, dw;

  AxisSupport(double u, int n) {  // u in [0, n-1]
    int base = static_cast<int>(u);
    if (base > n - 2) base = n - 2;  // u == n-1: last span, t = 1
    const CubicBSplineWeights b(static_cast<float>(u - base));
    w = b.w;
    dw = b.dw;
    start = base - 1;
    if (base == 0) {
      start = 0;
      fold_low(w);
      fold_low(dw);
    } else if (base == n - 2) {
      start = n - 4;
      fold_high(w);
      fold_high(dw);
    }
  }
  static void fold_low(Eigen::Array4f& a) {  // nodes -1, 0, 1, 2 -> 0, 1, 2, 3
    a = Eigen::Array4f(a[1] + 2 * a[0], a[2] - a[0], a[3], 0.0F);
  }
  static void fold_high(Eigen::Array4f& a) {  // nodes n-3 .. n -> n-4 .. n-1
    a = Eigen::Array4f(0.0F, a[0], a[1] - a[3], a[2] + 2 * a[3]);
  }
};

/// The tensor-product sums of CubicBSplineField::evaluate_impl over a 4 x 4 x 4 support whose
/// rows (4 nodes x 3 channels, contiguous) start at c0 + j row_stride + k plane_stride: DT_v and
/// its Jacobian per unit index (row c = gradient of channel c).
template <bool kGradient>
void support_sum(const float* c0, std::ptrdiff_t row_stride, std::ptrdiff_t plane_stride,
                 const AxisSupport& x, const AxisSupport& y, const AxisSupport& z,
                 Eigen::Vector3d* value, Eigen::Matrix3d* jacobian) {
  using Row = detail::RowPackets<3>;
  Row r, ry, rz;
  for (int q = 0; q < 3; ++q) {
    Eigen::Array4f a = Eigen::Array4f::Zero(), ay = a, az = a;
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) {
      const float* plane = c0 + k * plane_stride + 4 * q;
      Eigen::Array4f p = Eigen::Array4f::Zero(), py = p;
#pragma GCC unroll 4
      for (int j = 0; j < 4; ++j) {
        const Eigen::Array4f row = Eigen::Map<const Eigen::Array4f>(plane + j * row_stride);
        p += y.w[j] * row;
        if constexpr (kGradient) py += y.dw[j] * row;
      }
      a += z.w[k] * p;
      if constexpr (kGradient) {
        ay += z.w[k] * py;
        az += z.dw[k] * p;
      }
    }
    r.p[q] = a;
    ry.p[q] = ay;
    rz.p[q] = az;
  }
  const Row ex = Row::spread(x.w);
  *value = r.dot(ex);
  if constexpr (kGradient) {
    jacobian->col(0) = r.dot(Row::spread(x.dw));
    jacobian->col(1) = ry.dot(ex);
    jacobian->col(2) = rz.dot(ex);
  }
}

/// Clamps a continuous index to the node hull [0, n-1] (NaN -> 0, which std::clamp would pass
/// through to an integer conversion). \return whether u was inside, as CubicBSplineField::clamp.
bool clamp_to_hull(const Index& size, Eigen::Vector3d* u) {
  constexpr double kHullTolerance = 1e-9;  // as CubicBSplineField::clamp
  bool inside = true;
  for (int d = 0; d < 3; ++d) {
    const double x = (*u)[d], hi = size[d] - 1.0;
    inside &= (x >= -kHullTolerance) & (x <= hi + kHullTolerance);  // false for NaN
    const double lo_clamped = x >= 0.0 ? x : 0.0;                   // NaN -> 0
    (*u)[d] = lo_clamped <= hi ? lo_clamped : hi;
  }
  return inside;
}

std::size_t brick_linear(const Index& b, const Index& bricks) {
  return (static_cast<std::size_t>(b.z()) * bricks.y() + b.y()) * bricks.x() + b.x();
}

struct OwnedBricks {
  std::vector<std::int32_t> index;
  std::vector<float> coefficients;
  std::vector<std::int32_t> coarse;
};

}  // namespace

SparseVdtMap3::SparseVdtMap3(const GridFrame<3>& frame, const Index& size, double band,
                             Bricks bricks)
    : frame_(frame), size_(size), band_(band), bricks_(std::move(bricks)) {
  VDTNAV_CHECK((size.array() >= 4).all(), "SparseVdtMap3: the box needs >= 4 voxels per axis");
  bricks_size_ = (size.array() + (kBrick - 1)) / kBrick;
  VDTNAV_CHECK(std::isfinite(band) && band >= 0.0, "SparseVdtMap3: band must be finite and >= 0");
  VDTNAV_CHECK(bricks_.index != nullptr && bricks_.coarse != nullptr &&
                   (bricks_.num_bricks == 0 || bricks_.coefficients != nullptr),
               "SparseVdtMap3: missing brick arrays");
  const auto n = static_cast<std::size_t>(bricks_size_.prod());
  for (std::size_t b = 0; b < n; ++b) {
    VDTNAV_CHECK(
        bricks_.index[b] >= -1 && bricks_.index[b] < static_cast<std::int64_t>(bricks_.num_bricks),
        "SparseVdtMap3: brick index out of range");
    for (int d = 0; d < 3; ++d) {
      VDTNAV_CHECK(bricks_.coarse[3 * b + d] >= 0 && bricks_.coarse[3 * b + d] < size[d],
                   "SparseVdtMap3: coarse surface voxel outside the box");
    }
  }
}

SparseVdtMap3 SparseVdtMap3::build(const OccupancyGrid<3>& occupancy,
                                   const SparseVdtMapOptions& options) {
  std::vector<Index> occupied;
  for (std::size_t c = 0; c < occupancy.num_cells(); ++c) {
    if (occupancy[c] != 0) occupied.push_back(occupancy.index_of(static_cast<std::ptrdiff_t>(c)));
  }
  return build(occupied, occupancy.frame(), occupancy.size(), options);
}

SparseVdtMap3 SparseVdtMap3::build(const std::vector<Index>& occupied, const GridFrame<3>& frame,
                                   const Index& size, const SparseVdtMapOptions& options) {
  VDTNAV_CHECK((size.array() >= 4).all(),
               "SparseVdtMap3::build: the box needs >= 4 voxels per axis");
  VDTNAV_CHECK(std::isfinite(options.band) && options.band >= 0.0 && options.band <= 16.0,
               "SparseVdtMap3::build: band must be in [0, 16] voxels");
  VDTNAV_CHECK(options.prefilter_overlap >= 0 && options.prefilter_overlap <= 16,
               "SparseVdtMap3::build: prefilter_overlap must be in [0, 16] nodes");
  const Index nb = (size.array() + (kB - 1)) / kB;
  VDTNAV_CHECK(static_cast<double>(nb.x()) * nb.y() * nb.z() < 2147483648.0,
               "SparseVdtMap3::build: the box has 2^31 bricks or more");

  // 1. The occupied voxels as brick masks, then the features: surface voxels (a free 6-neighbour
  //    inside the box, as surface_cells()), or every occupied voxel.
  VoxelSet occ(nb);
  for (const Index& v : occupied) {
    if ((v.array() < 0).any() || (v.array() >= size.array()).any()) {
      std::ostringstream s;
      s << "SparseVdtMap3::build: occupied voxel (" << v.transpose() << ") outside the box ("
        << size.transpose() << ")";
      throw ConfigError(s.str());
    }
    occ.insert(v);
  }
  VDTNAV_CHECK(
      occ.num_bricks() > 0,
      "SparseVdtMap3::build: no voxel is occupied, so the distance transform is undefined");
  VoxelSet features(nb);
  if (options.all_occupied_cells) {
    features = occ;
  } else {
    for (std::size_t s = 0; s < occ.num_bricks(); ++s) {
      occ.for_each(s, [&](const Index& v) {
        for (int d = 0; d < 3; ++d)
          for (int step : {-1, 1}) {
            Index w = v;
            w[d] += step;
            if (w[d] >= 0 && w[d] < size[d] && !occ.contains(w)) {
              features.insert(v);
              return;
            }
          }
      });
    }
    if (features.num_bricks() == 0) features = occ;  // all occupied: surface_cells()'s rule
  }
  occ = VoxelSet(Index::Ones());  // release

  // 2. The coarse level: one node per brick, at the brick's centre (fine index 8 c + 3.5). Its
  //    surface voxels come from the tiles' exact transform where a tile is processed, and are the
  //    nearest feature voxel of the nearest feature brick elsewhere.
  std::vector<std::uint8_t> coarse_done(static_cast<std::size_t>(nb.prod()), 0);
  const auto coarse_linear = [&nb](const Index& c) { return brick_linear(c, nb); };
  const auto coarse_voxel = [&size](const Index& c) {  // the voxel at a coarse node's centre
    return Index((c * kB + Index::Constant(kB / 2)).cwiseMin(size - Index::Ones()));
  };

  // 3. Tile by tile: the exact feature transform of a window (halo H >= every distance that
  //    decides a node's allocation or a coefficient to ~1e-5), the bricks whose nodes a query
  //    within `band` needs, and the prefilter on the tile widened by the overlap.
  const double near_radius = options.band + 0.5 * std::sqrt(3.0);  // a span corner's reach
  const double near2 = near_radius * near_radius;
  constexpr int kSupport = 2;  // nodes of a span's support beyond a corner, per axis
  const int ov = options.prefilter_overlap;
  const int halo = std::max(ov, kSupport + static_cast<int>(std::ceil(near_radius))) + 16;
  const int dilation = (kSupport + static_cast<int>(std::ceil(near_radius)) + kB - 1) / kB;

  auto owned = std::make_shared<OwnedBricks>();
  owned->index.assign(static_cast<std::size_t>(nb.prod()), -1);
  owned->coarse.assign(static_cast<std::size_t>(nb.prod()) * 3, 0);
  {  // Reserve for every candidate brick: untouched pages cost address space, not memory.
    std::size_t candidates = 0;
    for (int z = 0; z < nb.z(); ++z)
      for (int y = 0; y < nb.y(); ++y)
        for (int x = 0; x < nb.x(); ++x) {
          bool any = false;
          for (int dz = -dilation; dz <= dilation && !any; ++dz)
            for (int dy = -dilation; dy <= dilation && !any; ++dy)
              for (int dx = -dilation; dx <= dilation && !any; ++dx) {
                const Index b(x + dx, y + dy, z + dz);
                any = (b.array() >= 0).all() && (b.array() < nb.array()).all() &&
                      features.slot(b) >= 0;
              }
          candidates += any;
        }
    owned->coefficients.reserve(candidates * kBrickFloats);
  }

  const Index tiles = (size.array() + (kTile - 1)) / kTile;
  const float res = static_cast<float>(frame.resolution());
  // A tile's bricks, in the order of its loops, and their coefficients. The coarse nodes of the
  // tile's own bricks are written in place (no other tile writes them).
  struct TileBricks {
    std::vector<Index> allocated;
    std::vector<float> coefficients;  // kBrickFloats per allocated brick
  };
  const auto build_tile = [&](int tx, int ty, int tz, TileBricks* out) {
    std::vector<float> samples;
    std::vector<std::uint8_t> near;
    std::vector<Index>& allocated = out->allocated;
    const Index tlo = Index(tx, ty, tz) * kTile;
    const Index thi = (tlo + Index::Constant(kTile)).cwiseMin(size);
    const Index b0 = tlo / kB, b1 = (thi.array() + (kB - 1)) / kB;
    bool active = false;
    const Index d0 = (b0 - Index::Constant(dilation)).cwiseMax(Index::Zero());
    const Index d1 = (b1 + Index::Constant(dilation)).cwiseMin(nb);
    for (int z = d0.z(); z < d1.z() && !active; ++z)
      for (int y = d0.y(); y < d1.y() && !active; ++y)
        for (int x = d0.x(); x < d1.x() && !active; ++x)
          active = features.slot(Index(x, y, z)) >= 0;
    if (!active) return;

    // The window's feature transform (window coordinates).
    const Index wlo = (tlo - Index::Constant(halo)).cwiseMax(Index::Zero());
    const Index whi = (thi + Index::Constant(halo)).cwiseMin(size);
    OccupancyGrid<3> window(whi - wlo, GridFrame<3>(1.0, Eigen::Vector3d::Zero()), 0);
    bool any_feature = false;
    const Index wb0 = wlo / kB, wb1 = (whi.array() + (kB - 1)) / kB;
    for (int z = wb0.z(); z < wb1.z(); ++z)
      for (int y = wb0.y(); y < wb1.y(); ++y)
        for (int x = wb0.x(); x < wb1.x(); ++x) {
          const std::int32_t s = features.slot(Index(x, y, z));
          if (s < 0) continue;
          features.for_each(static_cast<std::size_t>(s), [&](const Index& v) {
            if ((v.array() >= wlo.array()).all() && (v.array() < whi.array()).all()) {
              window(v - wlo) = 1;
              any_feature = true;
            }
          });
        }
    if (!any_feature) return;
    const Grid<std::int32_t, 3> nearest = nearest_occupied_cells(window);
    const auto offset = [&](const Index& w) {  // w - c(w), window voxels
      return Index(w - nearest.index_of(nearest(w)));
    };
    for (int bz = b0.z(); bz < b1.z(); ++bz)
      for (int by = b0.y(); by < b1.y(); ++by)
        for (int bx = b0.x(); bx < b1.x(); ++bx) {
          const Index c(bx, by, bz);
          const Index j = nearest.index_of(nearest(coarse_voxel(c) - wlo)) + wlo;
          for (int d = 0; d < 3; ++d) owned->coarse[3 * coarse_linear(c) + d] = j[d];
          coarse_done[coarse_linear(c)] = 1;
        }

    // Nodes within near_radius of a feature, over the tile widened by the support.
    const Index rlo = (tlo - Index::Constant(kSupport)).cwiseMax(Index::Zero());
    const Index rhi = (thi + Index::Constant(kSupport)).cwiseMin(size);
    const Index rn = rhi - rlo;
    near.assign(static_cast<std::size_t>(rn.prod()), 0);
    for (int z = 0; z < rn.z(); ++z)
      for (int y = 0; y < rn.y(); ++y)
        for (int x = 0; x < rn.x(); ++x) {
          const Index v(x, y, z);
          near[(static_cast<std::size_t>(z) * rn.y() + y) * rn.x() + x] =
              offset(v + rlo - wlo).squaredNorm() <= near2;
        }
    // A brick is needed when a node within its support reach is near.
    allocated.clear();
    for (int bz = b0.z(); bz < b1.z(); ++bz)
      for (int by = b0.y(); by < b1.y(); ++by)
        for (int bx = b0.x(); bx < b1.x(); ++bx) {
          const Index b(bx, by, bz);
          const Index lo = (b * kB - Index::Constant(kSupport)).cwiseMax(rlo) - rlo;
          const Index hi = (b * kB + Index::Constant(kB + kSupport)).cwiseMin(rhi) - rlo;
          bool need = false;
          for (int z = lo.z(); z < hi.z() && !need; ++z)
            for (int y = lo.y(); y < hi.y() && !need; ++y) {
              const std::uint8_t* row = &near[(static_cast<std::size_t>(z) * rn.y() + y) * rn.x()];
              need = std::any_of(row + lo.x(), row + hi.x(), [](std::uint8_t f) { return f; });
            }
          if (need) allocated.push_back(b);
        }
    if (allocated.empty()) return;

    // DT_v samples (grid axes, metres, as VdtMap::build) on the tile widened by the overlap,
    // prefiltered there with natural ends.
    const Index slo = (tlo - Index::Constant(ov)).cwiseMax(Index::Zero());
    const Index shi = (thi + Index::Constant(ov)).cwiseMin(size);
    const Index sn = shi - slo;
    samples.resize(static_cast<std::size_t>(sn.prod()) * 3);
    std::size_t c = 0;
    for (int z = 0; z < sn.z(); ++z)
      for (int y = 0; y < sn.y(); ++y)
        for (int x = 0; x < sn.x(); ++x, ++c) {
          const Index o = offset(Index(x, y, z) + slo - wlo);
          for (int d = 0; d < 3; ++d) samples[3 * c + d] = static_cast<float>(o[d]) * res;
        }
    const CubicBSplineField<3, 3> field(sn, std::move(samples));
    samples = std::vector<float>();
    const float* coef = field.coefficients().data();
    const Index padded = sn + Index::Constant(2);
    out->coefficients.assign(allocated.size() * kBrickFloats, 0.0F);
    for (std::size_t k = 0; k < allocated.size(); ++k) {
      const Index& b = allocated[k];
      float* dst = out->coefficients.data() + k * kBrickFloats;
      for (int z = 0; z < kB; ++z)
        for (int y = 0; y < kB; ++y)
          for (int x = 0; x < kB; ++x) {
            const Index g = b * kB + Index(x, y, z);
            if ((g.array() >= size.array()).any()) continue;  // beyond the box: never used
            const Index pn = g - slo + Index::Ones();         // padded node
            const std::size_t src =
                ((static_cast<std::size_t>(pn.z()) * padded.y() + pn.y()) * padded.x() + pn.x()) *
                3;
            std::memcpy(dst + ((z * kB + y) * kB + x) * 3, coef + src, 3 * sizeof(float));
          }
    }
  };
  // The tiles in batches, one tile per call of the pool, appended in tile order: the bricks and
  // their order are the same for any thread count.
  const std::size_t num_tiles = static_cast<std::size_t>(tiles.prod());
  const std::size_t batch = static_cast<std::size_t>(threads()) * 4;
  std::vector<TileBricks> done(batch);
  for (std::size_t t0 = 0; t0 < num_tiles; t0 += batch) {
    const std::size_t t1 = std::min(num_tiles, t0 + batch);
    parallel_for(t1 - t0, [&](std::size_t k) {
      const int t = static_cast<int>(t0 + k);  // x fastest, as the loops were
      done[k] = TileBricks();
      build_tile(t % tiles.x(), (t / tiles.x()) % tiles.y(), t / (tiles.x() * tiles.y()), &done[k]);
    });
    for (std::size_t k = 0; k < t1 - t0; ++k) {
      const TileBricks& tb = done[k];
      for (std::size_t i = 0; i < tb.allocated.size(); ++i) {
        owned->index[brick_linear(tb.allocated[i], nb)] =
            static_cast<std::int32_t>(owned->coefficients.size() / kBrickFloats);
        owned->coefficients.insert(owned->coefficients.end(),
                                   tb.coefficients.begin() + i * kBrickFloats,
                                   tb.coefficients.begin() + (i + 1) * kBrickFloats);
      }
      done[k] = TileBricks();
    }
  }

  // The coarse nodes no tile reached: the coarse feature transform of the feature bricks, then
  // the nearest feature voxel of the nearest brick.
  OccupancyGrid<3> coarse_occ(nb, GridFrame<3>(1.0, Eigen::Vector3d::Zero()), 0);
  for (std::size_t b = 0; b < features.num_bricks(); ++b) coarse_occ(features.coord(b)) = 1;
  const Grid<std::int32_t, 3> coarse_nearest = nearest_occupied_cells(coarse_occ);
  for (std::size_t c = 0; c < coarse_done.size(); ++c) {
    if (coarse_done[c] != 0) continue;
    const Index node = coarse_nearest.index_of(static_cast<std::ptrdiff_t>(c));
    const Index f = coarse_nearest.index_of(coarse_nearest[c]);
    const Eigen::Vector3d x = node.cast<double>() * kB + Eigen::Vector3d::Constant(3.5);
    double best = std::numeric_limits<double>::infinity();
    features.for_each(static_cast<std::size_t>(features.slot(f)), [&](const Index& v) {
      const double d2 = (x - v.cast<double>()).squaredNorm();
      if (d2 < best) {
        best = d2;
        for (int d = 0; d < 3; ++d) owned->coarse[3 * c + d] = v[d];
      }
    });
  }

  Bricks bricks;
  bricks.index = owned->index.data();
  bricks.coefficients = owned->coefficients.data();
  bricks.coarse = owned->coarse.data();
  bricks.num_bricks = owned->coefficients.size() / kBrickFloats;
  bricks.owner = owned;
  return SparseVdtMap3(frame, size, options.band, std::move(bricks));
}

bool SparseVdtMap3::evaluate_fine(const Vector& u, Vector* value, Matrix* jacobian) const {
  const AxisSupport ax(u.x(), size_.x()), ay(u.y(), size_.y()), az(u.z(), size_.z());
  const Index start(ax.start, ay.start, az.start);
  const Index b0(start.x() >> 3, start.y() >> 3, start.z() >> 3);
  const Index l0(start.x() & 7, start.y() & 7, start.z() & 7);
  // The support spans one brick per axis, or two when it starts in the last 3 nodes.
  const Index split((l0.array() > kBrick - 4).cast<int>());
  const float* slot[2][2][2] = {};
  for (int z = 0; z <= split.z(); ++z)
    for (int y = 0; y <= split.y(); ++y)
      for (int x = 0; x <= split.x(); ++x) {
        const std::int32_t s = bricks_.index[brick_linear(b0 + Index(x, y, z), bricks_size_)];
        if (s < 0) return false;
        slot[z][y][x] = bricks_.coefficients + static_cast<std::size_t>(s) * kBrickFloats;
      }
  constexpr std::ptrdiff_t kRow = 3 * kBrick, kPlane = kRow * kBrick;
  if (split.isZero()) {  // the whole support in one brick
    const float* c0 = slot[0][0][0] + (l0.z() * kPlane + l0.y() * kRow + l0.x() * 3);
    jacobian != nullptr ? support_sum<true>(c0, kRow, kPlane, ax, ay, az, value, jacobian)
                        : support_sum<false>(c0, kRow, kPlane, ax, ay, az, value, jacobian);
    return true;
  }
  // Gather the 4 x 4 x 4 support into contiguous rows.
  alignas(32) float buf[4][4][12];
  const int mx = kBrick - l0.x();  // nodes of a row in the first brick along x
  for (int k = 0; k < 4; ++k) {
    const int zk = l0.z() + k, oz = zk >> 3, lz = zk & 7;
    for (int j = 0; j < 4; ++j) {
      const int yj = l0.y() + j, oy = yj >> 3, ly = yj & 7;
      const float* row = slot[oz][oy][0] + (lz * kPlane + ly * kRow + l0.x() * 3);
      if (split.x() == 0) {
        std::memcpy(buf[k][j], row, 12 * sizeof(float));
      } else {
        std::memcpy(buf[k][j], row, static_cast<std::size_t>(3 * mx) * sizeof(float));
        std::memcpy(buf[k][j] + 3 * mx, slot[oz][oy][1] + (lz * kPlane + ly * kRow),
                    static_cast<std::size_t>(3 * (4 - mx)) * sizeof(float));
      }
    }
  }
  jacobian != nullptr ? support_sum<true>(&buf[0][0][0], 12, 48, ax, ay, az, value, jacobian)
                      : support_sum<false>(&buf[0][0][0], 12, 48, ax, ay, az, value, jacobian);
  return true;
}

SparseVdtMap3::Index SparseVdtMap3::coarse_nearest(const Vector& u) const {
  // Coarse node c sits at fine index 8 c + 3.5: the 2 x 2 x 2 nodes around u (clamped).
  Index lo, hi;
  for (int d = 0; d < 3; ++d) {
    const double x = (u[d] - 3.5) / kBrick;
    const int f = static_cast<int>(std::floor(x));
    lo[d] = std::clamp(f, 0, bricks_size_[d] - 1);
    hi[d] = std::clamp(f + 1, 0, bricks_size_[d] - 1);
  }
  Index best = Index::Zero();
  double best2 = std::numeric_limits<double>::infinity();
  for (int z : {lo.z(), hi.z()})
    for (int y : {lo.y(), hi.y()})
      for (int x : {lo.x(), hi.x()}) {
        const std::int32_t* c = bricks_.coarse + 3 * brick_linear(Index(x, y, z), bricks_size_);
        const Index v(c[0], c[1], c[2]);
        const double d2 = (u - v.cast<double>()).squaredNorm();
        if (d2 < best2) {
          best2 = d2;
          best = v;
        }
      }
  return best;
}

VdtSample<3> SparseVdtMap3::evaluate_one(const Vector& p, bool jacobian) const {
  VdtSample<3> s;
  Vector u = frame_.continuous_index(p);
  const bool inside = clamp_to_hull(size_, &u);
  if (evaluate_fine(u, &s.value, jacobian ? &s.jacobian : nullptr)) {
    // Grid axes per unit index -> world axes per metre (as VdtMap::to_world).
    s.jacobian *= frame_.inv_resolution();
    if (!frame_.axis_aligned()) {
      const Matrix& r = frame_.rotation();
      s.value = r * s.value;
      s.jacobian = r * s.jacobian * r.transpose();
    }
  } else {  // the coarse level at the clamped point: p - c, c fixed
    const Vector q = frame_.world_point(u);
    s.value = q - frame_.cell_center(coarse_nearest(u));
    if (jacobian) s.jacobian.setIdentity();
  }
  s.inside = inside;
  return s;
}

void SparseVdtMap3::evaluate(const Vector* p, std::size_t n, VdtSample<3>* out,
                             bool jacobian) const {
  // A lambda of a member has its access: the kernel's fallback for the coarse level's points.
  constexpr detail::SparseFallback kPortable = [](const SparseVdtMap3& map, const Vector& q,
                                                  bool with_jacobian) {
    return map.evaluate_one(q, with_jacobian);
  };
  if (detail::evaluate_simd(*this, p, n, out, jacobian, kPortable)) return;
  for (std::size_t k = 0; k < n; ++k) out[k] = evaluate_one(p[k], jacobian);
}

bool SparseVdtMap3::fine_level(const Vector& p) const {
  Vector u = frame_.continuous_index(p);
  (void)clamp_to_hull(size_, &u);
  Vector v;
  return evaluate_fine(u, &v, nullptr);
}

VdtSample<3> SparseVdtMap3::nearest_point_query(const Vector& p) const {
  VdtSample<3> s;
  const Index raw = frame_.cell_of(p);
  s.inside = (raw.array() >= 0).all() && (raw.array() < size_.array()).all();
  const Index cell = raw.cwiseMax(Index::Zero()).cwiseMin(size_ - Index::Ones());
  Vector v;
  if (evaluate_fine(cell.cast<double>(), &v, nullptr)) {
    // The spline interpolates the samples (i - c(i)) resolution at the nodes.
    Index off;
    for (int d = 0; d < 3; ++d)
      off[d] = static_cast<int>(std::lround(v[d] * frame_.inv_resolution()));
    s.value = p - frame_.cell_center(cell - off);
  } else {
    s.value = p - frame_.cell_center(coarse_nearest(cell.cast<double>()));
  }
  s.jacobian.setIdentity();
  return s;
}

std::size_t SparseVdtMap3::memory_bytes() const noexcept {
  return bricks_.num_bricks * kBrickFloats * sizeof(float) +
         static_cast<std::size_t>(bricks_size_.prod()) * 4 * sizeof(std::int32_t);
}

VdtSampleWithHessian<3> SparseVdtMap3::evaluate_with_hessian(const Vector& p) const {
  VdtSampleWithHessian<3> out;
  const double h = resolution() / 20.0;
  // The point and its six neighbours in one batch (one pass of the kernels, not seven).
  std::array<Vector, 7> q;
  std::array<VdtSample<3>, 7> s;
  q[0] = p;
  for (int a = 0; a < 3; ++a) {
    q[1 + 2 * a] = p + h * Vector::Unit(a);
    q[2 + 2 * a] = p - h * Vector::Unit(a);
  }
  evaluate(q.data(), q.size(), s.data());
  static_cast<VdtSample<3>&>(out) = s[0];
  for (int a = 0; a < 3; ++a) {
    const Matrix d = (s[1 + 2 * a].jacobian - s[2 + 2 * a].jacobian) / (2.0 * h);
    for (int c = 0; c < 3; ++c) out.hessian[c].col(a) = d.row(c).transpose();  // d(grad DT_c)/dp_a
  }
  for (int c = 0; c < 3; ++c)  // symmetric by definition: average out the differences' noise
    out.hessian[c] = 0.5 * (out.hessian[c] + out.hessian[c].transpose()).eval();
  return out;
}

}  // namespace vdtnav
