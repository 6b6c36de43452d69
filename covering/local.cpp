// Result-level classification of points on a leaf surface, and the exact class of a rational
// point (see covering/detail/local.h for the notation and the argument). Exact: rationals
// (CGAL::Gmpq, the type of field/detail/exact.h's points) for directions and rational points,
// with an interval filter (CGAL::Interval_nt) in front of the per-triangle ray tests.
#include "cover/covering/detail/local.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>

#include <array>
#include <map>
#include <stdexcept>

#include "cover/field/detail/exact.h"
#include "cover/solid/errors.h"
#include "cover/solid/predicates.h"

namespace cover::detail {
namespace {

using Rat = CGAL::Gmpq;
using field::detail::QPoint;
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

/// The query point: its exact coordinates, their enclosure, and the double point when it is one
/// (the double predicates then decide, faster).
struct QueryPoint {
  RVec r;
  IVec i;
  const Vec3* d = nullptr;
};
QueryPoint query_point(const Vec3& q) { return {rvec(q), ivec(q), &q}; }
QueryPoint query_point(const RVec& q) {
  CGAL::Protect_FPU_rounding<true> rounding;
  return {q, ivec(q), nullptr};
}

/// Sign of a signed rational quantity with an interval filter in front.
template <class Exact>
int filtered_sign(const Ival& filter, const Exact& exact) {
  if (filter.inf() > 0) return 1;
  if (filter.sup() < 0) return -1;
  return sgn(exact());
}

/// orient3d(a, b, c, q): the sign of ((b − a) × (c − a))·(q − a).
int orient_q(const CoverTri& t, const QueryPoint& q) {
  if (q.d != nullptr) return orient3d(t.a, t.b, t.c, *q.d);
  Ival f;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    const IVec a = ivec(t.a);
    f = dot(cross(ivec(t.b) - a, ivec(t.c) - a), q.i - a);
  }
  return filtered_sign(f, [&] {
    const RVec a = rvec(t.a);
    return dot(cross(rvec(t.b) - a, rvec(t.c) - a), q.r - a);
  });
}

/// The sign of ((u − q) × (v − q))·d.
int triple_q(const Vec3& u, const Vec3& v, const QueryPoint& q, const RVec& d, const IVec& di) {
  if (q.d != nullptr) return triple_sign(u, *q.d, v, *q.d, d, di);
  Ival f;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    f = dot(cross(ivec(u) - q.i, ivec(v) - q.i), di);
  }
  return filtered_sign(f, [&] { return dot(cross(rvec(u) - q.r, rvec(v) - q.r), d); });
}

/// True when q lies in the closed triangle t (exact). Precondition: t is not degenerate.
bool on_triangle_q(const CoverTri& t, const QueryPoint& q) {
  if (q.d != nullptr) return on_triangle(t.a, t.b, t.c, *q.d);
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    if (q.i.x.inf() > t.box.max.x || q.i.x.sup() < t.box.min.x || q.i.y.inf() > t.box.max.y ||
        q.i.y.sup() < t.box.min.y || q.i.z.inf() > t.box.max.z || q.i.z.sup() < t.box.min.z)
      return false;
  }
  if (orient_q(t, q) != 0) return false;
  // q is in the plane: containment in a projection along an axis the normal is not orthogonal
  // to is containment; the k-th components of the normals of (a, b, q), (b, c, q), (c, a, q).
  const RVec a = rvec(t.a), b = rvec(t.b), c = rvec(t.c);
  const RVec n = cross(b - a, c - a);
  const auto component = [](const RVec& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); };
  for (int k = 0; k < 3; ++k) {
    const int s = sgn(component(n, k));
    if (s == 0) continue;
    const int s1 = sgn(component(cross(b - a, q.r - a), k));
    const int s2 = sgn(component(cross(c - b, q.r - b), k));
    const int s3 = sgn(component(cross(a - c, q.r - c), k));
    return (s1 == 0 || s1 == s) && (s2 == 0 || s2 == s) && (s3 == 0 || s3 == s);
  }
  return false;
}

