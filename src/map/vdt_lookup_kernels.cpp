// Batch lookups of DT_v and its Jacobian (VdtMap::evaluate and SparseVdtMap3::evaluate over many
// points) with the instruction
// set chosen at run time: AVX2 + FMA where the CPU has them, the portable evaluation of
// cubic_bspline.hpp otherwise. The library is compiled for the baseline ISA; only the functions
// below carry target("avx2,fma"), and they use intrinsics only (no inline function of another
// library is instantiated with AVX2 code, which the linker could pick for a baseline caller).
//
// Per point: the continuous index u = (p - origin) / resolution - 1/2, clamped to the node hull
// (CubicBSplineField::clamp), and the sums of CubicBSplineField::evaluate_impl: per plane
// p = sum_j wy_j row_j (and its y derivative), over planes a = sum_k wz_k p (and the z
// derivatives), x reduced last with the node weights spread over the lanes of a row (node l =
// lane / channels). The Jacobian leaves in world units (times 1 / resolution); maps rotated in
// the world take the portable path. The dense 3D map and the sparse one share all of it
// (Locator3, support_weights, sum_support) and differ only in how the support's 16 rows are
// addressed (StridedRows, BrickRows).
#include "vdt_lookup_kernels.hpp"

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#define VDTNAV_HAVE_X86_KERNELS 1
#else
#define VDTNAV_HAVE_X86_KERNELS 0
#endif

