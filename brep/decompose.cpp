// Convex decomposition by reflex-edge plane cuts (decompose.h; [Erleben2006 §7 Fig. 20]).
//
// Notation
//   T        the input triangles (faces triangulated exactly, mesh/triangulate.h)
//   R        the input reflex edges: per edge, its two vertices a, b, its triangles f (holding
//            a → b) and g, and its bend (angle between the rounded unit normals: the cut order)
//   piece    a polygon mesh with, per face, its triangle in T (kNoFace for a cap)
//   R(piece) the reflex edges of R that the piece still holds: an edge of the piece between a
//            face from f and one from g (decompose.h "provenance")
// A piece is cut by one plane through the stored points of one of its reflex mesh edges; each
// half is split into connected components, each a new piece. A cut creates no reflex edge and
// removes its own, so R(component) ⊆ R(piece) in exact terms; the loop checks that the cut's mesh
// edge is gone from every half (else the next plane is tried) and bounds the piece count.
#include "cover/brep/decompose.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "cover/brep/clip.h"
#include "cover/brep/detail/convex_hull.h"
#include "cover/brep/detail/nef_parts.h"
#include "cover/brep/detail/shells.h"
#include "cover/brep/halfedge.h"
#include "cover/mesh/triangulate.h"
#include "cover/mesh/validate.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/union_find.h"

namespace cover::brep {
namespace {

using Clock = std::chrono::steady_clock;

/// The most (relative to the input volume) the hulls may change the cut pieces by, in all.
constexpr double kHullTolerance = 1e-10;
/// Pieces and cut-tree nodes with more triangles are not given to the (slow) Nef fallback.
constexpr size_t kMaxFallbackFaces = 20000;
/// The fallback goes up the cut tree through nodes of at most this many faces, then to the shell.
constexpr size_t kMaxLocalFallbackFaces = 400;
/// A clip half whose rounded volume is below −kSliver × the input's is invalid.
constexpr double kSliver = 1e-11;

std::string relative(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g", x);
  return text;
}

struct ReflexEdge {
  uint32_t a, b;  ///< input vertices (a → b in triangle f)
  uint32_t f, g;  ///< input triangles
  double bend;    ///< angle between the outward normals (larger: more reflex)
};

/// A mesh edge u → v of a piece (vertex ids of the piece) on reflex edge `reflex`, between
/// face ff (from the input triangle f) and face fg (from g).
struct PieceEdge {
  uint32_t reflex, u, v, ff, fg;
};

struct Piece {
  PolygonMesh mesh;
  std::vector<uint32_t> source;  ///< per face: input triangle, or kNoFace (cap)
  uint32_t node = 0;             ///< the cut-tree node (CutNode) it was cut from
  detail::HalfSpace cut{};       ///< the half of that node's cut it is a component of
  bool from_cut = false;         ///< false for a shell that was never cut (no `cut`)
  bool uncut = false;            ///< finished with reflex edges: no plane through them worked
};

/// A piece that was cut (node 0: the shell itself), kept for the fallback.
struct CutNode {
  PolygonMesh mesh;
  uint32_t parent;          ///< kNone for node 0
  detail::HalfSpace cut{};  ///< the half of the parent's cut it is a component of
  bool from_cut = false;    ///< false for node 0 and the shell's own node (no `cut`)
};

uint64_t key(uint32_t a, uint32_t b) { return uint64_t{a} << 32 | b; }

Vec3 unit_normal(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 n = cross(q - p, r - p);
  const double len = std::sqrt(dot(n, n));
  return len > 0 ? (1 / len) * n : n;
}

class Decomposer {
 public:
  Decomposer(PolygonMesh tris, const DecomposeOptions& o) : t_(std::move(tris)), o_(o) {
    // Directed edge → triangle; the reflex test on each undirected edge once (a < b).
    std::unordered_map<uint64_t, uint32_t> directed;
    directed.reserve(3 * t_.face_count());
    for (uint32_t f = 0; f < t_.face_count(); ++f) {
      const auto v = t_.face(f);
      for (int k = 0; k < 3; ++k) directed.emplace(key(v[k], v[(k + 1) % 3]), f);
    }
    for (uint32_t f = 0; f < t_.face_count(); ++f) {
      const auto v = t_.face(f);
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = v[k], b = v[(k + 1) % 3], w = v[(k + 2) % 3];
        const uint32_t g = directed.at(key(b, a));
        if (f > g) continue;  // each edge once
        const auto gv = t_.face(g);
        const uint32_t x =
            gv[0] != a && gv[0] != b ? gv[0] : (gv[1] != a && gv[1] != b ? gv[1] : gv[2]);
        const auto& P = t_.vertices;
        if (orient3d(P[a], P[b], P[w], P[x]) <= 0) continue;  // convex or flat
        const Vec3 nf = unit_normal(P[v[0]], P[v[1]], P[v[2]]);
        const Vec3 ng = unit_normal(P[gv[0]], P[gv[1]], P[gv[2]]);
        const Vec3 s = cross(nf, ng);  // |s| = sin(bend): accurate for small bends, unlike acos
        reflex_.push_back({a, b, f, g, std::atan2(std::sqrt(dot(s, s)), dot(nf, ng))});
      }
    }
    // Nearly flat reflex edges (decompose.h "nearly flat") are left uncut.
    std::vector<uint8_t> flat(reflex_.size(), 0);
    for (uint32_t i = 0; i < reflex_.size(); ++i)
      if (reflex_[i].bend <= o_.flat_angle) {
        flat[i] = 1;
        ++nearly_flat_;
      }
    std::vector<ReflexEdge> cut;
    for (uint32_t i = 0; i < reflex_.size(); ++i)
      if (!flat[i]) {
        pair_[key(reflex_[i].f, reflex_[i].g)] = static_cast<uint32_t>(cut.size());
        cut.push_back(reflex_[i]);
      }
    total_ = static_cast<int64_t>(reflex_.size());
    reflex_ = std::move(cut);
  }

