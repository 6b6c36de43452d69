// The baseline kernels of box_overlap_simd.h: SSE2 (part of x86-64) for the n = 4 masks, scalar
// elsewhere; and edge_axis, the exact scalar edge-axis test every level falls back on.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "cover/octree/detail/box_overlap_simd.h"
#include "cover/solid/predicates.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace cover::detail {
namespace baseline {

/// n = 4 with the baseline instructions: SSE2 (part of x86-64), two points per instruction,
/// the signs gathered by movemask; scalar elsewhere.
static void masks4(const double* fx, const double* fy, const double* fz, double b, uint64_t& pos,
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

void cells4(const HalfTerms& fx, const HalfTerms& fy, const HalfTerms& fz, double bound,
            uint32_t cells, uint64_t* pos, uint64_t* neg) {
  for (uint32_t m = cells; m != 0; m &= m - 1) {
    const int c = std::countr_zero(m);
    masks4(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound, pos[c], neg[c]);
  }
}

void masks27(const double* fx, const double* fy, const double* fz, double bound, uint32_t& pos,
             uint32_t& neg) {
  pos = neg = 0;
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) {
        const double f = fx[x] + fy[y] + fz[z];  // sign()'s sum, in its order
        const int i = (z * 3 + y) * 3 + x;
        pos |= uint32_t{f > bound} << i;
        neg |= uint32_t{f < -bound} << i;
      }
}

void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                       int (&out)[3]) {
  out[0] = orient3d(r, q, a, b);
  out[1] = orient3d(r, q, b, c);
  out[2] = orient3d(r, q, c, a);
}

uint8_t edge_axes(const Vec3 (&v)[3], const double (&planes)[3][3], uint8_t alive) {
  for (int axis = 0; axis < 3 && alive != 0; ++axis) {
    const int t = orient2d(v[0], v[1], v[2], axis);
    for (int e = 0; e < 3 && alive != 0; ++e)
      alive = edge_axis(v[e], v[(e + 1) % 3], axis, t, planes, alive);
  }
  return alive;
}

}  // namespace baseline

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

}  // namespace cover::detail
