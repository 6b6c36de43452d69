#pragma once
// Basic value types shared by every module.
// Conventions: right-handed coordinates, doubles everywhere; a face's vertex order is
// counter-clockwise seen from outside the solid (outward normal by the right-hand rule).

#include <array>
#include <cstdint>
#include <limits>

namespace cover {

/// The supported coordinate range: every vertex (after transforms) and every query point has
/// |x|, |y|, |z| ≤ 2^64 (about 1.8e19); loaders refuse anything outside it. Why this bound: the
/// exact predicates' floating-point filters stay finite up to degree 15 in the coordinates
/// ((2^65)^15 < 2^1023), so a filter never sees an infinity or a NaN and the exact fallback
/// (CGAL) only ever receives finite doubles; the float BVH boxes, squared lengths in cameras and
/// normals (degree ≤ 4) and the covering volume sums (degree 3) stay far from overflow. Tiny
/// coordinates need no bound: products that underflow fall below the filters' lower limit and
/// are decided exactly.
inline constexpr double kMaxCoordinate = 0x1p64;

/// A point or vector in R^3 (plain aggregate, 24 bytes, no invariants).
struct Vec3 {
  double x = 0, y = 0, z = 0;
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend bool operator==(const Vec3&, const Vec3&) = default;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// The plane normal·x = offset (normal need not be unit length; functions taking a Plane say
/// whether it may be zero). Its positive side is {x : normal·x > offset}: a clip's `above` half
/// (brep/clip.h), the half-space a render section removes (render/render.h).
struct Plane {
  Vec3 normal;
  double offset = 0;
};

/// Axis-aligned box; empty() until a point is added (min > max).
struct Bbox {
  Vec3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};
  bool empty() const { return min.x > max.x; }
  void add(Vec3 p) {
    min = {p.x < min.x ? p.x : min.x, p.y < min.y ? p.y : min.y, p.z < min.z ? p.z : min.z};
    max = {p.x > max.x ? p.x : max.x, p.y > max.y ? p.y : max.y, p.z > max.z ? p.z : max.z};
  }
  void add(const Bbox& b) {
    if (!b.empty()) {
      add(b.min);
      add(b.max);
    }
  }
  /// Closed containment test.
  bool contains(Vec3 p) const {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
           p.z <= max.z;
  }
  /// True when the open interiors overlap (boxes touching along a face do not overlap).
  bool interiors_overlap(const Bbox& b) const {
    return !empty() && !b.empty() && min.x < b.max.x && b.min.x < max.x && min.y < b.max.y &&
           b.min.y < max.y && min.z < b.max.z && b.min.z < max.z;
  }
};

}  // namespace cover