  int64_t total_reflex() const { return total_; }
  int64_t nearly_flat() const { return nearly_flat_; }

  const std::vector<ReflexEdge>& reflex() const { return reflex_; }

  /// The piece's mesh edges on reflex edges (decompose.h "provenance"), by reflex edge and
  /// vertex ids (deterministic order). A reflex edge is usually one mesh edge of a piece.
  std::vector<PieceEdge> reflex_of(const Piece& p) const {
    std::unordered_map<uint64_t, uint32_t> directed;
    const PolygonMesh& m = p.mesh;
    for (uint32_t f = 0; f < m.face_count(); ++f) {
      if (p.source[f] == kNoFace) continue;
      const auto v = m.face(f);
      for (size_t k = 0; k < v.size(); ++k) directed.emplace(key(v[k], v[(k + 1) % v.size()]), f);
    }
    std::vector<PieceEdge> out;
    for (const auto& [uv, ff] : directed) {
      const uint32_t u = static_cast<uint32_t>(uv >> 32), v = static_cast<uint32_t>(uv);
      const auto it = directed.find(key(v, u));
      if (it == directed.end()) continue;
      const uint32_t sf = p.source[ff], sg = p.source[it->second];
      const auto r = pair_.find(key(std::min(sf, sg), std::max(sf, sg)));
      // Each mesh edge once: from the face on the input triangle that holds a → b.
      if (r != pair_.end() && sf == reflex_[r->second].f)
        out.push_back({r->second, u, v, ff, it->second});
    }
    std::sort(out.begin(), out.end(), [](const PieceEdge& x, const PieceEdge& y) {
      return std::tie(x.reflex, x.u, x.v) < std::tie(y.reflex, y.u, y.v);
    });
    return out;
  }

  struct Cut {
    long score;                 ///< crossed − contained reflex edges (lower first)
    std::array<Vec3, 3> plane;  ///< through the mesh edge's two stored points
    PieceEdge edge;             ///< the mesh edge the plane goes through
  };

  /// The candidate cuts of piece p holding reflex mesh edges r, best first (decompose.h "order");
  /// ties keep the candidate order (most reflex edge, then half-angle, f, g planes).
  std::vector<Cut> rank(const Piece& p, const std::vector<PieceEdge>& r) const {
    std::vector<uint32_t> cand(r.size());
    for (uint32_t i = 0; i < cand.size(); ++i) cand[i] = i;
    const size_t k = std::min(cand.size(), static_cast<size_t>(std::max(1, o_.candidates)));
    std::partial_sort(cand.begin(), cand.begin() + static_cast<long>(k), cand.end(),
                      [&](uint32_t x, uint32_t y) {
                        const double bx = reflex_[r[x].reflex].bend, by = reflex_[r[y].reflex].bend;
                        return bx != by ? bx > by : x < y;
                      });
    const auto& P = t_.vertices;
    std::vector<Cut> cuts;
    for (size_t i = 0; i < k; ++i) {
      const PieceEdge& e = r[cand[i]];
      for (const std::array<Vec3, 3>& plane : planes(p, e)) {
        long score = 0;
        for (const PieceEdge& o : r) {
          if (o.reflex == e.reflex) continue;
          const int sa = orient3d(plane[0], plane[1], plane[2], P[reflex_[o.reflex].a]);
          const int sb = orient3d(plane[0], plane[1], plane[2], P[reflex_[o.reflex].b]);
          score += sa * sb < 0 ? 1 : (sa == 0 && sb == 0 ? -1 : 0);
        }
        cuts.push_back({score, plane, e});
      }
    }
    std::stable_sort(cuts.begin(), cuts.end(),
                     [](const Cut& x, const Cut& y) { return x.score < y.score; });
    return cuts;
  }

