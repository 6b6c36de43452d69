#include "cover/octree/detail/box_overlap.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define COVER_X86_DISPATCH 1
#endif

#include "cover/solid/predicates.h"

namespace cover::detail {
namespace {

Bbox lattice_box(const double (&planes)[3][3]) {
  Bbox box;
  box.min = {planes[0][0], planes[1][0], planes[2][0]};
  box.max = {planes[0][2], planes[1][2], planes[2][2]};
  return box;
}

/// The box as octant 0 of a lattice whose split planes are its high faces.
OctantOverlap single_octant(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box) {
  const double planes[3][3] = {{box.min.x, box.max.x, box.max.x},
                               {box.min.y, box.max.y, box.max.y},
                               {box.min.z, box.max.z, box.max.z}};
  return OctantOverlap(a, b, c, planes);
}

/// The side (+1 or −1) that all `count` values sign(0..count−1) lie on: strictly, or when `open`
/// on that side or 0 (all zero: −1); 0 when there is none. Stops at the first value that rules a
/// side out.
template <typename Sign>
int common_side(int count, bool open, Sign sign) {
  int lo = 1, hi = -1;
  for (int i = 0; i < count; ++i) {
    const int s = sign(i);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    if (open ? lo < 0 && hi > 0 : lo <= 0 && hi >= 0) return 0;
  }
  return hi <= 0 ? -1 : 1;
}

Simd detect_simd() {
#if defined(COVER_X86_DISPATCH)
  // libgcc's check includes the OS's support (XCR0) for the wider registers.
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return Simd::kAvx512;
  if (__builtin_cpu_supports("avx2")) return Simd::kAvx2;
#endif
  return Simd::kBaseline;
}

std::atomic<int> g_simd{-1};  ///< the level in use; −1: not chosen yet (best_simd())

// The sign masks of the plane's values f = (fx[i] + fy[j]) + fz[k] (PlaneSide::sign()'s sum, in
// its order) against ±bound, several points per instruction: bit (k·n + j)·n + i set in `pos`
// where f > bound, in `neg` where f < −bound (ordered comparisons, as C's > and <). Hand-
// written (no library offers a sign mask of a separable sum): a bunny00 octree at depth 10
// makes 7.1 M grid_masks and 3 M lattice_masks calls, and the widest instruction set saves about
// 8 % of its CPU time.
/// n = 4 with the baseline instructions: SSE2 (part of x86-64), two points per instruction,
/// the signs gathered by movemask; scalar elsewhere.
void masks4_baseline(const double* fx, const double* fy, const double* fz, double b, uint64_t& pos,
                     uint64_t& neg) {
  pos = neg = 0;
#if defined(__SSE2__)
  const __m128d x01 = _mm_loadu_pd(fx), x23 = _mm_loadu_pd(fx + 2);
  const __m128d hi = _mm_set1_pd(b), lo = _mm_set1_pd(-b);
  for (int row = 0; row < 16; ++row) {
    const __m128d y = _mm_set1_pd(fy[row & 3]), z = _mm_set1_pd(fz[row >> 2]);
    const __m128d f01 = _mm_add_pd(_mm_add_pd(x01, y), z);
    const __m128d f23 = _mm_add_pd(_mm_add_pd(x23, y), z);
    const auto p = static_cast<uint64_t>(_mm_movemask_pd(_mm_cmpgt_pd(f01, hi)) |
                                         _mm_movemask_pd(_mm_cmpgt_pd(f23, hi)) << 2);
    const auto q = static_cast<uint64_t>(_mm_movemask_pd(_mm_cmplt_pd(f01, lo)) |
                                         _mm_movemask_pd(_mm_cmplt_pd(f23, lo)) << 2);
    pos |= p << (4 * row);
    neg |= q << (4 * row);
  }
#else
  for (int row = 0; row < 16; ++row) {
    const double y = fy[row & 3], z = fz[row >> 2];
    const double f0 = (fx[0] + y) + z, f1 = (fx[1] + y) + z, f2 = (fx[2] + y) + z,
                 f3 = (fx[3] + y) + z;
    const uint64_t p =
        uint64_t{f0 > b} | uint64_t{f1 > b} << 1 | uint64_t{f2 > b} << 2 | uint64_t{f3 > b} << 3;
    const uint64_t q = uint64_t{f0 < -b} | uint64_t{f1 < -b} << 1 | uint64_t{f2 < -b} << 2 |
                       uint64_t{f3 < -b} << 3;
    pos |= p << (4 * row);
    neg |= q << (4 * row);
  }
#endif
}

#if defined(COVER_X86_DISPATCH)
// GCC 12's AVX-512 intrinsics start from a self-initialised "undefined" register, which
// -Wuninitialized reports at every use.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
/// n = 4 (64 points), 8 per instruction: lanes i + 4·(j & 1) of rows (j, j + 1).
__attribute__((target("avx512f"))) void masks4_avx512(const double* fx, const double* fy,
                                                      const double* fz, double bound, uint64_t& pos,
                                                      uint64_t& neg) {
  const __m512d x = _mm512_broadcast_f64x4(_mm256_loadu_pd(fx));
  const __m512d xy01 =
      _mm512_add_pd(x, _mm512_insertf64x4(_mm512_set1_pd(fy[0]), _mm256_set1_pd(fy[1]), 1));
  const __m512d xy23 =
      _mm512_add_pd(x, _mm512_insertf64x4(_mm512_set1_pd(fy[2]), _mm256_set1_pd(fy[3]), 1));
  const __m512d hi = _mm512_set1_pd(bound), lo = _mm512_set1_pd(-bound);
  uint64_t p = 0, q = 0;
  for (int k = 0; k < 4; ++k) {
    const __m512d z = _mm512_set1_pd(fz[k]);
    const __m512d f01 = _mm512_add_pd(xy01, z), f23 = _mm512_add_pd(xy23, z);
    p |= (uint64_t{_mm512_cmp_pd_mask(f01, hi, _CMP_GT_OQ)} |
          uint64_t{_mm512_cmp_pd_mask(f23, hi, _CMP_GT_OQ)} << 8)
         << (16 * k);
    q |= (uint64_t{_mm512_cmp_pd_mask(f01, lo, _CMP_LT_OQ)} |
          uint64_t{_mm512_cmp_pd_mask(f23, lo, _CMP_LT_OQ)} << 8)
         << (16 * k);
  }
  pos = p;
  neg = q;
}

/// n = 4, one row of 4 points per instruction.
__attribute__((target("avx2"))) void masks4_avx2(const double* fx, const double* fy,
                                                 const double* fz, double bound, uint64_t& pos,
                                                 uint64_t& neg) {
  const __m256d x = _mm256_loadu_pd(fx);
  __m256d xy[4];
  for (int j = 0; j < 4; ++j) xy[j] = _mm256_add_pd(x, _mm256_set1_pd(fy[j]));
  const __m256d hi = _mm256_set1_pd(bound), lo = _mm256_set1_pd(-bound);
  uint64_t p = 0, q = 0;
  for (int k = 0; k < 4; ++k) {
    const __m256d z = _mm256_set1_pd(fz[k]);
    for (int j = 0; j < 4; ++j) {
      const __m256d f = _mm256_add_pd(xy[j], z);
      const int at = 16 * k + 4 * j;
      p |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(f, hi, _CMP_GT_OQ))) << at;
      q |= static_cast<uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(f, lo, _CMP_LT_OQ))) << at;
    }
  }
  pos = p;
  neg = q;
}