namespace vdtnav {
namespace {

bool cpu_has_avx2_fma() {
#if VDTNAV_HAVE_X86_KERNELS
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

/// The best level of this CPU, unless the environment variable VDTNAV_SIMD=baseline asks for the
/// portable kernels (results then repeat bit for bit across machines).
std::atomic<SimdLevel>& chosen_level() {
  static std::atomic<SimdLevel> level{[] {
    const char* env = std::getenv("VDTNAV_SIMD");
    const bool baseline = env != nullptr && std::strcmp(env, "baseline") == 0;
    return !baseline && cpu_has_avx2_fma() ? SimdLevel::kAvx2Fma : SimdLevel::kBaseline;
  }()};
  return level;
}

#if VDTNAV_HAVE_X86_KERNELS
#define VDTNAV_AVX2 __attribute__((target("avx2,fma")))

// Same tolerance as CubicBSplineField::clamp: points on the hull up to rounding are inside.
constexpr double kHullTolerance = 1e-9;
constexpr std::size_t kPrefetch = 4;  // points ahead

/// Cubic B-spline weights (CubicBSplineWeights) of the offsets in t: lanes 0-3 the four nodes of
/// lane 0's offset, lanes 4-7 those of lane 4's.
VDTNAV_AVX2 inline void spline_weights(__m256 t, __m256* w, __m256* dw) {
  constexpr float k = 1.0F / 6.0F;
  const __m256 a0 = _mm256_setr_ps(k, 4 * k, k, 0, k, 4 * k, k, 0);
  const __m256 a1 = _mm256_setr_ps(-3 * k, 0, 3 * k, 0, -3 * k, 0, 3 * k, 0);
  const __m256 a2 = _mm256_setr_ps(3 * k, -6 * k, 3 * k, 0, 3 * k, -6 * k, 3 * k, 0);
  const __m256 a3 = _mm256_setr_ps(-k, 3 * k, -3 * k, k, -k, 3 * k, -3 * k, k);
  *w = _mm256_fmadd_ps(_mm256_fmadd_ps(_mm256_fmadd_ps(a3, t, a2), t, a1), t, a0);
  *dw = _mm256_fmadd_ps(
      _mm256_fmadd_ps(_mm256_mul_ps(_mm256_set1_ps(3.0F), a3), t, _mm256_add_ps(a2, a2)), t, a1);
}

/// The 8 lanes of a weight vector, spilled so that a lane is broadcast by a load
/// (vbroadcastss from memory runs on the load ports; a lane permute would compete with the
/// reductions' shuffles for the one shuffle port).
struct alignas(32) Lanes {
  float f[8];
  VDTNAV_AVX2 explicit Lanes(__m256 v) { _mm256_store_ps(f, v); }
  VDTNAV_AVX2 __m256 operator[](int i) const { return _mm256_broadcast_ss(f + i); }
};

/// 2 channels x 4 nodes (lanes c0 c1 c0 c1 ...) summed per channel: lanes 0, 1 of the result.
VDTNAV_AVX2 inline __m128 reduce_2(__m256 v) {
  const __m128 h = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  return _mm_add_ps(h, _mm_movehl_ps(h, h));
}

/// 3 channels x 4 nodes in 12 lanes (A B = ab, C = c) summed per channel: lanes 0-2 of
///   A + (A3 B0 B1 B2) + (B2 B3 C0 C1) + (C1 C2 C3 0).
VDTNAV_AVX2 inline __m128 reduce_3(__m256 ab, __m128 c) {
  const __m128i a = _mm_castps_si128(_mm256_castps256_ps128(ab));
  const __m128i b = _mm_castps_si128(_mm256_extractf128_ps(ab, 1));
  const __m128i ci = _mm_castps_si128(c);
  const __m128 s1 = _mm_add_ps(_mm_castsi128_ps(a), _mm_castsi128_ps(_mm_alignr_epi8(b, a, 12)));
  const __m128 s2 = _mm_add_ps(_mm_castsi128_ps(_mm_alignr_epi8(ci, b, 8)),
                               _mm_castsi128_ps(_mm_srli_si128(ci, 4)));
  return _mm_add_ps(s1, s2);
}

/// Writes lanes 0-2 of v as doubles to dst[0..2].
VDTNAV_AVX2 inline void store3(double* dst, __m128 v) {
  _mm256_maskstore_pd(dst, _mm256_setr_epi64x(-1, -1, -1, 0), _mm256_cvtps_pd(v));
}

template <bool kGradient>
VDTNAV_AVX2 void lookup_2d_avx2(const VdtMap<2>& map, const Eigen::Vector2d* p, std::size_t n,
                                VdtSample<2>* out) {
  const float* coef = map.field().coefficients().data();
  const Eigen::Vector2i size = map.size();
  const int padded_x = size.x() + 2;
  const std::ptrdiff_t row_stride = static_cast<std::ptrdiff_t>(padded_x) * 2;
  const __m128d origin = _mm_loadu_pd(map.frame().origin().data());
  const __m128d inv_res = _mm_set1_pd(map.frame().inv_resolution());
  const __m128d half = _mm_set1_pd(0.5), zero = _mm_setzero_pd();
  const __m128d hi = _mm_setr_pd(size.x() - 1, size.y() - 1);
  const __m128d lo_tol = _mm_set1_pd(-kHullTolerance);
  const __m128d hi_tol = _mm_add_pd(hi, _mm_set1_pd(kHullTolerance));
  const __m128i last_span = _mm_setr_epi32(size.x() - 2, size.y() - 2, 0, 0);
  const __m256i spread = _mm256_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3);
  const __m256i halves = _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1);
  const __m128 to_world = _mm_set1_ps(static_cast<float>(map.frame().inv_resolution()));
  for (std::size_t i = 0; i < n; ++i) {
    const __m128d u =
        _mm_sub_pd(_mm_mul_pd(_mm_sub_pd(_mm_loadu_pd(p[i].data()), origin), inv_res), half);
    // NaN compares false (outside) and _mm_max_pd returns its second operand for it (node 0).
    const __m128d in = _mm_and_pd(_mm_cmpge_pd(u, lo_tol), _mm_cmple_pd(u, hi_tol));
    out[i].inside = _mm_movemask_pd(in) == 3;
    const __m128d uc = _mm_min_pd(_mm_max_pd(u, zero), hi);
    const __m128i base = _mm_min_epi32(_mm_cvttpd_epi32(uc), last_span);  // u = n-1: t = 1
    const __m128 t = _mm_cvtpd_ps(_mm_sub_pd(uc, _mm_cvtepi32_pd(base)));
    const int ix = _mm_cvtsi128_si32(base), iy = _mm_extract_epi32(base, 1);
    const float* c0 = coef + (static_cast<std::ptrdiff_t>(iy) * padded_x + ix) * 2;
    __m256 w, dw;
    spline_weights(_mm256_permutevar8x32_ps(_mm256_castps128_ps256(t), halves), &w, &dw);
    // Rows 0, 1 and 2, 3 in two independent chains (shorter latency than one chain of four).
    const __m256 r0 = _mm256_loadu_ps(c0), r1 = _mm256_loadu_ps(c0 + row_stride),
                 r2 = _mm256_loadu_ps(c0 + 2 * row_stride),
                 r3 = _mm256_loadu_ps(c0 + 3 * row_stride);
    const Lanes lw(w), ldw(dw);
    const __m256 py0 = _mm256_add_ps(_mm256_fmadd_ps(lw[5], r1, _mm256_mul_ps(lw[4], r0)),
                                     _mm256_fmadd_ps(lw[7], r3, _mm256_mul_ps(lw[6], r2)));
    const __m256 ex = _mm256_permutevar8x32_ps(w, spread);
    _mm_storeu_pd(out[i].value.data(), _mm_cvtps_pd(reduce_2(_mm256_mul_ps(py0, ex))));
    if constexpr (!kGradient) continue;
    const __m256 py1 = _mm256_add_ps(_mm256_fmadd_ps(ldw[5], r1, _mm256_mul_ps(ldw[4], r0)),
                                     _mm256_fmadd_ps(ldw[7], r3, _mm256_mul_ps(ldw[6], r2)));
    const __m256 edx = _mm256_permutevar8x32_ps(dw, spread);
    double* jac = out[i].jacobian.data();  // column-major: column d = d/dp_d of the components
    _mm_storeu_pd(jac, _mm_cvtps_pd(_mm_mul_ps(reduce_2(_mm256_mul_ps(py0, edx)), to_world)));
    _mm_storeu_pd(jac + 2, _mm_cvtps_pd(_mm_mul_ps(reduce_2(_mm256_mul_ps(py1, ex)), to_world)));
  }
}

/// A 3D lattice's continuous index of world points (the dense field's nodes or the bricks'):
/// u = (p - origin) / resolution - 1/2, clamped to the node hull (uc), and its span `base`
/// (u = n-1 in the last span with t = 1), as CubicBSplineField::clamp and evaluate_impl.
struct Locator3 {
  __m256d origin, inv_res, half, zero, hi, lo_tol, hi_tol;
  __m128i last_span;
  __m256i first3;