 private:
  /// The side all vertices of face f other than u, v take (±1), −1 when all lie on the plane and
  /// the plane was built from f's own consecutive vertices (the clip then sends f below), else 0.
  static int face_side(const Piece& p, uint32_t f, const PieceEdge& e,
                       const std::array<Vec3, 3>& plane, bool own) {
    int side = 0;
    bool zero = false;
    for (uint32_t v : p.mesh.face(f)) {
      if (v == e.u || v == e.v) continue;
      const int s = orient3d(plane[0], plane[1], plane[2], p.mesh.vertices[v]);
      if (s == 0)
        zero = true;
      else if (side == 0)
        side = s;
      else if (s != side)
        return 0;
    }
    if (!zero) return side;
    if (side != 0) return 0;
    // In the plane: the clip sends a face of zero area above, else by its normal (below when the
    // plane was built from the face's own vertices).
    return collinear(p, f) ? 1 : (own ? -1 : 0);
  }

  /// All points of face f lie on one line (exactly): a face of zero area.
  static bool collinear(const Piece& p, uint32_t f) {
    const auto v = p.mesh.face(f);
    const auto& P = p.mesh.vertices;
    size_t j = 1;
    while (j < v.size() && P[v[j]] == P[v[0]]) ++j;
    if (j == v.size()) return true;
    for (size_t i = 1; i < v.size(); ++i)
      for (int axis = 0; axis < 3; ++axis)
        if (orient2d(P[v[0]], P[v[j]], P[v[i]], axis) != 0) return false;
    return true;
  }

  /// Planes through the stored points of mesh edge e that part its two faces (checked exactly
  /// as the clip will decide): the half-angle plane, then the planes of the two faces.
  std::vector<std::array<Vec3, 3>> planes(const Piece& p, const PieceEdge& e) const {
    const auto& P = t_.vertices;
    const ReflexEdge& re = reflex_[e.reflex];
    const auto fv = t_.face(re.f), gv = t_.face(re.g);
    const Vec3 nf = unit_normal(P[fv[0]], P[fv[1]], P[fv[2]]);
    const Vec3 ng = unit_normal(P[gv[0]], P[gv[1]], P[gv[2]]);
    const Vec3 a = p.mesh.vertices[e.u], b = p.mesh.vertices[e.v], d = b - a;
    std::vector<std::array<Vec3, 3>> out;
    auto keep = [&](const std::array<Vec3, 3>& plane, int own) {
      const int sf = face_side(p, e.ff, e, plane, own == 0);
      const int sg = face_side(p, e.fg, e, plane, own == 1);
      if (sf * sg < 0) out.push_back(plane);
    };
    // The bisecting plane of the dihedral has normal nf − ng; q ⟂ d lies in it.
    const Vec3 q = cross(nf - ng, d);
    const double lq = std::sqrt(dot(q, q));
    if (lq > 0) keep({a, b, a + (std::sqrt(dot(d, d)) / lq) * q}, -1);
    if (o_.face_planes || out.empty()) {
      // A face's next vertex after the edge, in the face's own order (u → v → w in ff).
      auto after = [&](uint32_t f, uint32_t from) {
        const auto v = p.mesh.face(f);
        for (size_t i = 0; i < v.size(); ++i)
          if (v[i] == from) return v[(i + 1) % v.size()];
        return from;
      };
      keep({a, b, p.mesh.vertices[after(e.ff, e.v)]}, 0);
      keep({b, a, p.mesh.vertices[after(e.fg, e.u)]}, 1);
    }
    return out;
  }

  PolygonMesh t_;  ///< the input triangles T
  const DecomposeOptions& o_;
  std::vector<ReflexEdge> reflex_;
  std::unordered_map<uint64_t, uint32_t> pair_;  ///< (min, max) triangle pair → reflex edge
  int64_t total_ = 0, nearly_flat_ = 0;
};

/// The input with every face triangulated (same vertices). Throws InputError for a face whose
/// boundary crosses itself.
PolygonMesh triangulated(const PolygonMesh& mesh) {
  PolygonMesh out;
  out.vertices = mesh.vertices;
  std::vector<std::array<uint32_t, 3>> tris;
  const std::span<const Vec3> points(mesh.vertices.data(), mesh.vertices.size());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    tris.clear();
    if (triangulate_face(points, mesh.face(f), tris) == FaceTiling::kCrossing)
      throw InputError("face " + std::to_string(f) + " crosses itself");
    for (const auto& t : tris) out.add_face({t[0], t[1], t[2]});
  }
  return out;
}