/// The cells of `cells` (bit c: cell c takes half (c >> a) & 1 of axis a), each with masks4.
/// fx[h], fy[h], fz[h]: the plane's terms at a half's 4 sub-point coordinates.
using HalfTerms = double[2][4];
__attribute__((target("avx512f"))) void cells4_avx512(const HalfTerms& fx, const HalfTerms& fy,
                                                      const HalfTerms& fz, double bound,
                                                      uint32_t cells, uint64_t* pos,
                                                      uint64_t* neg) {
  for (; cells != 0; cells &= cells - 1) {
    const int c = std::countr_zero(cells);
    masks4_avx512(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound, pos[c], neg[c]);
  }
}

__attribute__((target("avx2"))) void cells4_avx2(const HalfTerms& fx, const HalfTerms& fy,
                                                 const HalfTerms& fz, double bound, uint32_t cells,
                                                 uint64_t* pos, uint64_t* neg) {
  for (; cells != 0; cells &= cells - 1) {
    const int c = std::countr_zero(cells);
    masks4_avx2(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound, pos[c], neg[c]);
  }
}

/// Lane l of index vector v of axis a: the lattice coordinate along a of point 8v + l (27
/// points, index (z·3 + y)·3 + x; the 5 lanes past 26 repeat point 0 and are masked off).
struct LatticeLanes {
  alignas(64) int64_t index[3][4][8];
  constexpr LatticeLanes() : index{} {
    for (int v = 0; v < 4; ++v)
      for (int l = 0; l < 8; ++l) {
        const int i = 8 * v + l < 27 ? 8 * v + l : 0;
        index[0][v][l] = i % 3;
        index[1][v][l] = i / 3 % 3;
        index[2][v][l] = i / 9;
      }
  }
};
constexpr LatticeLanes kLatticeLanes;

/// The 27 lattice points, 8 per instruction.
__attribute__((target("avx512f"))) void masks27_avx512(const double* fx, const double* fy,
                                                       const double* fz, double bound,
                                                       uint32_t& pos, uint32_t& neg) {
  const __m512d x = _mm512_setr_pd(fx[0], fx[1], fx[2], 0, 0, 0, 0, 0);
  const __m512d y = _mm512_setr_pd(fy[0], fy[1], fy[2], 0, 0, 0, 0, 0);
  const __m512d z = _mm512_setr_pd(fz[0], fz[1], fz[2], 0, 0, 0, 0, 0);
  const __m512d hi = _mm512_set1_pd(bound), lo = _mm512_set1_pd(-bound);
  uint32_t p = 0, q = 0;
  for (int v = 0; v < 4; ++v) {
    // (a lambda would not inherit the target attribute)
    const __m512d xv = _mm512_permutexvar_pd(_mm512_load_si512(kLatticeLanes.index[0][v]), x);
    const __m512d yv = _mm512_permutexvar_pd(_mm512_load_si512(kLatticeLanes.index[1][v]), y);
    const __m512d zv = _mm512_permutexvar_pd(_mm512_load_si512(kLatticeLanes.index[2][v]), z);
    const __m512d f = _mm512_add_pd(_mm512_add_pd(xv, yv), zv);
    p |= uint32_t{_mm512_cmp_pd_mask(f, hi, _CMP_GT_OQ)} << (8 * v);
    q |= uint32_t{_mm512_cmp_pd_mask(f, lo, _CMP_LT_OQ)} << (8 * v);
  }
  constexpr uint32_t kAll27 = (uint32_t{1} << 27) - 1;
  pos = p & kAll27;
  neg = q & kAll27;
}

