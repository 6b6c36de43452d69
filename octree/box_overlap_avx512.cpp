// The AVX-512F kernels of box_overlap_simd.h.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "cover/octree/detail/box_overlap_simd.h"
#include "cover/solid/predicates.h"

#if defined(COVER_X86_DISPATCH)
#include <immintrin.h>

namespace cover::detail::avx512 {

// GCC 12's AVX-512 intrinsics start from a self-initialised "undefined" register, which
// -Wuninitialized reports at every use.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
/// n = 4 (64 points), 8 per instruction: lanes i + 4·(j & 1) of rows (j, j + 1).
static __attribute__((target("avx512f"))) void masks4(const double* fx, const double* fy,
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
__attribute__((target("avx512f"))) void cells4(const HalfTerms& fx, const HalfTerms& fy,
                                               const HalfTerms& fz, double bound, uint32_t cells,
                                               uint64_t* pos, uint64_t* neg) {
  for (; cells != 0; cells &= cells - 1) {
    const int c = std::countr_zero(cells);
    masks4(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound, pos[c], neg[c]);
  }
}

/// Lane l of index vector v of axis a: the lattice coordinate along a of point 8v + l (27
/// points, index (z·3 + y)·3 + x; the 5 lanes past 26 repeat point 0 and are masked off).
namespace {

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

}  // namespace

/// The 27 lattice points, 8 per instruction.
__attribute__((target("avx512f"))) void masks27(const double* fx, const double* fy,
                                                const double* fz, double bound, uint32_t& pos,
                                                uint32_t& neg) {
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
#pragma GCC diagnostic pop

}  // namespace cover::detail::avx512
#endif
