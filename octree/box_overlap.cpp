#include "octree/detail/box_overlap.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>

#include "solid/predicates.h"

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

}  // namespace

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
  std::fill(std::begin(plane_cache_), std::end(plane_cache_), kUnknown);
  std::fill(&edge_cache_[0][0], &edge_cache_[0][0] + 81, kUnknown);
  std::fill(std::begin(third_cache_), std::end(third_cache_), kUnknown);
}

int OctantOverlap::plane_sign(int ix, int iy, int iz) {
  int8_t& s = plane_cache_[(iz * 3 + iy) * 3 + ix];
  if (s == kUnknown)
    s = static_cast<int8_t>(plane_.sign({planes_[0][ix], planes_[1][iy], planes_[2][iz]}));
  return s;
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
    return plane_sign(bit[0] + (c & 1), bit[1] + ((c >> 1) & 1), bit[2] + (c >> 2));
  };
  if (common_side(8, open, corner) != 0) return true;
  // e_axis × edge: in the plane that drops `axis`, the octant's rectangle on one side of the
  // edge's line and the third vertex (hence the triangle) on the line or the other side. An
  // edge parallel to e_axis gives the zero axis, which separates nothing.
  for (int e = 0; e < 3; ++e)
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const Vec3 &p = v_[e], &q = v_[(e + 1) % 3];
      if (p[u] == q[u] && p[w] == q[w]) continue;
      const int iu = bit[u], iw = bit[w];
      const int side = common_side(
          4, open, [&](int c) { return edge_sign(e, axis, iu + (c & 1), iw + (c >> 1)); });
      if (side == 0) continue;
      int8_t& third = third_cache_[e * 3 + axis];
      if (third == kUnknown) third = static_cast<int8_t>(orient2d(p, q, v_[(e + 2) % 3], axis));
      if (third != side) return true;
    }
  return false;
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

int PlaneSide::sign(const Vec3& p) const {
  const double f = normal_.x * (p.x - a_.x) + normal_.y * (p.y - a_.y) + normal_.z * (p.z - a_.z);
  if (f > bound_) return 1;
  if (f < -bound_) return -1;
  return orient3d(a_, b_, c_, p);
}

}  // namespace cover::detail