/// The 27 lattice points, one row of 3 per instruction (the 4th lane repeats x = 2, masked).
__attribute__((target("avx2"))) void masks27_avx2(const double* fx, const double* fy,
                                                  const double* fz, double bound, uint32_t& pos,
                                                  uint32_t& neg) {
  const __m256d x = _mm256_setr_pd(fx[0], fx[1], fx[2], fx[2]);
  const __m256d hi = _mm256_set1_pd(bound), lo = _mm256_set1_pd(-bound);
  uint32_t p = 0, q = 0;
  for (int k = 0; k < 3; ++k) {
    const __m256d z = _mm256_set1_pd(fz[k]);
    for (int j = 0; j < 3; ++j) {
      const __m256d f = _mm256_add_pd(_mm256_add_pd(x, _mm256_set1_pd(fy[j])), z);
      const int at = 3 * (3 * k + j);
      p |= static_cast<uint32_t>(_mm256_movemask_pd(_mm256_cmp_pd(f, hi, _CMP_GT_OQ)) & 7) << at;
      q |= static_cast<uint32_t>(_mm256_movemask_pd(_mm256_cmp_pd(f, lo, _CMP_LT_OQ)) & 7) << at;
    }
  }
  pos = p;
  neg = q;
}
#pragma GCC diagnostic pop

/// edge_orientations with the 3 edges in the lanes of one AVX2 register (lane 3 unused): each
/// lane evaluates orient3d's filtered determinant and permanent as orient3d does, operation for
/// operation; a lane the filter leaves undecided goes to orient3d_exact.
__attribute__((target("avx2"))) void edge_orientations_avx2(const Vec3& r, const Vec3& q,
                                                            const Vec3& a, const Vec3& b,
                                                            const Vec3& c, int (&out)[3]) {
  const Vec3* v[3] = {&a, &b, &c};
  const __m256d sign_bit = _mm256_set1_pd(-0.0);
  // orient3d(r, q, C, D) for lane e: C = v[e], D = v[(e + 1) % 3].
  __m256d ad[3], bd[3], cd[3];
  for (int k = 0; k < 3; ++k) {
    const __m256d ck = _mm256_setr_pd((*v[0])[k], (*v[1])[k], (*v[2])[k], (*v[0])[k]);
    const __m256d dk = _mm256_permute4x64_pd(ck, 0x49);  // lanes 1, 2, 0, 1
    ad[k] = _mm256_sub_pd(_mm256_set1_pd(r[k]), dk);
    bd[k] = _mm256_sub_pd(_mm256_set1_pd(q[k]), dk);
    cd[k] = _mm256_sub_pd(ck, dk);
  }
  const __m256d bdxcdy = _mm256_mul_pd(bd[0], cd[1]), cdxbdy = _mm256_mul_pd(cd[0], bd[1]);
  const __m256d cdxady = _mm256_mul_pd(cd[0], ad[1]), adxcdy = _mm256_mul_pd(ad[0], cd[1]);
  const __m256d adxbdy = _mm256_mul_pd(ad[0], bd[1]), bdxady = _mm256_mul_pd(bd[0], ad[1]);
  const __m256d det =
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ad[2], _mm256_sub_pd(bdxcdy, cdxbdy)),
                                  _mm256_mul_pd(bd[2], _mm256_sub_pd(cdxady, adxcdy))),
                    _mm256_mul_pd(cd[2], _mm256_sub_pd(adxbdy, bdxady)));
  const __m256d permanent = _mm256_add_pd(
      _mm256_add_pd(_mm256_mul_pd(_mm256_add_pd(_mm256_andnot_pd(sign_bit, bdxcdy),
                                                _mm256_andnot_pd(sign_bit, cdxbdy)),
                                  _mm256_andnot_pd(sign_bit, ad[2])),
                    _mm256_mul_pd(_mm256_add_pd(_mm256_andnot_pd(sign_bit, cdxady),
                                                _mm256_andnot_pd(sign_bit, adxcdy)),
                                  _mm256_andnot_pd(sign_bit, bd[2]))),
      _mm256_mul_pd(
          _mm256_add_pd(_mm256_andnot_pd(sign_bit, adxbdy), _mm256_andnot_pd(sign_bit, bdxady)),
          _mm256_andnot_pd(sign_bit, cd[2])));
  const __m256d in_range =
      _mm256_and_pd(_mm256_cmp_pd(permanent, _mm256_set1_pd(kFilterMin), _CMP_GT_OQ),
                    _mm256_cmp_pd(permanent, _mm256_set1_pd(kFilterMax), _CMP_LT_OQ));
  const __m256d bound = _mm256_mul_pd(_mm256_set1_pd(kOrient3dErr), permanent);
  // Shewchuk's sign of det, negated (orient3d's convention).
  const int above =
      _mm256_movemask_pd(_mm256_and_pd(in_range, _mm256_cmp_pd(det, bound, _CMP_GT_OQ)));
  const int below = _mm256_movemask_pd(
      _mm256_and_pd(in_range, _mm256_cmp_pd(det, _mm256_xor_pd(bound, sign_bit), _CMP_LT_OQ)));
  for (int e = 0; e < 3; ++e)
    out[e] = above >> e & 1   ? -1
             : below >> e & 1 ? 1
                              : orient3d_exact(r, q, *v[e], *v[(e + 1) % 3]);
}
#endif

}  // namespace

