// Result-level classification of points on a leaf surface (see covering/detail/local.h for the
// notation and the argument). Exact: rationals (CGAL::Exact_rational) for directions, with an
// interval filter (CGAL::Interval_nt) in front of the per-triangle ray tests.
#include "cover/covering/detail/local.h"

#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>

#include <array>
#include <map>
#include <stdexcept>

#include "cover/solid/errors.h"
#include "cover/solid/predicates.h"

namespace cover::detail {
namespace {

using Rat = CGAL::Exact_rational;
using Ival = CGAL::Interval_nt<false>;

struct RVec {
  Rat x, y, z;
};
RVec rvec(const Vec3& p) { return {Rat(p.x), Rat(p.y), Rat(p.z)}; }
RVec operator-(const RVec& a, const RVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
RVec operator+(const RVec& a, const RVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
RVec operator*(const Rat& s, const RVec& a) { return {s * a.x, s * a.y, s * a.z}; }
Rat dot(const RVec& a, const RVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
RVec cross(const RVec& a, const RVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
int sgn(const Rat& r) { return static_cast<int>(CGAL::sign(r)); }
bool is_zero(const RVec& v) { return sgn(v.x) == 0 && sgn(v.y) == 0 && sgn(v.z) == 0; }

struct IVec {
  Ival x, y, z;
};
IVec ivec(const Vec3& p) { return {Ival(p.x), Ival(p.y), Ival(p.z)}; }
IVec ivec(const RVec& p) {
  return {Ival(CGAL::to_interval(p.x)), Ival(CGAL::to_interval(p.y)), Ival(CGAL::to_interval(p.z))};
}
IVec operator-(const IVec& a, const IVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Ival dot(const IVec& a, const IVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
IVec cross(const IVec& a, const IVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Exact sign of (u × v)·w where u, v are differences of double points: interval first.
int triple_sign(const Vec3& u1, const Vec3& u0, const Vec3& v1, const Vec3& v0, const RVec& w,
                const IVec& wi) {
  {
    CGAL::Protect_FPU_rounding<true> rounding;  // Interval_nt<false> needs rounding towards +inf
    const Ival t = dot(cross(ivec(u1) - ivec(u0), ivec(v1) - ivec(v0)), wi);
    if (t.inf() > 0) return 1;
    if (t.sup() < 0) return -1;
  }
  return sgn(dot(cross(rvec(u1) - rvec(u0), rvec(v1) - rvec(v0)), w));
}

/// A probe ray from q in direction d: its winding for one leaf, or nullopt on a tie (the ray
/// passes exactly through an edge or vertex of a triangle it would cross).
std::optional<int> ray_winding(const LeafTriangles& lt, size_t leaf, const Vec3& q, const RVec& d) {
  IVec di;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    di = ivec(d);
  }
  int w = 0;
  for (uint32_t i = lt.leaf_start[leaf]; i < lt.leaf_start[leaf + 1]; ++i) {
    const CoverTri& t = lt.tris[i];
    const int o3 = orient3d(t.a, t.b, t.c, q);
    if (o3 == 0) continue;  // plane through q: the ray leaves it at t = 0
    const int nd = triple_sign(t.b, t.a, t.c, t.a, d, di);  // sign of n·d
    if (nd == 0 || nd != -o3) continue;                     // parallel, or plane behind q
    const int s1 = triple_sign(t.a, q, t.b, q, d, di);
    const int s2 = triple_sign(t.b, q, t.c, q, d, di);
    const int s3 = triple_sign(t.c, q, t.a, q, d, di);
    const bool pos = s1 > 0 || s2 > 0 || s3 > 0, neg = s1 < 0 || s2 < 0 || s3 < 0;
    if (pos && neg) continue;                                // line misses the triangle
    if (s1 == 0 || s2 == 0 || s3 == 0) return std::nullopt;  // through an edge or vertex
    w += nd;  // leaving through an outward face counts +1
  }
  return w;
}

struct Cell {
  std::vector<int8_t> sides;  ///< sign of n_m·d for every plane m
  RVec d;
  bool member = false;
};

class Arrangement {
 public:
  explicit Arrangement(std::vector<RVec> normals) : n_(std::move(normals)) {}

  const std::vector<RVec>& normals() const { return n_; }
  std::vector<Cell>& cells() { return cells_; }

  void enumerate() {
    if (n_.size() == 1) {
      add_probe(n_[0]);
      add_probe(Rat(-1) * n_[0]);
      return;
    }
    for (size_t i = 0; i < n_.size(); ++i)
      for (size_t j = i + 1; j < n_.size(); ++j)
        for (int s : {1, -1}) around_vertex(Rat(s) * cross(n_[i], n_[j]));
  }

  /// Largest step δ/2 along w from d that keeps every nonzero side of d.
  Rat safe_step(const RVec& d, const RVec& w) const {
    bool bounded = false;
    Rat best;
    for (const RVec& n : n_) {
      const Rat nd = dot(n, d), nw = dot(n, w);
      if (sgn(nd) != 0 && sgn(nw) == -sgn(nd)) {
        const Rat bound = CGAL::abs(nd / nw);
        if (!bounded || bound < best) best = bound;
        bounded = true;
      }
    }
    return bounded ? best / Rat(2) : Rat(1);
  }

  std::vector<int8_t> sides(const RVec& d) const {
    std::vector<int8_t> s(n_.size());
    for (size_t m = 0; m < n_.size(); ++m) s[m] = static_cast<int8_t>(sgn(dot(n_[m], d)));
    return s;
  }

 private:
  void around_vertex(const RVec& v) {
    std::vector<RVec> tangents;
    std::vector<size_t> through;
    for (size_t m = 0; m < n_.size(); ++m)
      if (sgn(dot(n_[m], v)) == 0) {
        through.push_back(m);
        tangents.push_back(cross(n_[m], v));
      }
    for (size_t a = 0; a < tangents.size(); ++a)
      for (size_t b = a + 1; b < tangents.size(); ++b)
        for (int sa : {1, -1})
          for (int sb : {1, -1}) {
            const RVec w = Rat(sa) * tangents[a] + Rat(sb) * tangents[b];
            bool on_line = false;
            for (size_t m : through) on_line |= sgn(dot(n_[m], w)) == 0;
            if (!on_line) add_probe(v + safe_step(v, w) * w);
          }
  }

  void add_probe(const RVec& d) {
    std::vector<int8_t> s = sides(d);
    for (int8_t x : s)
      if (x == 0) return;
    if (seen_.emplace(s, cells_.size()).second) cells_.push_back(Cell{std::move(s), d, false});
  }

  std::vector<RVec> n_;
  std::vector<Cell> cells_;
  std::map<std::vector<int8_t>, size_t> seen_;
};

/// Membership of the result in every cell (probe rays, perturbed inside the cell on ties).
void evaluate_cells(Arrangement& arr, const LeafTriangles& lt, const CsgTree& tree, const Vec3& q,
                    std::span<const uint8_t> on_surface, std::span<const uint8_t> inside) {
  static const std::array<std::array<int, 3>, 6> kNudges{
      {{1, 2, 3}, {-3, 1, 2}, {2, -3, 1}, {1, 1, -4}, {-2, 5, 1}, {4, -1, -3}}};
  std::vector<uint8_t> member(inside.begin(), inside.end());
  for (Cell& cell : arr.cells()) {
    RVec d = cell.d;
    for (size_t l = 0; l < on_surface.size(); ++l) {
      if (!on_surface[l]) continue;
      std::optional<int> w;
      for (int attempt = 0; !(w = ray_winding(lt, l, q, d)); ++attempt) {
        if (attempt == 64) throw InternalError("classification: no tie-free probe ray");
        const auto& k = kNudges[attempt % kNudges.size()];
        const RVec r{Rat(k[0]), Rat(k[1]), Rat(k[2])};
        d = d + (arr.safe_step(d, r) / Rat(1 << (attempt % 16))) * r;
      }
      member[l] = *w != 0;
    }
    cell.member = tree.evaluate(member);
  }
}

/// True when cell membership is a function of the sides of the planes in `subset`.
bool depends_only_on(const std::vector<Cell>& cells, const std::vector<size_t>& subset) {
  std::map<std::vector<int8_t>, bool> seen;
  for (const Cell& c : cells) {
    std::vector<int8_t> key;
    for (size_t m : subset) key.push_back(c.sides[m]);
    auto [it, fresh] = seen.emplace(std::move(key), c.member);
    if (!fresh && it->second != c.member) return false;
  }
  return true;
}

}  // namespace

PointClass classify_on_surface(const LeafTriangles& lt, const CsgTree& tree, const Vec3& q,
                               std::span<const uint8_t> on_surface,
                               std::span<const uint8_t> inside) {
  std::vector<RVec> normals;
  for (size_t l = 0; l < on_surface.size(); ++l) {
    if (!on_surface[l]) continue;
    for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i) {
      const CoverTri& t = lt.tris[i];
      if (!on_triangle(t.a, t.b, t.c, q)) continue;
      const RVec a = rvec(t.a);
      const RVec n = cross(rvec(t.b) - a, rvec(t.c) - a);
      bool known = false;
      for (const RVec& m : normals) known = known || is_zero(cross(m, n));
      if (!known) normals.push_back(n);
    }
  }
  Arrangement arr(std::move(normals));
  arr.enumerate();
  evaluate_cells(arr, lt, tree, q, on_surface, inside);
  const std::vector<Cell>& cells = arr.cells();
  bool any_in = false, any_out = false;
  for (const Cell& c : cells) (c.member ? any_in : any_out) = true;
  if (!any_out) return PointClass::kInside;
  if (!any_in) return PointClass::kOutside;
  const std::vector<RVec>& n = arr.normals();
  for (size_t p = 0; p < n.size(); ++p)
    if (depends_only_on(cells, {p})) return PointClass::kFace;
  for (size_t i = 0; i < n.size(); ++i)
    for (size_t j = i + 1; j < n.size(); ++j) {
      const RVec u = cross(n[i], n[j]);
      std::vector<size_t> through;
      for (size_t m = 0; m < n.size(); ++m)
        if (sgn(dot(n[m], u)) == 0) through.push_back(m);
      if (depends_only_on(cells, through)) return PointClass::kEdge;
    }
  return PointClass::kVertex;
}

}  // namespace cover::detail
