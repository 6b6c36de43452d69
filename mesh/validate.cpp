// Leaf validation (validate.h): edge table, vertex fans, components, Euler characteristic.
// Notation:
//   half-edge h  a position in face_vertices: (from, to) = (loop[i], loop[i+1]) of face f's loop,
//                wrapping; h is present when from != to (a repeated index is not an edge).
//                next(h) / prev(h) are the neighbouring present half-edges of the same face.
//   false pair   (u,v) and (v,u) in the same face ([Segura2004 §3 Fig. 1]): an edge of its
//                own, glued only to itself, never a side of a surface edge.
//   real edge    the other present half-edges, grouped by undirected vertex pair: its sides.
//   mate[h]      the two halves of a false pair are mates; the sides of a real edge are linked in
//                a cycle (a manifold edge: the other side); a boundary side has none (kNone).
//   corner c     the present half-edge c entering vertex to(c) and next(c) leaving it. Crossing an
//                edge through mates goes from corner to corner around a vertex; a vertex is
//                manifold when this walk visits all its corners in one fan.
// The topology is that of the index lists read literally: each face is a disk bounded by its loop,
// glued to itself along its false pairs (L loops joined by L−1 false edges: a disk with L−1 holes)
// and to other faces along real edges. Hence χ = V − E + F counts each false pair in E, which
// equals V − E_real + Σ_f (2 − L_f).

#include "cover/mesh/validate.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "cover/mesh/repair.h"
#include "cover/solid/measure.h"
#include "cover/solid/predicates.h"

namespace cover {
namespace {

/// The number of distinct vertex indices of each face, summed (a face with a hole lists the
/// vertices of its false edge twice).
size_t distinct_face_vertices(const PolygonMesh& mesh) {
  size_t total = 0;
  std::vector<uint32_t> sorted;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const std::span<const uint32_t> face = mesh.face(f);
    sorted.assign(face.begin(), face.end());
    std::sort(sorted.begin(), sorted.end());
    total += static_cast<size_t>(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
  }
  return total;
}

constexpr uint32_t kNone = UINT32_MAX;

/// Present half-edges of a mesh's faces (no storage beyond the face of each position).
class HalfEdges {
 public:
  explicit HalfEdges(const PolygonMesh& mesh)
      : fv_(mesh.face_vertices), start_(mesh.face_start), face_of_(fv_.size()) {
    for (size_t f = 0; f + 1 < start_.size(); ++f)
      std::fill(face_of_.begin() + start_[f], face_of_.begin() + start_[f + 1],
                static_cast<uint32_t>(f));
  }
  size_t size() const { return fv_.size(); }
  uint32_t face(uint32_t h) const { return face_of_[h]; }
  uint32_t from(uint32_t h) const { return fv_[h]; }
  uint32_t to(uint32_t h) const { return fv_[succ(h)]; }
  bool present(uint32_t h) const { return from(h) != to(h); }
  /// Next present half-edge of h's face. Precondition: h present.
  uint32_t next(uint32_t h) const {
    do h = succ(h);
    while (!present(h));
    return h;
  }
  /// Previous present half-edge of h's face. Precondition: h present.
  uint32_t prev(uint32_t h) const {
    do h = pred(h);
    while (!present(h));
    return h;
  }

 private:
  uint32_t succ(uint32_t h) const {
    return h + 1 < start_[face_of_[h] + 1] ? h + 1 : start_[face_of_[h]];
  }
  uint32_t pred(uint32_t h) const {
    return h > start_[face_of_[h]] ? h - 1 : start_[face_of_[h] + 1] - 1;
  }

