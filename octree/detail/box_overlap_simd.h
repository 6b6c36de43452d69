#pragma once
// The vector kernels of the box-overlap predicates (box_overlap.h), one file per instruction set
// behind one interface, the table SimdKernels: box_overlap_baseline.cpp (SSE2, part of x86-64;
// scalar elsewhere), box_overlap_avx2.cpp and box_overlap_avx512.cpp. box_overlap.cpp picks the
// table of simd() (box_overlap.h). Every table computes the same sums in the same order (IEEE
// doubles, no contraction), so every table gives the same signs; the tests compare them.
// Idiom: Cover's portable 128-bit loops use GCC's vector extensions (solid/simd.h); these kernels
// gather comparison signs into bit masks (movemask, AVX-512 mask registers), which the vector
// extensions cannot express, so they use intrinsics. Each wider function carries its own target
// attribute (here and at its definition) and is called only when the CPU has the set: compiling
// a whole file with -mavx2 would let inline functions of shared headers be emitted with AVX2
// instructions and picked by the linker for baseline code.
// Why hand-written: no library offers a sign mask of a separable sum; a bunny00 octree at depth
// 10 makes 7.1 M grid_masks and 3 M lattice_masks calls, and the widest instruction set saves
// about 8 % of its CPU time; the scalar edge axes would be about 30 % of the build.

#include <cstdint>

#include "cover/solid/types.h"

#if defined(__x86_64__) && defined(__GNUC__)
#define COVER_X86_DISPATCH 1
#endif

namespace cover::detail {

/// A plane's terms at 4 sub-point coordinates per half of each axis: fx[h][i] = n.x·(x_i − a.x)
/// of half h, and so on (PlaneSide::cell_masks).
using HalfTerms = double[2][4];

/// One instruction set's kernels. The masks of the plane's values f = (fx[i] + fy[j]) + fz[k]
/// (PlaneSide::sign()'s sum, in its order) against ±bound: bit (k·n + j)·n + i set in `pos` where
/// f > bound, in `neg` where f < −bound (ordered comparisons, as C's > and <).
struct SimdKernels {
  /// The cells of `cells` (bit c: cell c takes half (c >> a) & 1 of axis a), n = 4 each: cell c's
  /// masks in pos[c] and neg[c].
  void (*cells4)(const HalfTerms& fx, const HalfTerms& fy, const HalfTerms& fz, double bound,
                 uint32_t cells, uint64_t* pos, uint64_t* neg);
  /// The 27 points of a 3 × 3 × 3 lattice (n = 3).
  void (*masks27)(const double* fx, const double* fy, const double* fz, double bound, uint32_t& pos,
                  uint32_t& neg);
  /// edge_orientations (box_overlap.h): orient3d(r, q, a, b), (r, q, b, c), (r, q, c, a), exact.
  void (*edge_orientations)(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b,
                            const Vec3& c, int (&out)[3]);
  /// crossed_octants' 9 edge axes e_axis × edge over the triangle v: the octants of `alive` that
  /// none of them separates (edge_axis for each pair).
  uint8_t (*edge_axes)(const Vec3 (&v)[3], const double (&planes)[3][3], uint8_t alive);
};

/// Octant o has bit (o >> k) & 1 = half h along axis k: the octants of a half along k, and of a
/// quadrant (hu, hw) of the plane dropping an axis.
inline constexpr uint8_t kHalf[3][2] = {{0x55, 0xAA}, {0x33, 0xCC}, {0x0F, 0xF0}};

/// Bit i of m set where bit i, i+1, i+3 or i+4 of m is (a 3 × 3 lattice, index 3·row + column):
/// for each quadrant's low corner, whether any of its 4 corners is set.
constexpr uint32_t spread9(uint32_t m) {
  m |= m >> 1;
  return m | m >> 3;
}

/// The octants of `alive` that the axis e_axis × (q − p) does not separate from the triangle
/// (t: its projected orientation, orient2d(a, b, c, axis)): in the plane that drops `axis`, per
/// quadrant of the lattice, the quadrant's rectangle weakly on one side of the edge's line and
/// the triangle on the line or the other side. Exact (box_overlap_baseline.cpp).
uint8_t edge_axis(const Vec3& p, const Vec3& q, int axis, int t, const double (&planes)[3][3],
                  uint8_t alive);

namespace baseline {
void cells4(const HalfTerms& fx, const HalfTerms& fy, const HalfTerms& fz, double bound,
            uint32_t cells, uint64_t* pos, uint64_t* neg);
void masks27(const double* fx, const double* fy, const double* fz, double bound, uint32_t& pos,
             uint32_t& neg);
void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                       int (&out)[3]);
uint8_t edge_axes(const Vec3 (&v)[3], const double (&planes)[3][3], uint8_t alive);
}  // namespace baseline

#if defined(COVER_X86_DISPATCH)
namespace avx2 {
__attribute__((target("avx2"))) void cells4(const HalfTerms& fx, const HalfTerms& fy,
                                            const HalfTerms& fz, double bound, uint32_t cells,
                                            uint64_t* pos, uint64_t* neg);
__attribute__((target("avx2"))) void masks27(const double* fx, const double* fy, const double* fz,
                                             double bound, uint32_t& pos, uint32_t& neg);
__attribute__((target("avx2"))) void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a,
                                                       const Vec3& b, const Vec3& c, int (&out)[3]);
__attribute__((target("avx2"))) uint8_t edge_axes(const Vec3 (&v)[3], const double (&planes)[3][3],
                                                  uint8_t alive);
}  // namespace avx2

/// AVX-512F for the masks; the table of that level takes AVX2's edge kernels (3 lanes of 4).
namespace avx512 {
__attribute__((target("avx512f"))) void cells4(const HalfTerms& fx, const HalfTerms& fy,
                                               const HalfTerms& fz, double bound, uint32_t cells,
                                               uint64_t* pos, uint64_t* neg);
__attribute__((target("avx512f"))) void masks27(const double* fx, const double* fy,
                                                const double* fz, double bound, uint32_t& pos,
                                                uint32_t& neg);
}  // namespace avx512
#endif

}  // namespace cover::detail