void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                       int (&out)[3]) {
#if defined(COVER_X86_DISPATCH)
  if (simd() >= Simd::kAvx2) return edge_orientations_avx2(r, q, a, b, c, out);
#endif
  out[0] = orient3d(r, q, a, b);
  out[1] = orient3d(r, q, b, c);
  out[2] = orient3d(r, q, c, a);
}

Simd best_simd() {
  static const Simd best = detect_simd();
  return best;
}

Simd simd() {
  const int level = g_simd.load(std::memory_order_relaxed);
  return level < 0 ? best_simd() : static_cast<Simd>(level);
}

void use_simd(Simd level) {
  g_simd.store(static_cast<int>(std::min(level, best_simd())), std::memory_order_relaxed);
}

bool triangle_meets_box(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box) {
  return single_octant(a, b, c, box).meets(0);
}

bool triangle_crosses_box(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box) {
  return single_octant(a, b, c, box).crosses(0);
}

OctantOverlap::OctantOverlap(const Vec3& a, const Vec3& b, const Vec3& c,
                             const double (&planes)[3][3])
    : v_{a, b, c},
      lo_{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})},
      hi_{std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})},
      plane_(a, b, c, lattice_box(planes)) {
  std::memcpy(planes_, planes, sizeof planes_);
  plane_.grid_signs(planes[0], planes[1], planes[2], 3, plane_cache_, 1);
  std::fill(std::begin(third_cache_), std::end(third_cache_), kUnknown);
  std::fill(std::begin(skip_), std::end(skip_), kUnknown);
}

bool OctantOverlap::skip(int e, int axis) {
  int8_t& skip = skip_[e * 3 + axis];
  if (skip != kUnknown) return skip != 0;
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  const Vec3 &p = v_[e], &q = v_[(e + 1) % 3];
  skip = 1;
  if (p[u] == q[u] && p[w] == q[w]) return true;  // the zero axis separates nothing
  // The edge filter at the 9 lattice points of the plane dropping `axis`.
  const double cu = p[w] - q[w], cw = q[u] - p[u];  // exact signs (one rounded subtraction)
  double gu[3], gw[3];
  for (int i = 0; i < 3; ++i) {
    gu[i] = cu * (planes_[u][i] - p[u]);
    gw[i] = cw * (planes_[w][i] - p[w]);
  }
  const double mag =
      std::max(std::abs(gu[0]), std::abs(gu[2])) + std::max(std::abs(gw[0]), std::abs(gw[2]));
  int8_t* signs = edge_cache_[e * 3 + axis];
  int lo = 1, hi = -1;  // the signs' range, kUnknown counting as both
  if (in_filter_range(mag)) {
    const double bound = kPlaneSideErr * mag;
    // The common case first: the whole lattice strictly on the third vertex's side. The 9
    // computed values gu[iu] + gw[iw] are monotone in iu and in iw (the planes ascend, rounding
    // is monotone), so their least (greatest) is the sum of the least (greatest) terms: one
    // sum decides "all 9 above the bound" exactly as the 9 would.
    const int third = third_sign(e, axis);
    if (third > 0 && std::min(gu[0], gu[2]) + std::min(gw[0], gw[2]) > bound) return true;
    if (third < 0 && std::max(gu[0], gu[2]) + std::max(gw[0], gw[2]) < -bound) return true;
    for (int iw = 0; iw < 3; ++iw)
      for (int iu = 0; iu < 3; ++iu) {
        const double g = gu[iu] + gw[iw];
        const int8_t sign = g > bound ? 1 : (g < -bound ? -1 : kUnknown);
        signs[iw * 3 + iu] = sign;
        lo = std::min(lo, sign == kUnknown ? -1 : int{sign});
        hi = std::max(hi, sign == kUnknown ? 1 : int{sign});
      }
  } else {
    // No filter (e.g. mag = 0: a point box on the edge's line): every sign is left to
    // orient2d. The row must be marked, it is read by edge_sign() next.
    std::fill(signs, signs + 9, kUnknown);
    lo = -1;
    hi = 1;
  }
  // The whole lattice strictly on the third vertex's side: no octant is separated by this axis.
  if (!(lo == hi && lo == third_sign(e, axis))) skip = 0;
  return skip != 0;
}

int OctantOverlap::third_sign(int e, int axis) {
  int8_t& third = third_cache_[e * 3 + axis];
  if (third == kUnknown) {
    // orient2d(v_e, v_e+1, v_e+2) is the projected triangle's orientation, the same for the
    // three edges (a cyclic permutation): one exact predicate per axis.
    third = static_cast<int8_t>(orient2d(v_[e], v_[(e + 1) % 3], v_[(e + 2) % 3], axis));
    for (int f = 0; f < 3; ++f) third_cache_[f * 3 + axis] = third;
  }
  return third;
}