/// The connected components of one clip half, each with its faces' input triangles.
void components(const ClipHalf& half, const std::vector<uint32_t>& parent_source,
                std::vector<Piece>& out) {
  const PolygonMesh& m = half.mesh;
  if (m.face_count() == 0) return;
  UnionFind uf(m.vertices.size());
  for (size_t f = 0; f < m.face_count(); ++f) {
    const auto v = m.face(f);
    for (size_t k = 1; k < v.size(); ++k) uf.unite(v[0], v[k]);
  }
  std::vector<uint32_t> comp(m.vertices.size(), kNone), local(m.vertices.size(), kNone);
  const size_t first = out.size();
  for (size_t f = 0; f < m.face_count(); ++f) {
    const auto v = m.face(f);
    const uint32_t root = uf.find(v[0]);
    if (comp[root] == kNone) {
      comp[root] = static_cast<uint32_t>(out.size() - first);
      out.emplace_back();
    }
    Piece& p = out[first + comp[root]];
    std::vector<uint32_t> ids(v.size());
    for (size_t k = 0; k < v.size(); ++k) {
      if (local[v[k]] == kNone) {
        local[v[k]] = static_cast<uint32_t>(p.mesh.vertices.size());
        p.mesh.vertices.push_back(m.vertices[v[k]]);
      }
      ids[k] = local[v[k]];
    }
    p.mesh.add_face(ids);
    const uint32_t s = half.face_source[f];
    p.source.push_back(s == kNoFace ? kNoFace : parent_source[s]);
  }
}

/// The bounding box of a mesh's vertices, and whether two closed boxes share a point: a cavity
/// belongs to the shells whose boxes meet its own (roots(), join_cavities()).
Bbox box_of(const PolygonMesh& mesh) {
  Bbox b;
  for (const Vec3& p : mesh.vertices) b.add(p);
  return b;
}

bool meets(const Bbox& a, const Bbox& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

/// Puts every cavity among the components out[first..] (volume below −`sliver`: an inward shell
/// the cut did not cross) into one piece with the components whose bounding boxes meet its box,
/// as roots() does for the input's shells: a cavity belongs to a shell around it, and only a
/// later cut separates them. Cavities that meet no other component are left alone (the cut is
/// then invalid).
void join_cavities(std::vector<Piece>& out, size_t first, double sliver) {
  const size_t n = out.size() - first;
  if (n < 2) return;
  std::vector<Bbox> boxes(n);
  std::vector<uint8_t> cavity(n);
  for (size_t i = 0; i < n; ++i) {
    boxes[i] = box_of(out[first + i].mesh);
    cavity[i] = signed_volume(out[first + i].mesh) < -sliver;
  }
  if (std::none_of(cavity.begin(), cavity.end(), [](uint8_t c) { return c; })) return;
  UnionFind groups(n);
  for (size_t i = 0; i < n; ++i)
    if (cavity[i])
      for (size_t j = 0; j < n; ++j)
        if (j != i && meets(boxes[i], boxes[j]))
          groups.unite(static_cast<uint32_t>(i), static_cast<uint32_t>(j));
  std::vector<Piece> joined;
  std::vector<uint32_t> slot(n, kNone);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t g = groups.find(static_cast<uint32_t>(i));
    if (slot[g] == kNone) {
      slot[g] = static_cast<uint32_t>(joined.size());
      joined.emplace_back();
    }
    Piece& to = joined[slot[g]];
    Piece& from = out[first + i];
    const auto base = static_cast<uint32_t>(to.mesh.vertices.size());
    to.mesh.vertices.insert(to.mesh.vertices.end(), from.mesh.vertices.begin(),
                            from.mesh.vertices.end());
    for (size_t f = 0; f < from.mesh.face_count(); ++f) {
      std::vector<uint32_t> ids;
      for (uint32_t v : from.mesh.face(f)) ids.push_back(base + v);
      to.mesh.add_face(ids);
    }
    to.source.insert(to.source.end(), from.source.begin(), from.source.end());
  }
  out.resize(first);
  for (Piece& p : joined) out.push_back(std::move(p));
}

/// Four points of `pts` not on one plane exist.
bool spans_volume(std::span<const Vec3> pts) {
  size_t i1 = 1;
  while (i1 < pts.size() && pts[i1] == pts[0]) ++i1;
  if (i1 >= pts.size()) return false;
  size_t i2 = i1 + 1;
  while (i2 < pts.size() && orient2d(pts[0], pts[i1], pts[i2], 0) == 0 &&
         orient2d(pts[0], pts[i1], pts[i2], 1) == 0 && orient2d(pts[0], pts[i1], pts[i2], 2) == 0)
    ++i2;
  if (i2 >= pts.size()) return false;
  for (size_t i3 = 0; i3 < pts.size(); ++i3)
    if (orient3d(pts[0], pts[i1], pts[i2], pts[i3]) != 0) return true;
  return false;
}