  struct Located {
    __m256d u, uc;
    __m128i base;
  };

  VDTNAV_AVX2 Locator3(const GridFrame<3>& frame, const Eigen::Vector3i& size) {
    const Eigen::Vector3d& o = frame.origin();
    origin = _mm256_setr_pd(o.x(), o.y(), o.z(), 0.0);
    inv_res = _mm256_set1_pd(frame.inv_resolution());
    half = _mm256_set1_pd(0.5);
    zero = _mm256_setzero_pd();
    hi = _mm256_setr_pd(size.x() - 1, size.y() - 1, size.z() - 1, 0.0);
    lo_tol = _mm256_set1_pd(-kHullTolerance);
    hi_tol = _mm256_add_pd(hi, _mm256_set1_pd(kHullTolerance));
    last_span = _mm_setr_epi32(size.x() - 2, size.y() - 2, size.z() - 2, 0);
    first3 = _mm256_setr_epi64x(-1, -1, -1, 0);
  }
  VDTNAV_AVX2 Located operator()(const Eigen::Vector3d& p) const {
    Located l;
    l.u = _mm256_sub_pd(
        _mm256_mul_pd(_mm256_sub_pd(_mm256_maskload_pd(p.data(), first3), origin), inv_res), half);
    // NaN: _mm256_max_pd returns its second operand (node 0).
    l.uc = _mm256_min_pd(_mm256_max_pd(l.u, zero), hi);
    l.base = _mm_min_epi32(_mm256_cvttpd_epi32(l.uc), last_span);
    return l;
  }
  /// NaN compares false (outside).
  VDTNAV_AVX2 bool inside(const Located& l) const {
    const __m256d in = _mm256_and_pd(_mm256_cmp_pd(l.u, lo_tol, _CMP_GE_OQ),
                                     _mm256_cmp_pd(l.u, hi_tol, _CMP_LE_OQ));
    return (_mm256_movemask_pd(in) & 7) == 7;
  }
  /// The offsets t = uc - base in the span, lanes 0-2.
  VDTNAV_AVX2 static __m128 offset(const Located& l) {
    return _mm256_cvtpd_ps(_mm256_sub_pd(l.uc, _mm256_cvtepi32_pd(l.base)));
  }
};

/// The weights of a 4 x 4 x 4 support: x in lanes 0-3 and y in lanes 4-7 of xy, z in lanes 0-3
/// (and 4-7) of z.
struct Weights3 {
  __m256 xy, dxy, z, dz;
};

VDTNAV_AVX2 inline Weights3 support_weights(__m128 t) {
  const __m256 t8 = _mm256_castps128_ps256(t);
  Weights3 w;
  spline_weights(_mm256_permutevar8x32_ps(t8, _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1)), &w.xy,
                 &w.dxy);
  spline_weights(_mm256_permutevar8x32_ps(t8, _mm256_set1_epi32(2)), &w.z, &w.dz);
  return w;
}