/// A probe ray from q in direction d: its winding for one leaf, or nullopt on a tie (the ray
/// passes exactly through an edge or vertex of a triangle it would cross).
std::optional<int> ray_winding(const LeafTriangles& lt, size_t leaf, const QueryPoint& q,
                               const RVec& d) {
  IVec di;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    di = ivec(d);
  }
  int w = 0;
  for (uint32_t i = lt.leaf_start[leaf]; i < lt.leaf_start[leaf + 1]; ++i) {
    const CoverTri& t = lt.tris[i];
    const int o3 = orient_q(t, q);
    if (o3 == 0) continue;  // plane through q: the ray leaves it at t = 0
    const int nd = triple_sign(t.b, t.a, t.c, t.a, d, di);  // sign of n·d
    if (nd == 0 || nd != -o3) continue;                     // parallel, or plane behind q
    const int s1 = triple_q(t.a, t.b, q, d, di);
    const int s2 = triple_q(t.b, t.c, q, d, di);
    const int s3 = triple_q(t.c, t.a, q, d, di);
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
void evaluate_cells(Arrangement& arr, const LeafTriangles& lt, const CsgTree& tree,
                    const QueryPoint& q, std::span<const uint8_t> on_surface,
                    std::span<const uint8_t> inside) {
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

PointClass classify_on_surface_q(const LeafTriangles& lt, const CsgTree& tree, const QueryPoint& q,
                                 std::span<const uint8_t> on_surface,
                                 std::span<const uint8_t> inside) {
  std::vector<RVec> normals;
  for (size_t l = 0; l < on_surface.size(); ++l) {
    if (!on_surface[l]) continue;
    for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i) {
      const CoverTri& t = lt.tris[i];
      if (!on_triangle_q(t, q)) continue;
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

/// Winding of a closed mesh leaf at q (not on its surface): a probe ray in a generic direction,
/// nudged on ties.
int winding_at(const LeafTriangles& lt, size_t leaf, const QueryPoint& q) {
  static const std::array<std::array<int, 3>, 6> kNudges{
      {{1, 2, 3}, {-3, 1, 2}, {2, -3, 1}, {1, 1, -4}, {-2, 5, 1}, {4, -1, -3}}};
  RVec d{Rat(1), Rat(1) / Rat(3), Rat(1) / Rat(7)};
  for (int attempt = 0; attempt < 64; ++attempt) {
    if (const std::optional<int> w = ray_winding(lt, leaf, q, d)) return *w;
    const auto& k = kNudges[attempt % kNudges.size()];
    d = d + (Rat(1) / Rat(1 << (1 + attempt % 16))) * RVec{Rat(k[0]), Rat(k[1]), Rat(k[2])};
  }
  throw InternalError("classification: no tie-free probe ray");
}

QPoint qpoint(const RVec& r) { return {r.x, r.y, r.z}; }
RVec rvec(const QPoint& p) { return {p.x, p.y, p.z}; }

/// The exact class of the rational point q in prepared's solid (see exact_warp_member).
std::optional<field::Sign> exact_member(const Prepared& prepared, const QueryPoint& q) {
  const Solid& solid = prepared.solid();
  const GwnForest* forest = solid.has_open_leaf() ? prepared.gwn() : nullptr;
  const size_t n = solid.leaves.size();
  std::vector<uint8_t> inside(n, 0), on(n, 0);
  std::vector<uint32_t> implicit_on;
  bool mesh_on = false;
  std::optional<LeafTriangles> lt;
  Bbox qb;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    qb = {{q.i.x.inf(), q.i.y.inf(), q.i.z.inf()}, {q.i.x.sup(), q.i.y.sup(), q.i.z.sup()}};
  }
  for (uint32_t l = 0; l < n; ++l) {
    const Leaf& leaf = solid.leaves[l];
    const Bbox& b = leaf.bbox;
    if (qb.min.x > b.max.x || qb.max.x < b.min.x || qb.min.y > b.max.y || qb.max.y < b.min.y ||
        qb.min.z > b.max.z || qb.max.z < b.min.z)
      continue;  // outside the leaf's closed box: outside the leaf, off its surface
    std::optional<field::Sign> s;
    if (leaf.is_field()) {
      s = field::detail::sign_at(solid.fields[leaf.field], qpoint(q.r));
      if (*s == field::Sign::kUndecided) return std::nullopt;
    } else if (leaf.is_warp()) {
      QPoint p;
      if (!field::detail::rational_inverse(solid.warps[leaf.warp], qpoint(q.r), p))
        return std::nullopt;
      s = exact_member(prepared.warp_child(leaf.warp), query_point(rvec(p)));
      if (!s) return std::nullopt;
    } else {
      if (forest != nullptr && forest->tree_of_leaf[l] >= 0) return std::nullopt;  // open leaf
      if (!lt) lt = covering_triangles(solid);
      for (uint32_t i = lt->leaf_start[l]; i < lt->leaf_start[l + 1] && !on[l]; ++i)
        on[l] = on_triangle_q(lt->tris[i], q);
      if (on[l])
        mesh_on = true;
      else
        inside[l] = winding_at(*lt, l, q) != 0;
      continue;
    }
    inside[l] = *s == field::Sign::kInside;
    if (*s == field::Sign::kOn) implicit_on.push_back(l);
  }
  const auto of_class = [](PointClass c) {
    return c == PointClass::kInside    ? field::Sign::kInside
           : c == PointClass::kOutside ? field::Sign::kOutside
                                       : field::Sign::kOn;
  };
  if (!implicit_on.empty()) {
    // Implicit surfaces through q: as classify's field_surface_class, without mesh surfaces.
    constexpr size_t kMaxOn = 12;
    if (mesh_on || implicit_on.size() > kMaxOn) return std::nullopt;
    bool all_in = true, all_out = true;
    for (uint32_t mask = 0; mask < (1u << implicit_on.size()); ++mask) {
      for (size_t i = 0; i < implicit_on.size(); ++i) inside[implicit_on[i]] = (mask >> i) & 1;
      const bool in = solid.tree.evaluate(inside);
      all_in &= in;
      all_out &= !in;
    }
    if (all_in) return field::Sign::kInside;
    if (all_out) return field::Sign::kOutside;
    if (implicit_on.size() == 1) return field::Sign::kOn;
    return std::nullopt;
  }
  if (mesh_on) return of_class(classify_on_surface_q(*lt, solid.tree, q, on, inside));
  return solid.tree.evaluate(inside) ? field::Sign::kInside : field::Sign::kOutside;
}

}  // namespace

PointClass classify_on_surface(const LeafTriangles& lt, const CsgTree& tree, const Vec3& q,
                               std::span<const uint8_t> on_surface,
                               std::span<const uint8_t> inside) {
  return classify_on_surface_q(lt, tree, query_point(q), on_surface, inside);
}

std::optional<field::Sign> exact_warp_member(const Prepared& prepared, size_t warp, const Vec3& q) {
  QPoint p;
  if (!field::detail::rational_inverse(prepared.solid().warps[warp],
                                       QPoint{Rat(q.x), Rat(q.y), Rat(q.z)}, p))
    return std::nullopt;
  return exact_member(prepared.warp_child(warp), query_point(rvec(p)));
}

}  // namespace cover::detail