int OctantOverlap::edge_sign(int e, int axis, int iu, int iw) {
  int8_t& s = edge_cache_[e * 3 + axis][iw * 3 + iu];
  if (s == kUnknown) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    double x[3] = {planes_[0][0], planes_[1][0], planes_[2][0]};  // the dropped one is irrelevant
    x[u] = planes_[u][iu];
    x[w] = planes_[w][iw];
    s = static_cast<int8_t>(orient2d(v_[e], v_[(e + 1) % 3], Vec3{x[0], x[1], x[2]}, axis));
  }
  return s;
}

bool OctantOverlap::separated(int o, bool open) {
  const int bit[3] = {o & 1, (o >> 1) & 1, (o >> 2) & 1};
  // Box normals: the triangle's box against the octant (exact comparisons).
  for (int k = 0; k < 3; ++k) {
    const double lo = planes_[k][bit[k]], hi = planes_[k][bit[k] + 1];
    if (open ? lo_[k] >= hi || hi_[k] <= lo : lo_[k] > hi || hi_[k] < lo) return true;
  }
  // The triangle's normal: all 8 corners on one side of its plane.
  const auto corner = [&](int c) {
    return int{
        plane_cache_[((bit[2] + (c >> 2)) * 3 + bit[1] + ((c >> 1) & 1)) * 3 + bit[0] + (c & 1)]};
  };
  if (common_side(8, open, corner) != 0) return true;
  // e_axis × edge: in the plane that drops `axis`, the octant's rectangle on one side of the
  // edge's line and the third vertex (hence the triangle) on the line or the other side. An
  // edge parallel to e_axis gives the zero axis, which separates nothing.
  for (int e = 0; e < 3; ++e)
    for (int axis = 0; axis < 3; ++axis) {
      if (skip(e, axis)) continue;
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const int iu = bit[u], iw = bit[w];
      const int side = common_side(
          4, open, [&](int c) { return edge_sign(e, axis, iu + (c & 1), iw + (c >> 1)); });
      if (side == 0) continue;
      if (third_sign(e, axis) != side) return true;
    }
  return false;
}

// Octant o has bit (o >> k) & 1 = half h along axis k: the octants of a half along k, and of a
// quadrant (hu, hw) of the plane dropping an axis.
constexpr uint8_t kHalf[3][2] = {{0x55, 0xAA}, {0x33, 0xCC}, {0x0F, 0xF0}};

namespace {

/// Bit i of m set where bit i, i+1, i+3 or i+4 of m is (a 3 × 3 lattice, index 3·row + column):
/// for each quadrant's low corner, whether any of its 4 corners is set.
constexpr uint32_t spread9(uint32_t m) {
  m |= m >> 1;
  return m | m >> 3;
}

}  // namespace

uint8_t crossed_octants(const Vec3& a, const Vec3& b, const Vec3& c, const double (&planes)[3][3],
                        uint8_t wanted) {
  if (wanted == 0) return 0;
  Bbox box;
  box.min = {planes[0][0], planes[1][0], planes[2][0]};
  box.max = {planes[0][2], planes[1][2], planes[2][2]};
  uint32_t pos = 0, neg = 0;
  PlaneSide(a, b, c, box).lattice_masks(planes, pos, neg);
  return crossed_octants(a, b, c, planes, pos, neg, wanted);
}