/// The tensor-product sums of CubicBSplineField::evaluate_impl over a 4 x 4 x 4 support of
/// 3-channel nodes: per plane p = sum_j wy_j row_j (and its y derivative), over planes
/// a = sum_k wz_k p (and the z derivatives), x reduced last with the node weights spread over the
/// lanes of a row. rows(j, k, &ab, &c) loads row j of plane k (4 nodes x 3 channels: lanes 0-7
/// in ab, 8-11 in c); how rows are addressed is all that differs between the dense lattice and
/// the bricks. Writes DT_v and, with kGradient, the Jacobian times `to_world` (grid axes).
template <bool kGradient, typename Rows>
VDTNAV_AVX2 inline void sum_support(const Rows& rows, const Weights3& w, __m128 to_world,
                                    VdtSample<3>* out) {
  const Lanes lwxy(w.xy), ldwxy(w.dxy), lwz(w.z), ldwz(w.dz);
  __m256 a_ab = _mm256_setzero_ps(), ay_ab = a_ab, az_ab = a_ab;
  __m128 a_c = _mm_setzero_ps(), ay_c = a_c, az_c = a_c;
  for (int k = 0; k < 4; ++k) {
    __m256 p_ab = _mm256_setzero_ps(), py_ab = p_ab;
    __m128 p_c = _mm_setzero_ps(), py_c = p_c;
    for (int j = 0; j < 4; ++j) {
      __m256 ab;
      __m128 c;
      rows(j, k, &ab, &c);
      const __m256 wy = lwxy[4 + j], dwy = ldwxy[4 + j];
      p_ab = _mm256_fmadd_ps(wy, ab, p_ab);
      if constexpr (kGradient) py_ab = _mm256_fmadd_ps(dwy, ab, py_ab);
      p_c = _mm_fmadd_ps(_mm256_castps256_ps128(wy), c, p_c);
      if constexpr (kGradient) py_c = _mm_fmadd_ps(_mm256_castps256_ps128(dwy), c, py_c);
    }
    const __m256 wk = lwz[k], dwk = ldwz[k];
    a_ab = _mm256_fmadd_ps(wk, p_ab, a_ab);
    if constexpr (kGradient) {
      ay_ab = _mm256_fmadd_ps(wk, py_ab, ay_ab);
      az_ab = _mm256_fmadd_ps(dwk, p_ab, az_ab);
    }
    a_c = _mm_fmadd_ps(_mm256_castps256_ps128(wk), p_c, a_c);
    if constexpr (kGradient) {
      ay_c = _mm_fmadd_ps(_mm256_castps256_ps128(wk), py_c, ay_c);
      az_c = _mm_fmadd_ps(_mm256_castps256_ps128(dwk), p_c, az_c);
    }
  }
  const __m256i spread_ab = _mm256_setr_epi32(0, 0, 0, 1, 1, 1, 2, 2);
  const __m256i spread_c = _mm256_setr_epi32(2, 3, 3, 3, 3, 3, 3, 3);
  const __m256 ex_ab = _mm256_permutevar8x32_ps(w.xy, spread_ab);
  const __m128 ex_c = _mm256_castps256_ps128(_mm256_permutevar8x32_ps(w.xy, spread_c));
  store3(out->value.data(), reduce_3(_mm256_mul_ps(a_ab, ex_ab), _mm_mul_ps(a_c, ex_c)));
  if constexpr (kGradient) {
    const __m256 edx_ab = _mm256_permutevar8x32_ps(w.dxy, spread_ab);
    const __m128 edx_c = _mm256_castps256_ps128(_mm256_permutevar8x32_ps(w.dxy, spread_c));
    double* jac = out->jacobian.data();  // column-major: column d = d/dp_d of the components
    store3(jac,
           _mm_mul_ps(reduce_3(_mm256_mul_ps(a_ab, edx_ab), _mm_mul_ps(a_c, edx_c)), to_world));
    store3(jac + 3,
           _mm_mul_ps(reduce_3(_mm256_mul_ps(ay_ab, ex_ab), _mm_mul_ps(ay_c, ex_c)), to_world));
    store3(jac + 6,
           _mm_mul_ps(reduce_3(_mm256_mul_ps(az_ab, ex_ab), _mm_mul_ps(az_c, ex_c)), to_world));
  }
}

