// The AVX2 kernels of box_overlap_simd.h.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "cover/octree/detail/box_overlap_simd.h"
#include "cover/solid/predicates.h"

#if defined(COVER_X86_DISPATCH)
#include <immintrin.h>

namespace cover::detail::avx2 {

/// n = 4, one row of 4 points per instruction.
static __attribute__((target("avx2"))) void masks4(const double* fx, const double* fy,
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

__attribute__((target("avx2"))) void cells4(const HalfTerms& fx, const HalfTerms& fy,
                                            const HalfTerms& fz, double bound, uint32_t cells,
                                            uint64_t* pos, uint64_t* neg) {
  for (; cells != 0; cells &= cells - 1) {
    const int c = std::countr_zero(cells);
    masks4(fx[c & 1], fy[(c >> 1) & 1], fz[c >> 2], bound, pos[c], neg[c]);
  }
}

/// The 27 lattice points, one row of 3 per instruction (the 4th lane repeats x = 2, masked).
__attribute__((target("avx2"))) void masks27(const double* fx, const double* fy, const double* fz,
                                             double bound, uint32_t& pos, uint32_t& neg) {
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

/// edge_orientations with the 3 edges in the lanes of one AVX2 register (lane 3 unused): each
/// lane evaluates orient3d's filtered determinant and permanent as orient3d does, operation for
/// operation; a lane the filter leaves undecided goes to orient3d_exact.
__attribute__((target("avx2"))) void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a,
                                                       const Vec3& b, const Vec3& c,
                                                       int (&out)[3]) {
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

/// The 9 edge axes, one coordinate axis at a time with the 3 edges in the lanes of one AVX2
/// register (lane 3 unused): edge_axis's sums at all 9 lattice points, the quadrants' sides
/// by lane masks. A lane whose magnitude is outside the filter's range or with a point the
/// filter leaves undecided goes through edge_axis (orient2d). Hand-written: the scalar loop, an
/// edge and axis at a time, would be about 30% of an octree build's CPU time (bunny00, depth 10).
__attribute__((target("avx2"))) uint8_t edge_axes(const Vec3 (&v)[3], const double (&planes)[3][3],
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

}  // namespace cover::detail::avx2
#endif
