#include "cover/octree/detail/box_overlap.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#include "cover/octree/detail/box_overlap_simd.h"
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

/// The kernels of each level (box_overlap_simd.h), by Simd.
constexpr SimdKernels kKernels[] = {
    {baseline::cells4, baseline::masks27, baseline::edge_orientations, baseline::edge_axes},
#if defined(COVER_X86_DISPATCH)
    {avx2::cells4, avx2::masks27, avx2::edge_orientations, avx2::edge_axes},
    {avx512::cells4, avx512::masks27, avx2::edge_orientations, avx2::edge_axes},
#endif
};

/// The kernels of the level in use.
const SimdKernels& kernels() { return kKernels[static_cast<int>(simd())]; }

}  // namespace

void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                       int (&out)[3]) {
  kernels().edge_orientations(r, q, a, b, c, out);
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

namespace {}  // namespace

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

namespace {}  // namespace

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
  return kernels().edge_axes(v, planes, alive);
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
  kernels().masks27(fx, fy, fz, bound_, pos, neg);
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
  kernels().cells4(fx, fy, fz, bound_, cells, pos, neg);
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