/// Rows at c0 + j row_stride + k plane_stride (floats), each 12 contiguous floats: the dense
/// lattice, and a support inside one brick.
struct StridedRows {
  const float* c0;
  std::ptrdiff_t row_stride, plane_stride;
  VDTNAV_AVX2 void operator()(int j, int k, __m256* ab, __m128* c) const {
    const float* row = c0 + k * plane_stride + j * row_stride;
    *ab = _mm256_loadu_ps(row);
    *c = _mm_loadu_ps(row + 8);
  }
};

/// Requests the 16 rows of a support (12 floats each) into L1.
VDTNAV_AVX2 inline void prefetch_support(const float* c0, std::ptrdiff_t row_stride,
                                         std::ptrdiff_t plane_stride) {
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 4; ++j) {
      const char* row = reinterpret_cast<const char*>(c0 + k * plane_stride + j * row_stride);
      _mm_prefetch(row, _MM_HINT_T0);
      _mm_prefetch(row + 44, _MM_HINT_T0);
    }
}

template <bool kGradient>
VDTNAV_AVX2 void lookup_3d_avx2(const VdtMap<3>& map, const Eigen::Vector3d* p, std::size_t n,
                                VdtSample<3>* out) {
  const float* coef = map.field().coefficients().data();
  const Eigen::Vector3i padded = map.size() + Eigen::Vector3i::Constant(2);
  const std::ptrdiff_t row_stride = static_cast<std::ptrdiff_t>(padded.x()) * 3;
  const std::ptrdiff_t plane_stride = row_stride * padded.y();
  const Locator3 locate(map.frame(), map.size());
  const __m128 to_world = _mm_set1_ps(static_cast<float>(map.frame().inv_resolution()));
  // The first coefficient of a point's 4 x 4 x 4 support (the padded lattice's ghost layer holds
  // the natural ends: node base - 1 is padded node base).
  const auto first = [&](const Locator3::Located& l) VDTNAV_AVX2 {
    return coef + ((static_cast<std::ptrdiff_t>(_mm_extract_epi32(l.base, 2)) * padded.y() +
                    _mm_extract_epi32(l.base, 1)) *
                       padded.x() +
                   _mm_cvtsi128_si32(l.base)) *
                      3;
  };
  for (std::size_t i = 0; i < n; ++i) {
    // The support of point i + kPrefetch is requested while point i is summed: 16 rows in 4
    // planes, mostly not in L1 (scan endpoints hop between walls), whose latency would otherwise
    // serialise the loop.
    if (i + kPrefetch < n)
      prefetch_support(first(locate(p[i + kPrefetch])), row_stride, plane_stride);
    const Locator3::Located l = locate(p[i]);
    out[i].inside = locate.inside(l);
    sum_support<kGradient>(StridedRows{first(l), row_stride, plane_stride},
                           support_weights(Locator3::offset(l)), to_world, &out[i]);
  }
}