/// The roots to cut: the input's shells (detail/shells.h), each on its own, except that a shell
/// of negative volume (a cavity) and every shell whose bounding box meets a cavity's go into one
/// root together (a cavity belongs to a shell around it, and only cuts separate them).
std::vector<PolygonMesh> roots(const PolygonMesh& tris) {
  std::vector<PolygonMesh> shells = detail::split_shells(tris);
  std::vector<Bbox> boxes;
  std::vector<uint8_t> cavity;
  for (const PolygonMesh& s : shells) {
    boxes.push_back(box_of(s));
    cavity.push_back(signed_volume(s) <= 0);
  }
  std::vector<PolygonMesh> out;
  PolygonMesh joint;
  for (size_t i = 0; i < shells.size(); ++i) {
    bool with_cavity = cavity[i];
    for (size_t j = 0; j < shells.size() && !with_cavity; ++j)
      with_cavity = cavity[j] && meets(boxes[i], boxes[j]);
    if (!with_cavity) {
      out.push_back(std::move(shells[i]));
      continue;
    }
    const auto base = static_cast<uint32_t>(joint.vertices.size());
    joint.vertices.insert(joint.vertices.end(), shells[i].vertices.begin(),
                          shells[i].vertices.end());
    for (size_t f = 0; f < shells[i].face_count(); ++f) {
      const auto v = shells[i].face(f);
      joint.add_face({base + v[0], base + v[1], base + v[2]});
    }
  }
  if (joint.face_count() > 0) out.push_back(std::move(joint));
  return out;
}

/// The finished (reflex-free) pieces of one root, depth-first.
void cut_root(PolygonMesh tris, const DecomposeOptions& options, double input_volume,
              DecomposeResult& result, std::vector<Piece>& finished, std::vector<CutNode>& nodes) {
  nodes.push_back({tris, kNone});
  Piece root{std::move(tris), {}, 0};
  root.source.resize(root.mesh.face_count());
  for (uint32_t f = 0; f < root.source.size(); ++f) root.source[f] = f;
  const Decomposer d(root.mesh, options);  // keeps its own copy of T
  result.reflex_edges += d.total_reflex();
  result.nearly_flat_edges += d.nearly_flat();

  // Depth-first: a stack of pieces, finished pieces in the order they are found.
  std::vector<Piece> todo, parts;
  todo.push_back(std::move(root));
  while (!todo.empty()) {
    Piece p = std::move(todo.back());
    todo.pop_back();
    const std::vector<PieceEdge> r = d.reflex_of(p);
    if (r.empty()) {
      finished.push_back(std::move(p));
      continue;
    }
    // The best cut whose halves no longer hold its mesh edge (a guard: the planes are checked
    // before, so the first one should do; otherwise the next candidate is tried).
    bool done = false;
    for (const auto& cut : d.rank(p, r)) {
      ClipResult c;
      ++result.cuts;
      try {
        c = clip(p.mesh, cut.plane);
      } catch (const std::exception&) {
        // The piece or its rings are degenerate through rounding (the input itself was checked
        // above): the next plane.
        ++result.failed_cuts;
        continue;
      }
      parts.clear();
      const double sliver = kSliver * input_volume;
      components(c.below, p.source, parts);
      join_cavities(parts, 0, sliver);
      const size_t below = parts.size();
      components(c.above, p.source, parts);
      join_cavities(parts, below, sliver);
      for (size_t k = 0; k < parts.size(); ++k) {
        parts[k].cut = {cut.plane, k >= below};
        parts[k].from_cut = true;
      }
      const Vec3 a = p.mesh.vertices[cut.edge.u], b = p.mesh.vertices[cut.edge.v];
      // Rounding can leave a half that is no closed 2-manifold (a constructed point rounded
      // across a sliver): then this plane fails too.
      // Components of zero exact volume (slivers whose rounded volume is ~0 or negative) are
      // dropped; what they held is accounted for by the volume check of decompose().
      const bool valid = std::all_of(parts.begin(), parts.end(), [&](const Piece& part) {
        try {
          const BrepReport v = validate(HalfedgeMesh::from_polygon_mesh(part.mesh));
          return v.closed && v.manifold && signed_volume(part.mesh) > -sliver;
        } catch (const std::exception&) {
          return false;
        }
      });
      std::erase_if(parts, [&](const Piece& part) { return signed_volume(part.mesh) <= 0; });
      done = valid && std::none_of(parts.begin(), parts.end(), [&](const Piece& part) {
               for (const PieceEdge& e : d.reflex_of(part)) {
                 const Vec3 x = part.mesh.vertices[e.u], y = part.mesh.vertices[e.v];
                 if (e.reflex == cut.edge.reflex && ((x == a && y == b) || (x == b && y == a)))
                   return true;
               }
               return false;
             });
      if (done) break;
      ++result.failed_cuts;
    }
    if (!done) {
      // Every plane through its reflex edges is undone by rounding (slivers of zero area next
      // to the edge): the piece is kept as it is; its hull must then change it by no more than
      // rounding (checked by decompose()).
      ++result.uncut_pieces;
      p.uncut = true;
      finished.push_back(std::move(p));
      continue;
    }
    const auto node = static_cast<uint32_t>(nodes.size());
    nodes.push_back({std::move(p.mesh), p.node, p.cut, p.from_cut});
    for (Piece& part : parts) {
      part.node = node;
      todo.push_back(std::move(part));
    }
    if (static_cast<int64_t>(todo.size() + finished.size()) > options.max_pieces)
      throw NotComputable("decompose: more than " + std::to_string(options.max_pieces) + " pieces");
  }
}