  const std::vector<uint32_t>& fv_;
  const std::vector<uint32_t>& start_;
  std::vector<uint32_t> face_of_;
};

/// One present half-edge in the bucket of its smaller endpoint lo.
struct BucketEntry {
  uint32_t hi, face, h;
  bool forward;  ///< from(h) == lo
};

bool entry_less(const BucketEntry& a, const BucketEntry& b) {
  if (a.hi != b.hi) return a.hi < b.hi;
  if (a.face != b.face) return a.face < b.face;
  return a.forward < b.forward;
}

struct EdgeTable {
  std::vector<uint32_t> mate;  ///< per half-edge (kNone: absent or boundary side)
  int64_t edges = 0;           ///< real edges + false pairs
  int64_t boundary = 0;
  int64_t nonmanifold = 0;
  bool oriented = true;
};

/// Links the half-edges of one undirected pair: entries[0..n) sorted by entry_less.
void group_edge(const BucketEntry* entries, size_t n, EdgeTable& table) {
  uint32_t first_real = kNone, last_real = kNone;
  int64_t real_fwd = 0, real_bwd = 0;
  auto add_real = [&](const BucketEntry& e) {
    if (first_real == kNone)
      first_real = e.h;
    else
      table.mate[last_real] = e.h;
    last_real = e.h;
    (e.forward ? real_fwd : real_bwd) += 1;
  };
  for (size_t s0 = 0; s0 < n;) {
    size_t bwd = 0, s1 = s0;
    for (; s1 < n && entries[s1].face == entries[s0].face; ++s1) bwd += entries[s1].forward ? 0 : 1;
    // Backward half-edges of this face come first: pair the k-th backward with the k-th forward.
    const size_t pairs = std::min(bwd, s1 - s0 - bwd);
    for (size_t k = 0; k < pairs; ++k) {
      const uint32_t b = entries[s0 + k].h, f = entries[s0 + bwd + k].h;
      table.mate[b] = f;
      table.mate[f] = b;
    }
    table.edges += static_cast<int64_t>(pairs);
    for (size_t i = s0 + pairs; i < s0 + bwd; ++i) add_real(entries[i]);
    for (size_t i = s0 + bwd + pairs; i < s1; ++i) add_real(entries[i]);
    s0 = s1;
  }
  const int64_t sides = real_fwd + real_bwd;
  if (sides == 0) return;
  ++table.edges;
  if (sides > 1) table.mate[last_real] = first_real;
  if (sides == 1) ++table.boundary;
  if (sides > 2) ++table.nonmanifold;
  if (sides == 2 && real_fwd != 1) table.oriented = false;
}

/// Groups the half-edges by undirected pair: counting sort by smaller endpoint, then a sort of
/// each bucket by (larger endpoint, face, direction).
EdgeTable build_edges(size_t vertex_count, const HalfEdges& he) {
  std::vector<uint32_t> bucket_start(vertex_count + 1, 0);
  for (uint32_t h = 0; h < he.size(); ++h)
    if (he.present(h)) ++bucket_start[std::min(he.from(h), he.to(h)) + 1];
  for (size_t v = 0; v < vertex_count; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<BucketEntry> entries(bucket_start.back());
  {
    std::vector<uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (uint32_t h = 0; h < he.size(); ++h) {
      const uint32_t u = he.from(h), v = he.to(h);
      if (u == v) continue;
      const uint32_t lo = std::min(u, v);
      entries[fill[lo]++] = {std::max(u, v), he.face(h), h, u == lo};
    }
  }
  EdgeTable table;
  table.mate.assign(he.size(), kNone);
  for (size_t lo = 0; lo < vertex_count; ++lo) {
    BucketEntry* begin = entries.data() + bucket_start[lo];
    BucketEntry* end = entries.data() + bucket_start[lo + 1];
    std::sort(begin, end, entry_less);
    for (BucketEntry* g = begin; g != end;) {
      BucketEntry* g1 = g;
      while (g1 != end && g1->hi == g->hi) ++g1;
      group_edge(g, static_cast<size_t>(g1 - g), table);
      g = g1;
    }
  }
  return table;
}

/// Walks the corners around vertex to(start) from corner `start`, leaving through its half-edge
/// `exit`, until the walk closes (true) or reaches a boundary side (false). Marks visited corners.
/// Precondition: no real edge has more than two sides.
bool walk_fan(const HalfEdges& he, const std::vector<uint32_t>& mate, uint32_t start, uint32_t exit,
              std::vector<uint8_t>& visited) {
  const uint32_t v = he.to(start);
  uint32_t corner = start;
  for (;;) {
    visited[corner] = 1;
    const uint32_t side = mate[exit];
    if (side == kNone) return false;
    // The corner at v on the other side of the edge, and the half-edge it is left through.
    if (he.to(side) == v) {
      corner = side;
      exit = he.next(side);
    } else {
      corner = he.prev(side);
      exit = corner;
    }
    if (corner == start) return true;
  }
}

struct Fans {
  int64_t vertices = 0;  ///< vertices on at least one edge
  int64_t pinched = 0;   ///< vertices whose corners form more than one fan
};

Fans count_fans(size_t vertex_count, const HalfEdges& he, const EdgeTable& table) {
  Fans fans;
  std::vector<uint8_t> visited(he.size(), 0), per_vertex(vertex_count, 0);
  for (uint32_t h = 0; h < he.size(); ++h) {
    if (visited[h] || !he.present(h)) continue;
    if (!walk_fan(he, table.mate, h, he.next(h), visited)) walk_fan(he, table.mate, h, h, visited);
    uint8_t& count = per_vertex[he.to(h)];
    if (count == 0) ++fans.vertices;
    if (count == 1) ++fans.pinched;
    if (count < 2) ++count;
  }
  return fans;
}

bool has_edge(std::span<const uint32_t> loop) {
  return std::any_of(loop.begin(), loop.end(), [&](uint32_t v) { return v != loop[0]; });
}

/// Connected components of the faces that have an edge, through mates (breadth first).
int64_t count_components(const PolygonMesh& mesh, const HalfEdges& he,
                         const std::vector<uint32_t>& mate) {
  int64_t components = 0;
  std::vector<uint8_t> seen(mesh.face_count(), 0);
  std::vector<uint32_t> queue;
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    if (seen[f] || !has_edge(mesh.face(f))) continue;
    ++components;
    seen[f] = 1;
    queue.assign(1, f);
    while (!queue.empty()) {
      const uint32_t g = queue.back();
      queue.pop_back();
      for (uint32_t h = mesh.face_start[g]; h < mesh.face_start[g + 1]; ++h) {
        if (mate[h] == kNone) continue;
        const uint32_t other = he.face(mate[h]);
        if (!seen[other]) {
          seen[other] = 1;
          queue.push_back(other);
        }
      }
    }
  }
  return components;
}

}  // namespace

MeshReport validate_mesh(const PolygonMesh& mesh, const ValidateOptions& options) {
  MeshReport report;
  const HalfEdges he(mesh);
  const EdgeTable table = build_edges(mesh.vertices.size(), he);
  report.edges = table.edges;
  report.boundary_edges = table.boundary;
  report.nonmanifold_edges = table.nonmanifold;
  report.closed = table.boundary == 0;
  report.oriented = table.oriented;
  report.volume = signed_volume(mesh);
  report.outward = report.closed && report.oriented && report.volume > 0;
  if (!options.full_report) return report;
  report.components = count_components(mesh, he, table.mate);
  // Fans are only defined when no edge has more than two sides; otherwise not manifold anyway.
  const Fans fans = table.nonmanifold == 0 ? count_fans(mesh.vertices.size(), he, table) : Fans{};
  report.manifold = table.nonmanifold == 0 && fans.pinched == 0;
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (all_collinear(mesh.vertices, mesh.face(f))) ++report.degenerate_faces;
  if (report.closed && report.manifold && report.oriented) {
    int64_t faces = 0;
    for (size_t f = 0; f < mesh.face_count(); ++f) faces += has_edge(mesh.face(f)) ? 1 : 0;
    const int64_t chi = fans.vertices - table.edges + faces;
    report.genus = (2 * report.components - chi) / 2;
  }
  if (options.check_self_intersection) {
    report.self_intersecting = self_intersects(mesh);
    report.self_touching = false;
    // Distinct indices at equal coordinates count as a contact in self_intersects(); a mesh whose
    // faces meet only there touches itself. Identify those vertices and test again: faces sharing
    // a vertex or an edge then meet only if they meet beyond it. A face that would repeat a
    // vertex keeps the contact (it touches itself within one face).
    if (*report.self_intersecting) {
      PolygonMesh welded = mesh;
      if (weld_duplicate_vertices(welded) > 0 &&
          distinct_face_vertices(welded) == distinct_face_vertices(mesh) &&
          !self_intersects(welded)) {
        report.self_intersecting = false;
        report.self_touching = true;
      }
    }
  }
  return report;
}

}  // namespace cover