namespace {

/// The octants of `alive` that the axis e_axis × (q − p) does not separate from the triangle
/// (t: its projected orientation, orient2d(a, b, c, axis)): in the plane that drops `axis`, per
/// quadrant of the lattice, the quadrant's rectangle weakly on one side of the edge's line and
/// the triangle on the line or the other side.
uint8_t edge_axis(const Vec3& p, const Vec3& q, int axis, int t, const double (&planes)[3][3],
                  uint8_t alive) {
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  if (p[u] == q[u] && p[w] == q[w]) return alive;  // the zero axis separates nothing
  // orient2d(p, q, x) = cu·(x_u − p_u) + cw·(x_w − p_w), its coefficients' signs exact.
  const double cu = p[w] - q[w], cw = q[u] - p[u];
  double gu[3], gw[3];
  for (int i = 0; i < 3; ++i) {
    gu[i] = cu * (planes[u][i] - p[u]);
    gw[i] = cw * (planes[w][i] - p[w]);
  }
  const double mag =
      std::max(std::abs(gu[0]), std::abs(gu[2])) + std::max(std::abs(gw[0]), std::abs(gw[2]));
  uint32_t pos = 0, neg = 0;
  if (in_filter_range(mag)) {
    const double bound = kPlaneSideErr * mag;
    // The common case: the whole lattice strictly on the third vertex's side (the sums are
    // monotone in iu and iw: one sum decides it exactly as the 9 would).
    if (t > 0 && std::min(gu[0], gu[2]) + std::min(gw[0], gw[2]) > bound) return alive;
    if (t < 0 && std::max(gu[0], gu[2]) + std::max(gw[0], gw[2]) < -bound) return alive;
    for (int iw = 0; iw < 3; ++iw)
      for (int iu = 0; iu < 3; ++iu) {
        const double g = gu[iu] + gw[iw];
        pos |= uint32_t{g > bound} << (iw * 3 + iu);
        neg |= uint32_t{g < -bound} << (iw * 3 + iu);
      }
  }
  for (uint32_t m = ~(pos | neg) & 0x1FF; m != 0; m &= m - 1) {
    const int i = std::countr_zero(m);
    double x[3] = {planes[0][0], planes[1][0], planes[2][0]};  // the dropped one: irrelevant
    x[u] = planes[u][i % 3];
    x[w] = planes[w][i / 3];
    const int s = orient2d(p, q, Vec3{x[0], x[1], x[2]}, axis);
    pos |= uint32_t{s > 0} << i;
    neg |= uint32_t{s < 0} << i;
  }
  const uint32_t any_pos = spread9(pos), any_neg = spread9(neg);
  for (int hw = 0; hw < 2; ++hw)
    for (int hu = 0; hu < 2; ++hu) {
      const int at = hw * 3 + hu;
      const bool hp = any_pos >> at & 1, hn = any_neg >> at & 1;
      // The rectangle's side: 0 when it has corners strictly on both sides, else +1 when one
      // is strictly positive, else −1 (all ≤ 0); separated when that side is not 0 and not the
      // third vertex's.
      const bool separated = t > 0 ? !hp : (t < 0 ? hp && !hn : !(hp && hn));
      if (separated) alive &= static_cast<uint8_t>(~(kHalf[u][hu] & kHalf[w][hw]));
    }
  return alive;
}

#if defined(COVER_X86_DISPATCH)
/// The 9 edge axes, one coordinate axis at a time with the 3 edges in the lanes of one AVX2
/// register (lane 3 unused): edge_axis's sums at all 9 lattice points, the quadrants' sides
/// by lane masks. A lane whose magnitude is outside the filter's range or with a point the
/// filter leaves undecided goes through edge_axis (orient2d). Hand-written: the scalar loop, an
/// edge and axis at a time, would be about 30% of an octree build's CPU time (bunny00, depth 10).
__attribute__((target("avx2"))) uint8_t edge_axes_avx2(const Vec3 (&v)[3],
                                                       const double (&planes)[3][3],
                                                       uint8_t alive) {
  const __m256d sign_bit = _mm256_set1_pd(-0.0);
  const __m256d err = _mm256_set1_pd(kPlaneSideErr);
  const __m256d mag_lo = _mm256_set1_pd(kFilterMin), mag_hi = _mm256_set1_pd(kFilterMax);
  const __m256d zero = _mm256_setzero_pd();
  // Lane e: edge e from p = v[e] to q = v[(e + 1) % 3]; p's and q's coordinate k.
  __m256d ps[3], qs[3];
  for (int k = 0; k < 3; ++k) {
    ps[k] = _mm256_setr_pd(v[0][k], v[1][k], v[2][k], v[0][k]);
    qs[k] = _mm256_permute4x64_pd(ps[k], 0x09);  // lanes 1, 2, 0, 0
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (alive == 0) return 0;
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    const int t = orient2d(v[0], v[1], v[2], axis);
    const __m256d pu = ps[u], pw = ps[w], qu = qs[u], qw = qs[w];
    const __m256d cu = _mm256_sub_pd(pw, qw), cw = _mm256_sub_pd(qu, pu);
    __m256d gu[3], gw[3];
    for (int i = 0; i < 3; ++i) {
      gu[i] = _mm256_mul_pd(cu, _mm256_sub_pd(_mm256_set1_pd(planes[u][i]), pu));
      gw[i] = _mm256_mul_pd(cw, _mm256_sub_pd(_mm256_set1_pd(planes[w][i]), pw));
    }
    const __m256d mag = _mm256_add_pd(
        _mm256_max_pd(_mm256_andnot_pd(sign_bit, gu[0]), _mm256_andnot_pd(sign_bit, gu[2])),
        _mm256_max_pd(_mm256_andnot_pd(sign_bit, gw[0]), _mm256_andnot_pd(sign_bit, gw[2])));
    const __m256d hi = _mm256_mul_pd(err, mag);
    const __m256d lo = _mm256_xor_pd(hi, sign_bit);
    __m256d pos[9], neg[9];
    __m256d decided = _mm256_and_pd(_mm256_cmp_pd(mag, mag_lo, _CMP_GT_OQ),
                                    _mm256_cmp_pd(mag, mag_hi, _CMP_LT_OQ));
    for (int iw = 0; iw < 3; ++iw)
      for (int iu = 0; iu < 3; ++iu) {
        const __m256d g = _mm256_add_pd(gu[iu], gw[iw]);
        pos[iw * 3 + iu] = _mm256_cmp_pd(g, hi, _CMP_GT_OQ);
        neg[iw * 3 + iu] = _mm256_cmp_pd(g, lo, _CMP_LT_OQ);
        decided = _mm256_and_pd(decided, _mm256_or_pd(pos[iw * 3 + iu], neg[iw * 3 + iu]));
      }
    // The zero axis (an edge parallel to e_axis: cu = cw = 0 exactly) separates nothing.
    const int zero_axis = _mm256_movemask_pd(
        _mm256_and_pd(_mm256_cmp_pd(cu, zero, _CMP_EQ_OQ), _mm256_cmp_pd(cw, zero, _CMP_EQ_OQ)));
    const int exact = ~_mm256_movemask_pd(decided) & ~zero_axis & 7;
    const int vector_lanes = ~exact & ~zero_axis & 7;
    for (int hw = 0; hw < 2; ++hw)
      for (int hu = 0; hu < 2; ++hu) {
        const int c = hw * 3 + hu;  // the quadrant's low corner
        const __m256d hp =
            _mm256_or_pd(_mm256_or_pd(pos[c], pos[c + 1]), _mm256_or_pd(pos[c + 3], pos[c + 4]));
        const __m256d hn =
            _mm256_or_pd(_mm256_or_pd(neg[c], neg[c + 1]), _mm256_or_pd(neg[c + 3], neg[c + 4]));
        // edge_axis's rule: separated when t > 0 and no corner is strictly positive, t < 0 and
        // one is but none is strictly negative, t = 0 and not both.
        const int any_pos = _mm256_movemask_pd(hp), any_neg = _mm256_movemask_pd(hn);
        const int separated =
            t > 0 ? ~any_pos : (t < 0 ? any_pos & ~any_neg : ~(any_pos & any_neg));
        if (separated & vector_lanes) alive &= static_cast<uint8_t>(~(kHalf[u][hu] & kHalf[w][hw]));
      }
    for (int m = exact; m != 0; m &= m - 1) {
      const int e = std::countr_zero(static_cast<unsigned>(m));
      alive = edge_axis(v[e], v[(e + 1) % 3], axis, t, planes, alive);
    }
  }
  return alive;
}
#endif

}  // namespace