/// The exact convex hull of `pts`, appended to `out` unless it has no volume (in doubles: a
/// sliver whose rounded volume is ≤ 0 is dropped; the volume checks account for it).
void add_hull(std::span<const Vec3> pts, std::vector<PolygonMesh>& out) {
  if (!spans_volume(pts)) return;
  PolygonMesh hull = detail::convex_hull(pts);
  if (signed_volume(hull) > 0) out.push_back(std::move(hull));
}

/// The winding number of `mesh` around q (Σ of its fan triangles' solid angles / 4π; doubles):
/// about 1 deep inside a closed outward mesh, 0 outside, even where rounding folded a few faces.
/// (covering/gwn.h's triangle_winding is the same formula; brep does not depend on covering.)
double winding(const PolygonMesh& mesh, const Vec3& q) {
  double sum = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto v = mesh.face(f);
    for (size_t k = 1; k + 1 < v.size(); ++k) {
      const Vec3 a = mesh.vertices[v[0]] - q, b = mesh.vertices[v[k]] - q,
                 c = mesh.vertices[v[k + 1]] - q;
      const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
      const double det = dot(a, cross(b, c));
      const double denom = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
      sum += 2 * std::atan2(det, denom);
    }
  }
  return sum / (4 * 3.14159265358979323846);
}

double volume_of(const std::vector<PolygonMesh>& meshes) {
  double sum = 0;
  for (const PolygonMesh& m : meshes) sum += signed_volume(m);
  return sum;
}

/// Whether CGAL's Nef polyhedron of the triangle mesh `tris` can be built safely: no triangle of
/// zero area, no two vertices at one point, no self-intersection (all exact). Rounding can fold a
/// cut piece so; Nef's convex decomposition of such a mesh may crash rather than fail.
bool nef_safe(const PolygonMesh& tris) {
  std::vector<Vec3> points(tris.vertices.begin(), tris.vertices.end());
  std::sort(points.begin(), points.end(), [](const Vec3& a, const Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  });
  if (std::adjacent_find(points.begin(), points.end()) != points.end()) return false;
  const std::span<const Vec3> all(tris.vertices.data(), tris.vertices.size());
  for (size_t f = 0; f < tris.face_count(); ++f)
    if (all_collinear(all, tris.face(f))) return false;
  return !self_intersects(tris);
}

/// The exact convex parts of `mesh` (the Nef fallback) as hulls, and how much they change its
/// volume; nullopt when the Nef polyhedron cannot be built.
std::optional<std::pair<std::vector<PolygonMesh>, double>> nef_hulls(const PolygonMesh& mesh) {
  std::vector<PolygonMesh> hulls;
  for (const std::vector<Vec3>& part : detail::nef_convex_parts(mesh))
    add_hull(std::span<const Vec3>(part.data(), part.size()), hulls);
  if (hulls.empty()) return std::nullopt;
  const double change = std::abs(volume_of(hulls) - signed_volume(mesh));
  return std::make_pair(std::move(hulls), change);
}