/// Folds the natural-end ghosts into the 4 weights of an axis whose support reaches one (as the
/// portable AxisSupport): c_{-1} = 2 c_0 - c_1 at the low end (span 0), c_n = 2 c_{n-1} - c_{n-2}
/// at the high end (span n-2).
inline void fold_ghosts(float* a, bool low) {
  if (low) {  // nodes -1, 0, 1, 2 -> 0, 1, 2, 3
    const float a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3];
    a[0] = a1 + 2 * a0;
    a[1] = a2 - a0;
    a[2] = a3;
    a[3] = 0.0F;
  } else {  // nodes n-3 .. n -> n-4 .. n-1
    const float a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3];
    a[0] = 0.0F;
    a[1] = a0;
    a[2] = a1 - a3;
    a[3] = a2 + 2 * a3;
  }
}

/// The rows of a support that crosses a brick face in y or z (and, with kSplitX, in x): row j of
/// plane k lies in brick[oz][oy] (0 or 1 brick further along the axis) at its node
/// (lx, (ly + j) & 7, (lz + k) & 7). A row crossing the x face takes its first 3 mx floats from the
/// x-lower brick and the rest from the row's start in the x-upper one, by complementary masked
/// loads (masked-out lanes read nothing and do not fault).
template <bool kSplitX>
struct BrickRows {
  const float* brick[2][2][2];  ///< [oz][oy][ox]
  std::ptrdiff_t x_offset;      ///< floats: 3 lx
  std::ptrdiff_t row_offset[4], plane_offset[4];
  int oy[4], oz[4];
  __m256i lo_ab, hi_ab;  ///< lanes of the x-lower, x-upper brick
  __m128i lo_c, hi_c;

  VDTNAV_AVX2 void operator()(int j, int k, __m256* ab, __m128* c) const {
    const std::ptrdiff_t at = plane_offset[k] + row_offset[j];
    const float* a = brick[oz[k]][oy[j]][0] + at + x_offset;
    if constexpr (!kSplitX) {
      *ab = _mm256_loadu_ps(a);
      *c = _mm_loadu_ps(a + 8);
    } else {
      // The x-upper row is addressed 3 mx floats before its start (integer arithmetic: the
      // address may lie before the array; only its unmasked lanes are read).
      const auto b = reinterpret_cast<const float*>(
          reinterpret_cast<std::uintptr_t>(brick[oz[k]][oy[j]][1] + at) -
          (3 * SparseVdtMap3::kBrick - x_offset) * sizeof(float));
      const auto a8 =
          reinterpret_cast<const float*>(reinterpret_cast<std::uintptr_t>(a) + 8 * sizeof(float));
      *ab = _mm256_or_ps(_mm256_maskload_ps(a, lo_ab), _mm256_maskload_ps(b, hi_ab));
      *c = _mm_or_ps(_mm_maskload_ps(a8, lo_c), _mm_maskload_ps(b + 8, hi_c));
    }
  }
};