uint8_t crossed_octants(const Vec3& a, const Vec3& b, const Vec3& c, const double (&planes)[3][3],
                        uint32_t pos, uint32_t neg, uint8_t wanted) {
  const Vec3 v[3] = {a, b, c};
  uint8_t alive = wanted;
  // Box normals (exact comparisons), per half: lo ≥ the half's high face or hi ≤ its low face.
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({a[k], b[k], c[k]}), hi = std::max({a[k], b[k], c[k]});
    if (lo >= planes[k][1] || hi <= planes[k][0]) alive &= static_cast<uint8_t>(~kHalf[k][0]);
    if (lo >= planes[k][2] || hi <= planes[k][1]) alive &= static_cast<uint8_t>(~kHalf[k][1]);
  }
  // The triangle's normal: an octant survives when it has a corner strictly on each side.
  const uint32_t both = spread27(pos) & spread27(neg);
  for (int o = 0; o < 8; ++o)
    if (!(both >> kOctantCorner[o] & 1)) alive &= static_cast<uint8_t>(~(1u << o));
  if (alive == 0) return 0;
    // e_axis × edge for the 9 pairs.
#if defined(COVER_X86_DISPATCH)
  if (simd() >= Simd::kAvx2) return edge_axes_avx2(v, planes, alive);
#endif
  for (int axis = 0; axis < 3 && alive != 0; ++axis) {
    const int t = orient2d(v[0], v[1], v[2], axis);
    for (int e = 0; e < 3 && alive != 0; ++e)
      alive = edge_axis(v[e], v[(e + 1) % 3], axis, t, planes, alive);
  }
  return alive;
}

uint8_t OctantOverlap::crossed_octants(uint8_t wanted) {
  return detail::crossed_octants(v_[0], v_[1], v_[2], planes_, wanted);
}

PlaneSide::PlaneSide(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box)
    : a_(a), b_(b), c_(c), bound_(std::numeric_limits<double>::infinity()) {
  const Vec3 u = b - a, v = c - a;
  normal_ = cross(u, v);
  // Error analysis (u = 2⁻⁵³, γ_k = ku/(1 − ku)): with P_i = |u_j v_k| + |u_k v_j| (the
  // permanent of n_i) and d = p − a, |ñ_i − n_i| ≤ γ_4·P_i and the dot product of ñ with the
  // rounded d adds ≤ γ_4·Σ|ñ_i||d_i|, so |ñ·d̃ − n·d| ≤ ~8u·Σ P_i|d_i|. Over the box
  // |d_i| ≤ max(|lo_i − a_i|, |hi_i − a_i|); 16u leaves a factor 2 for the rounding of the
  // bound itself (detail::kPlaneBoxErr = 16u). Outside the filter range (solid/predicates.h)
  // under/overflow could void it: orient3d decides alone.
  const double perm[3] = {std::abs(u.y * v.z) + std::abs(u.z * v.y),
                          std::abs(u.z * v.x) + std::abs(u.x * v.z),
                          std::abs(u.x * v.y) + std::abs(u.y * v.x)};
  double sum = 0;
  for (int i = 0; i < 3; ++i)
    sum += perm[i] * std::max(std::abs(box.min[i] - a[i]), std::abs(box.max[i] - a[i]));
  if (in_filter_range(sum)) bound_ = kPlaneBoxErr * sum;
}

int PlaneSide::exact_sign(const Vec3& p) const { return orient3d(a_, b_, c_, p); }