/// The hulls of one shell's finished pieces (decompose.h "rounding"). A piece whose hull changes
/// its volume by more than `tolerance` is redone by the Nef fallback (decompose.h "fallback"):
/// the piece alone, else together with the other pieces cut from the same cut-tree node, going up
/// the tree until the fallback's change is within `tolerance`. Returns the hulls and the sum of
/// the changes.
std::pair<std::vector<PolygonMesh>, double> hull_shell(const std::vector<Piece>& finished,
                                                       const std::vector<CutNode>& nodes,
                                                       double tolerance, int64_t& fallbacks) {
  const size_t n = finished.size();
  std::vector<std::vector<PolygonMesh>> hulls(n);
  std::vector<double> change(n, 0);
  parallel_for(n, 1, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      const auto& v = finished[i].mesh.vertices;
      add_hull(std::span<const Vec3>(v.data(), v.size()), hulls[i]);
      change[i] = std::abs(volume_of(hulls[i]) - signed_volume(finished[i].mesh));
    }
  });
  // replaced[n]: the node whose fallback covers the piece (kNone: its own hull).
  std::vector<uint32_t> replaced(n, kNone);
  std::vector<std::pair<uint32_t, std::vector<PolygonMesh>>> redone;
  std::vector<double> redone_change;
  auto descends = [&](uint32_t node, uint32_t from) {
    for (; node != kNone; node = nodes[node].parent)
      if (node == from) return true;
    return false;
  };
  // The Nef fallback's hulls of `mesh` if it can build them within `tolerance`; `input`: the
  // shell itself (exact input points, no safety test needed).
  auto nef_within = [&](const PolygonMesh& mesh, bool input = false) {
    std::optional<std::pair<std::vector<PolygonMesh>, double>> nef;
    if (mesh.face_count() > kMaxFallbackFaces) return nef;
    try {
      const PolygonMesh tris = triangulated(mesh);
      if (input || nef_safe(tris)) nef = nef_hulls(tris);
    } catch (const InputError&) {
    }
    if (nef && nef->second > tolerance) nef.reset();
    return nef;
  };
  // The exact region of a piece or node (`mesh`, the last cut on its path `last` or none, its
  // parent node `node`): the shell's Nef polyhedron within the mesh's box and the half-spaces of
  // the cuts on its path (decompose.h "fallback"); its convex parts are those whose centres the
  // rounded mesh winds around. Their hulls, and how much they change the mesh's volume, if Nef can
  // build the region and the change is within `tolerance`.
  std::unique_ptr<detail::ShellRegions> regions;  // built for the first piece that needs it
  // Rounded points lie within rounding of the exact region; this margin around a rounded mesh's
  // box keeps all of the region in it (a part lost outside would show in the change).
  Bbox all;
  for (const Vec3& p : nodes[0].mesh.vertices) all.add(p);
  const double size = (all.max.x - all.min.x) + (all.max.y - all.min.y) + (all.max.z - all.min.z);
  const Vec3 margin{1e-6 * size, 1e-6 * size, 1e-6 * size};
  auto region_within = [&](const PolygonMesh& mesh, const detail::HalfSpace* last, uint32_t node) {
    std::optional<std::pair<std::vector<PolygonMesh>, double>> out;
    std::vector<detail::HalfSpace> cuts;
    if (last) cuts.push_back(*last);
    for (; node != 0; node = nodes[node].parent)
      if (nodes[node].from_cut) cuts.push_back(nodes[node].cut);
    std::reverse(cuts.begin(), cuts.end());
    Bbox near;
    for (const Vec3& p : mesh.vertices) near.add(p);
    near.min = near.min - margin;
    near.max = near.max + margin;
    // Cuts with the whole box on their kept side change nothing there (most of a deep path).
    std::erase_if(cuts, [&](const detail::HalfSpace& h) {
      for (int k = 0; k < 8; ++k) {
        const Vec3 corner{k & 1 ? near.max.x : near.min.x, k & 2 ? near.max.y : near.min.y,
                          k & 4 ? near.max.z : near.min.z};
        const int side = orient3d(h.plane[0], h.plane[1], h.plane[2], corner);
        if (h.above ? side < 0 : side > 0) return false;
      }
      return true;
    });
    if (!regions) regions = std::make_unique<detail::ShellRegions>(nodes[0].mesh);
    const auto parts = regions->convex_parts(cuts, near);
    if (!parts) return out;
    std::vector<PolygonMesh> mine;
    for (const std::vector<Vec3>& part : *parts) {
      if (part.empty()) continue;
      Vec3 centre{0, 0, 0};
      for (const Vec3& p : part) centre = centre + p;
      centre = (1.0 / static_cast<double>(part.size())) * centre;
      if (winding(mesh, centre) > 0.5)
        add_hull(std::span<const Vec3>(part.data(), part.size()), mine);
    }
    // What the exact parts differ from the rounded mesh by is rounding the other pieces' hulls
    // share (a rounded sliver whose exact region is empty leaves a gap as large as itself).
    const double moved = std::abs(volume_of(mine) - signed_volume(mesh));
    if (moved <= tolerance) out.emplace(std::move(mine), moved);
    return out;
  };
  // A node's fallback: its Nef parts when Nef can safely take its rounded mesh, else those of its
  // exact region.
  auto nef_or_region = [&](uint32_t node) {
    auto nef = nef_within(nodes[node].mesh, node == 0);
    if (!nef && node != 0)
      nef = region_within(nodes[node].mesh, nodes[node].from_cut ? &nodes[node].cut : nullptr,
                          nodes[node].parent);
    return nef;
  };
  // The exact convex parts of a cut-tree node, if the fallback can build them within
  // `tolerance`; the pieces cut from the node are then replaced by them.
  auto redo_node = [&](uint32_t node) {
    auto nef = nef_or_region(node);
    if (!nef) return false;
    // Earlier fallbacks inside this node are superseded.
    for (size_t k = 0; k < redone.size(); ++k)
      if (descends(redone[k].first, node)) {
        redone[k].second.clear();
        redone_change[k] = 0;
      }
    for (size_t j = 0; j < n; ++j)
      if (descends(finished[j].node, node)) replaced[j] = node;
    redone.emplace_back(node, std::move(nef->first));
    redone_change.push_back(nef->second);
    ++fallbacks;
    return true;
  };
  // A piece finished because it had no reflex edge is convex in exact arithmetic, so its exact
  // region is one part (or a few, with its siblings' parts within its box) and comes first:
  // Nef's decomposition of its rounded points splits at every edge that rounding bent inwards
  // (a tessellated 127-face piece: 71 s and about a thousand parts). A piece that no plane could
  // cut has reflex edges: first the piece itself (its written doubles; usually tens of faces, so
  // the Nef decomposition takes milliseconds), then its exact region. Then the nodes up the cut
  // tree, smallest first: the shell itself (exact input points) can take minutes on a few
  // thousand faces.
  for (size_t i = 0; i < n; ++i) {
    if (change[i] <= tolerance || replaced[i] != kNone) continue;
    const Piece& piece = finished[i];
    auto exact_region = [&] {
      return region_within(piece.mesh, piece.from_cut ? &piece.cut : nullptr, piece.node);
    };
    std::optional<std::pair<std::vector<PolygonMesh>, double>> exact;
    if (!piece.uncut) exact = exact_region();
    if (!exact) exact = nef_within(piece.mesh);
    if (!exact) {
      // A sliver that rounding folded (its points coincide or cross: no Nef polyhedron) whose
      // volume is within `tolerance`: dropped, and its volume counted as its change.
      const double volume = signed_volume(piece.mesh);
      if (std::abs(volume) <= tolerance) {
        hulls[i].clear();
        change[i] = std::abs(volume);
        continue;
      }
      if (piece.uncut) exact = exact_region();
    }
    if (exact) {
      hulls[i] = std::move(exact->first);
      change[i] = exact->second;
      ++fallbacks;
      continue;
    }
    // Up the tree through the small nodes (rounded points too: often no Nef polyhedron either),
    // then the shell.
    bool done = false;
    for (uint32_t node = finished[i].node;
         !done && node != 0 && nodes[node].mesh.face_count() <= kMaxLocalFallbackFaces;
         node = nodes[node].parent)
      done = redo_node(node);
    if (!done) redo_node(0);
  }
  std::vector<PolygonMesh> out;
  double total = 0;
  for (size_t i = 0; i < n; ++i) {
    if (replaced[i] != kNone) continue;
    total += change[i];
    for (PolygonMesh& h : hulls[i]) out.push_back(std::move(h));
  }
  for (size_t k = 0; k < redone.size(); ++k) {
    total += redone_change[k];
    for (PolygonMesh& h : redone[k].second) out.push_back(std::move(h));
  }
  return {std::move(out), total};
}

}  // namespace