/// SparseVdtMap3's batch lookup: the dense kernel's sums (sum_support) on rows addressed through
/// the brick index. Per point: the span as the dense map's, the support's first node
/// clamp(base - 1, 0, n - 4) (the ghosts folded into the weights at the box's ends), its brick
/// and node in the brick; a support within one brick (lx, ly, lz <= 4: 24 % of uniform points)
/// is strided like the dense lattice, one crossing a face takes its rows from up to 8 bricks. A
/// point whose support reaches an unallocated brick is the coarse level's: `fallback`.
template <bool kGradient>
VDTNAV_AVX2 void lookup_sparse_avx2(const SparseVdtMap3& map, const Eigen::Vector3d* p,
                                    std::size_t n, VdtSample<3>* out,
                                    detail::SparseFallback fallback) {
  constexpr int kB = SparseVdtMap3::kBrick;
  constexpr std::ptrdiff_t kRow = 3 * kB, kPlane = kRow * kB;
  const SparseVdtMap3::Bricks& bricks = map.bricks();
  const std::int32_t* index = bricks.index;
  const float* coef = bricks.coefficients;
  const Eigen::Vector3i& nb = map.brick_grid_size();
  const std::ptrdiff_t brick_row = nb.x(), brick_plane = brick_row * nb.y();
  const Locator3 locate(map.frame(), map.size());
  const __m128i last_start = _mm_sub_epi32(
      _mm_setr_epi32(map.size().x(), map.size().y(), map.size().z(), 0), _mm_set1_epi32(4));
  const __m128 to_world = _mm_set1_ps(static_cast<float>(map.frame().inv_resolution()));
  const __m256i lanes_ab = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m128i lanes_c = _mm_setr_epi32(8, 9, 10, 11);
  struct Support {
    __m128i start;             ///< first node per axis
    const std::int32_t* slot;  ///< the brick index at the first node's brick
    int lx, ly, lz;            ///< first node in its brick
  };
  const auto support_of = [&](const Locator3::Located& l) VDTNAV_AVX2 {
    Support s;
    s.start = _mm_min_epi32(
        _mm_max_epi32(_mm_sub_epi32(l.base, _mm_set1_epi32(1)), _mm_setzero_si128()), last_start);
    const int x = _mm_cvtsi128_si32(s.start), y = _mm_extract_epi32(s.start, 1),
              z = _mm_extract_epi32(s.start, 2);
    s.slot = index + ((z >> 3) * brick_plane + (y >> 3) * brick_row + (x >> 3));
    s.lx = x & 7;
    s.ly = y & 7;
    s.lz = z & 7;
    return s;
  };
  const auto brick_at = [&](std::int32_t slot) {
    return coef + static_cast<std::ptrdiff_t>(slot) * SparseVdtMap3::kBrickFloats;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kPrefetch < n) {  // the rows in the next point's first brick (see lookup_3d_avx2)
      const Support s = support_of(locate(p[i + kPrefetch]));
      if (*s.slot >= 0)
        prefetch_support(brick_at(*s.slot) + s.lz * kPlane + s.ly * kRow + 3 * s.lx, kRow, kPlane);
    }
    const Locator3::Located l = locate(p[i]);
    const bool inside = locate.inside(l);
    const Support s = support_of(l);
    Weights3 w = support_weights(Locator3::offset(l));
    const __m128i base = l.base;
    const int low = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(base, _mm_setzero_si128())));
    const int high = _mm_movemask_ps(
        _mm_castsi128_ps(_mm_cmpeq_epi32(base, _mm_add_epi32(last_start, _mm_set1_epi32(2)))));
    if (((low | high) & 7) != 0) {  // a support at the box's end: rare, folded in scalars
      alignas(32) float xy[8], dxy[8], z[8], dz[8];
      _mm256_store_ps(xy, w.xy);
      _mm256_store_ps(dxy, w.dxy);
      _mm256_store_ps(z, w.z);
      _mm256_store_ps(dz, w.dz);
      for (int d = 0; d < 3; ++d) {
        if (((low | high) >> d & 1) == 0) continue;
        float* a = d == 2 ? z : xy + 4 * d;
        float* da = d == 2 ? dz : dxy + 4 * d;
        fold_ghosts(a, (low >> d & 1) != 0);
        fold_ghosts(da, (low >> d & 1) != 0);
      }
      w = Weights3{_mm256_load_ps(xy), _mm256_load_ps(dxy), _mm256_load_ps(z), _mm256_load_ps(dz)};
    }
    const int sx = s.lx > kB - 4, sy = s.ly > kB - 4, sz = s.lz > kB - 4;
    if ((sx | sy | sz) == 0) {  // the whole support in one brick
      const std::int32_t slot = *s.slot;
      if (slot < 0) {
        out[i] = fallback(map, p[i], kGradient);
        continue;
      }
      const float* c0 = brick_at(slot) + s.lz * kPlane + s.ly * kRow + 3 * s.lx;
      sum_support<kGradient>(StridedRows{c0, kRow, kPlane}, w, to_world, &out[i]);
      out[i].inside = inside;
      continue;
    }
    // Up to 2 x 2 x 2 bricks; any unallocated one sends the point to the coarse level.
    const float* brick[2][2][2] = {};
    std::int32_t any_missing = 0;
    for (int oz = 0; oz <= sz; ++oz)
      for (int oy = 0; oy <= sy; ++oy)
        for (int ox = 0; ox <= sx; ++ox) {
          const std::int32_t slot = s.slot[oz * brick_plane + oy * brick_row + ox];
          any_missing |= slot;
          brick[oz][oy][ox] = brick_at(slot);
        }
    if (any_missing < 0) {
      out[i] = fallback(map, p[i], kGradient);
      continue;
    }
    const auto fill = [&](auto& rows) VDTNAV_AVX2 {
      std::memcpy(rows.brick, brick, sizeof(brick));
      rows.x_offset = 3 * s.lx;
      for (int q = 0; q < 4; ++q) {
        rows.oy[q] = (s.ly + q) >> 3;
        rows.oz[q] = (s.lz + q) >> 3;
        rows.row_offset[q] = ((s.ly + q) & 7) * kRow;
        rows.plane_offset[q] = ((s.lz + q) & 7) * kPlane;
      }
    };
    if (sx == 0) {
      BrickRows<false> rows;
      fill(rows);
      sum_support<kGradient>(rows, w, to_world, &out[i]);
    } else {
      BrickRows<true> rows;
      fill(rows);
      const __m256i mx3 = _mm256_set1_epi32(3 * (kB - s.lx));  // lanes of the x-lower brick
      rows.lo_ab = _mm256_cmpgt_epi32(mx3, lanes_ab);
      rows.hi_ab = _mm256_xor_si256(rows.lo_ab, _mm256_set1_epi32(-1));
      rows.lo_c = _mm_cmpgt_epi32(_mm256_castsi256_si128(mx3), lanes_c);
      rows.hi_c = _mm_xor_si128(rows.lo_c, _mm_set1_epi32(-1));
      sum_support<kGradient>(rows, w, to_world, &out[i]);
    }
    out[i].inside = inside;
  }
}
#endif  // VDTNAV_HAVE_X86_KERNELS

}  // namespace