void PlaneSide::grid_signs(const double* xs, const double* ys, const double* zs, int n, int8_t* out,
                           size_t stride) const {
  double fx[32], fy[32], fz[32];
  for (int i = 0; i < n; ++i) {
    fx[i] = normal_.x * (xs[i] - a_.x);
    fy[i] = normal_.y * (ys[i] - a_.y);
    fz[i] = normal_.z * (zs[i] - a_.z);
  }
  // Filtered signs first (branch-free, one row at a time), orient3d for the undecided ones.
  size_t o = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j) {
      const double yz = fy[j];
      const double z = fz[k];
      bool undecided = false;
      for (int i = 0; i < n; ++i) {
        const double f = fx[i] + yz + z;  // sign()'s sum, in its order
        const bool pos = f > bound_, neg = f < -bound_;
        out[o + i * stride] = static_cast<int8_t>(int{pos} - int{neg});
        undecided |= !(pos | neg);
      }
      if (undecided)
        for (int i = 0; i < n; ++i) {
          const double f = fx[i] + yz + z;
          if (!(f > bound_) && !(f < -bound_))
            out[o + i * stride] = static_cast<int8_t>(exact_sign({xs[i], ys[j], zs[k]}));
        }
      o += size_t(n) * stride;
    }
}

void PlaneSide::lattice_masks(const double (&planes)[3][3], uint32_t& pos, uint32_t& neg) const {
  double fx[3], fy[3], fz[3];
  for (int i = 0; i < 3; ++i) {
    fx[i] = normal_.x * (planes[0][i] - a_.x);
    fy[i] = normal_.y * (planes[1][i] - a_.y);
    fz[i] = normal_.z * (planes[2][i] - a_.z);
  }
  pos = neg = 0;
#if defined(COVER_X86_DISPATCH)
  const Simd level = simd();
  if (level == Simd::kAvx512)
    masks27_avx512(fx, fy, fz, bound_, pos, neg);
  else if (level == Simd::kAvx2)
    masks27_avx2(fx, fy, fz, bound_, pos, neg);
  else
#endif
    for (int z = 0; z < 3; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) {
          const double f = fx[x] + fy[y] + fz[z];  // sign()'s sum, in its order
          const int i = (z * 3 + y) * 3 + x;
          pos |= uint32_t{f > bound_} << i;
          neg |= uint32_t{f < -bound_} << i;
        }
  for (uint32_t m = ~(pos | neg) & 0x7FFFFFF; m != 0; m &= m - 1) {
    const int i = std::countr_zero(m);
    const int s = exact_sign({planes[0][i % 3], planes[1][i / 3 % 3], planes[2][i / 9]});
    pos |= uint32_t{s > 0} << i;
    neg |= uint32_t{s < 0} << i;
  }
}

void PlaneSide::grid_masks(const double* xs, const double* ys, const double* zs, int n,
                           uint64_t& pos, uint64_t& neg) const {
  if (n != 4) {
    int8_t signs[64];
    grid_signs(xs, ys, zs, n, signs, 1);
    pos = neg = 0;
    for (int p = 0; p < n * n * n; ++p) {
      pos |= uint64_t{signs[p] > 0} << p;
      neg |= uint64_t{signs[p] < 0} << p;
    }
    return;
  }
  // n = 4: cell_masks with one cell (cell 0 takes the low half of every axis).
  const double* const x[2] = {xs, xs};
  const double* const y[2] = {ys, ys};
  const double* const z[2] = {zs, zs};
  cell_masks(x, y, z, 4, 1, &pos, &neg);
}

void PlaneSide::cell_masks(const double* const (&xs)[2], const double* const (&ys)[2],
                           const double* const (&zs)[2], int n, uint8_t cells, uint64_t* pos,
                           uint64_t* neg) const {
  if (n != 4) {
    for (uint32_t m = cells; m != 0; m &= m - 1) {
      const int c = std::countr_zero(m);
      grid_masks(xs[c & 1], ys[(c >> 1) & 1], zs[c >> 2], n, pos[c], neg[c]);
    }
    return;
  }
  // sign()'s products, once per half: the cells taking a half share them.
  double fx[2][4], fy[2][4], fz[2][4];
  for (int h = 0; h < 2; ++h)
    for (int i = 0; i < 4; ++i) {
      fx[h][i] = normal_.x * (xs[h][i] - a_.x);
      fy[h][i] = normal_.y * (ys[h][i] - a_.y);
      fz[h][i] = normal_.z * (zs[h][i] - a_.z);
    }
#if defined(COVER_X86_DISPATCH)
  const Simd level = simd();
  if (level == Simd::kAvx512)
    cells4_avx512(fx, fy, fz, bound_, cells, pos, neg);
  else if (level == Simd::kAvx2)
    cells4_avx2(fx, fy, fz, bound_, cells, pos, neg);
  else
#endif
    for (uint32_t m = cells; m != 0; m &= m - 1) {
      const int c = std::countr_zero(m);
      masks4_baseline(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound_, pos[c], neg[c]);
    }
  // Points the filter leaves undecided: orient3d.
  for (uint32_t m = cells; m != 0; m &= m - 1) {
    const int c = std::countr_zero(m);
    const double *x = xs[c & 1], *y = ys[(c >> 1) & 1], *z = zs[c >> 2];
    for (uint64_t u = ~(pos[c] | neg[c]); u != 0; u &= u - 1) {
      const int p = std::countr_zero(u);
      const int sign = exact_sign({x[p & 3], y[(p >> 2) & 3], z[p >> 4]});
      pos[c] |= uint64_t{sign > 0} << p;
      neg[c] |= uint64_t{sign < 0} << p;
    }
  }
}

}  // namespace cover::detail