DecomposeResult decompose(const PolygonMesh& mesh, const DecomposeOptions& options) {
  const auto start = Clock::now();
  DecomposeResult result;
  if (mesh.face_count() == 0) return result;
  const PolygonMesh tris = triangulated(mesh);
  const std::vector<PolygonMesh> shells = roots(tris);  // InputError: open or misoriented
  result.input_volume = signed_volume(tris);
  if (!(result.input_volume > 0))
    throw InputError("the mesh is inside out or has no volume (volume " +
                     std::to_string(result.input_volume) + ")");
  double hull_seconds = 0, total_change = 0;
  for (const PolygonMesh& s : shells) {
    const double volume = signed_volume(s);
    if (!(volume > 0))
      throw InputError("a shell of the mesh is inside out (volume " + std::to_string(volume) + ")");
    std::vector<Piece> finished;
    std::vector<CutNode> nodes;
    cut_root(s, options, result.input_volume, result, finished, nodes);
    const auto hull_start = Clock::now();
    auto [hulls, change] =
        hull_shell(finished, nodes, kSliver * result.input_volume, result.fallback_nodes);
    total_change += change;
    result.hull_change = std::max(result.hull_change, change / result.input_volume);
    for (PolygonMesh& hull : hulls) result.pieces.push_back(std::move(hull));
    hull_seconds += std::chrono::duration<double>(Clock::now() - hull_start).count();
  }
  std::vector<uint8_t> convex(result.pieces.size(), 1);
  parallel_for(result.pieces.size(), 1, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) convex[i] = is_convex_exact(result.pieces[i]);
  });
  for (size_t i = 0; i < result.pieces.size(); ++i) {
    if (!convex[i]) throw InternalError("decompose: a piece's convex hull is not convex");
    result.volume += signed_volume(result.pieces[i]);
  }
  // The hulls may differ from the cut pieces (and so overlap or leave gaps) by no more than
  // kHullTolerance of the input in all, and their volumes must add up to the input's as closely.
  const double missing = std::abs(result.volume - result.input_volume);
  if (total_change > kHullTolerance * result.input_volume ||
      missing > kHullTolerance * result.input_volume)
    throw NotComputable(
        "decompose: rounded cut points leave pieces that are not convex (their hulls change " +
        relative(total_change / result.input_volume) + " of the volume, the pieces' volumes " +
        "differ from the input's by " + relative(missing / result.input_volume) + "; at most " +
        relative(kHullTolerance) + " is allowed)");
  result.hull_seconds = hull_seconds;
  result.cut_seconds = std::chrono::duration<double>(Clock::now() - start).count() - hull_seconds;
  return result;
}

bool is_convex_exact(const PolygonMesh& piece) {
  const auto& P = piece.vertices;
  for (size_t f = 0; f < piece.face_count(); ++f) {
    const auto v = piece.face(f);
    for (size_t k = 1; k + 1 < v.size(); ++k)
      for (size_t i = 0; i < P.size(); ++i)
        if (orient3d(P[v[0]], P[v[k]], P[v[k + 1]], P[i]) > 0) return false;
  }
  return true;
}

}  // namespace cover::brep