SimdLevel simd_level() noexcept { return chosen_level().load(std::memory_order_relaxed); }

SimdLevel set_simd_level(SimdLevel level) noexcept {
  if (level == SimdLevel::kAvx2Fma && !cpu_has_avx2_fma()) level = SimdLevel::kBaseline;
  chosen_level().store(level, std::memory_order_relaxed);
  return level;
}

namespace detail {

template <int Dim>
bool evaluate_simd(const VdtMap<Dim>& map, const typename SpaceTraits<Dim>::Vector* p,
                   std::size_t n, VdtSample<Dim>* out, bool jacobian) {
#if VDTNAV_HAVE_X86_KERNELS
  if (simd_level() != SimdLevel::kAvx2Fma || !map.frame().axis_aligned()) return false;
  if constexpr (Dim == 2) {
    jacobian ? lookup_2d_avx2<true>(map, p, n, out) : lookup_2d_avx2<false>(map, p, n, out);
  } else {
    jacobian ? lookup_3d_avx2<true>(map, p, n, out) : lookup_3d_avx2<false>(map, p, n, out);
  }
  return true;
#else
  (void)map, (void)p, (void)n, (void)out, (void)jacobian;
  return false;
#endif
}

bool evaluate_simd(const SparseVdtMap3& map, const Eigen::Vector3d* p, std::size_t n,
                   VdtSample<3>* out, bool jacobian, SparseFallback fallback) {
#if VDTNAV_HAVE_X86_KERNELS
  if (simd_level() != SimdLevel::kAvx2Fma || !map.frame().axis_aligned()) return false;
  jacobian ? lookup_sparse_avx2<true>(map, p, n, out, fallback)
           : lookup_sparse_avx2<false>(map, p, n, out, fallback);
  return true;
#else
  (void)map, (void)p, (void)n, (void)out, (void)jacobian, (void)fallback;
  return false;
#endif
}

template bool evaluate_simd<2>(const VdtMap<2>&, const Eigen::Vector2d*, std::size_t, VdtSample<2>*,
                               bool);
template bool evaluate_simd<3>(const VdtMap<3>&, const Eigen::Vector3d*, std::size_t, VdtSample<3>*,
                               bool);

}  // namespace detail
}  // namespace vdtnav
