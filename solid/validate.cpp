// Leaf validation (validate.h): edge table, vertex links, components, Euler characteristic.
// Notation:
//   half-edge h  a directed pair (from[h], to[h]) of consecutive indices of one face's loop
//                (wrapping); a pair with from == to (a repeated index) is dropped. Face f owns the
//                half-edges face_first[f] .. face_first[f+1]-1, in loop order.
//   false pair   (u,v) and (v,u) in the same face (paper §3 Fig. 1). Each pair is an edge of its
//                own, glued only to itself, and is never a side of a surface edge.
//   real edge    the other half-edges, grouped by undirected vertex pair; its sides are its
//                half-edges (a boundary edge has one, a manifold edge two).
//   edge end     node 2·e + (v == hi[e]): edge e seen from its endpoint v.
//   corner       two consecutive half-edges of a face meeting at a vertex; it joins two edge ends.
//                A vertex is manifold when its corners join all its edge ends into one fan.
// The topology is that of the index lists read literally: each face is a disk bounded by its loop,
// glued to itself along its false pairs (L loops joined by L−1 false edges: a disk with L−1 holes)
// and to other faces along real edges. So χ = V − E + F counts the false pairs in E, which equals
// V − E_real + Σ_f (2 − L_f).

#include "solid/validate.h"

#include <algorithm>
#include <numeric>

#include "solid/detail/exact_geometry.h"
#include "solid/measure.h"

namespace cover {
namespace {

/// Disjoint sets over 0 .. n-1 (path halving; the smaller index becomes the root).
class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b) parent_[b] = a;
    if (b < a) parent_[a] = b;
  }

 private:
  std::vector<uint32_t> parent_;
};

struct HalfEdges {
  std::vector<uint32_t> from, to, face;  ///< per half-edge
  std::vector<uint32_t> face_first;      ///< #F+1 offsets
};

HalfEdges collect_half_edges(const PolygonMesh& mesh) {
  HalfEdges he;
  const size_t n = mesh.face_vertices.size();
  he.from.reserve(n);
  he.to.reserve(n);
  he.face.reserve(n);
  he.face_first.reserve(mesh.face_count() + 1);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    he.face_first.push_back(static_cast<uint32_t>(he.from.size()));
    auto loop = mesh.face(f);
    for (size_t i = 0; i < loop.size(); ++i) {
      const uint32_t u = loop[i], v = loop[i + 1 < loop.size() ? i + 1 : 0];
      if (u == v) continue;
      he.from.push_back(u);
      he.to.push_back(v);
      he.face.push_back(static_cast<uint32_t>(f));
    }
  }
  he.face_first.push_back(static_cast<uint32_t>(he.from.size()));
  return he;
}

/// Edges of the mesh: ids per half-edge, endpoints per edge, and the per-edge counts.
struct EdgeTable {
  std::vector<uint32_t> edge;    ///< per half-edge: its edge id
  std::vector<uint32_t> lo, hi;  ///< per edge: endpoints, lo < hi
  int64_t boundary = 0;
  int64_t nonmanifold = 0;
  bool oriented = true;
};

/// One half-edge in the bucket of its smaller endpoint, sorted by (hi, face).
struct BucketEntry {
  uint32_t hi, face, h;
  bool forward;  ///< from[h] == lo
};

/// Assigns edge ids to the half-edges of one undirected pair (lo, hi): entries[0..n) are sorted by
/// face. False pairs get one id each; the remaining (real) half-edges share one id.
void group_edges(uint32_t lo, const BucketEntry* entries, size_t n, EdgeTable& table,
                 UnionFind& faces) {
  uint32_t real_id = UINT32_MAX;
  int64_t real_fwd = 0, real_bwd = 0;
  uint32_t first_face = 0;
  auto new_edge = [&] {
    table.lo.push_back(lo);
    table.hi.push_back(entries[0].hi);
    return static_cast<uint32_t>(table.lo.size() - 1);
  };
  for (size_t s0 = 0; s0 < n;) {
    size_t s1 = s0;
    int64_t fwd = 0, bwd = 0;
    for (; s1 < n && entries[s1].face == entries[s0].face; ++s1)
      (entries[s1].forward ? fwd : bwd) += 1;
    // The k-th forward and k-th backward half-edge of the face form false pair k.
    const int64_t pairs = std::min(fwd, bwd);
    const size_t base = table.lo.size();
    for (int64_t k = 0; k < pairs; ++k) new_edge();
    int64_t seen_fwd = 0, seen_bwd = 0;
    for (size_t i = s0; i < s1; ++i) {
      const uint32_t h = entries[i].h;
      int64_t& seen = entries[i].forward ? seen_fwd : seen_bwd;
      if (seen < pairs) {
        table.edge[h] = static_cast<uint32_t>(base + seen++);
        continue;
      }
      ++seen;
      if (real_id == UINT32_MAX) {
        real_id = new_edge();
        first_face = entries[i].face;
      }
      table.edge[h] = real_id;
      (entries[i].forward ? real_fwd : real_bwd) += 1;
      faces.unite(first_face, entries[i].face);
    }
    s0 = s1;
  }
  const int64_t sides = real_fwd + real_bwd;
  if (sides == 1) ++table.boundary;
  if (sides > 2) ++table.nonmanifold;
  if (sides == 2 && real_fwd != 1) table.oriented = false;
}

/// Builds the edge table with a counting sort by smaller endpoint, then a sort of each bucket.
EdgeTable build_edges(size_t vertex_count, const HalfEdges& he, UnionFind& faces) {
  const size_t n = he.from.size();
  std::vector<uint32_t> bucket_start(vertex_count + 1, 0);
  for (size_t h = 0; h < n; ++h) ++bucket_start[std::min(he.from[h], he.to[h]) + 1];
  std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
  std::vector<BucketEntry> entries(n);
  {
    std::vector<uint32_t> next(bucket_start.begin(), bucket_start.end() - 1);
    for (size_t h = 0; h < n; ++h) {
      const uint32_t lo = std::min(he.from[h], he.to[h]), hi = std::max(he.from[h], he.to[h]);
      entries[next[lo]++] = {hi, he.face[h], static_cast<uint32_t>(h), he.from[h] == lo};
    }
  }
  EdgeTable table;
  table.edge.resize(n);
  table.lo.reserve(n / 2 + 1);
  table.hi.reserve(n / 2 + 1);
  for (uint32_t lo = 0; lo < vertex_count; ++lo) {
    BucketEntry* begin = entries.data() + bucket_start[lo];
    BucketEntry* end = entries.data() + bucket_start[lo + 1];
    std::sort(begin, end, [](const BucketEntry& a, const BucketEntry& b) {
      return a.hi != b.hi ? a.hi < b.hi : a.face < b.face;
    });
    for (BucketEntry* g = begin; g != end;) {
      BucketEntry* g1 = g;
      while (g1 != end && g1->hi == g->hi) ++g1;
      group_edges(lo, g, static_cast<size_t>(g1 - g), table, faces);
      g = g1;
    }
  }
  return table;
}

struct VertexLinks {
  int64_t used = 0;     ///< vertices on at least one edge
  int64_t pinched = 0;  ///< vertices whose corners form more than one fan
};

VertexLinks vertex_links(size_t vertex_count, const HalfEdges& he, const EdgeTable& table) {
  const size_t edges = table.lo.size();
  UnionFind ends(2 * edges);
  auto end_at = [&](uint32_t h, uint32_t v) {
    const uint32_t e = table.edge[h];
    return 2 * e + (v == table.hi[e] ? 1u : 0u);
  };
  for (size_t f = 0; f + 1 < he.face_first.size(); ++f) {
    const uint32_t first = he.face_first[f], last = he.face_first[f + 1];
    for (uint32_t h = first; h < last; ++h) {
      const uint32_t next = h + 1 < last ? h + 1 : first;
      const uint32_t v = he.to[h];
      ends.unite(end_at(h, v), end_at(next, v));
    }
  }
  VertexLinks links;
  std::vector<uint8_t> fans(vertex_count, 0);
  for (uint32_t node = 0; node < 2 * edges; ++node) {
    if (ends.find(node) != node) continue;
    const uint32_t v = (node & 1) ? table.hi[node / 2] : table.lo[node / 2];
    if (fans[v] == 0) ++links.used;
    if (fans[v] == 1) ++links.pinched;
    if (fans[v] < 2) ++fans[v];
  }
  return links;
}

}  // namespace

MeshReport validate_mesh(const PolygonMesh& mesh, const ValidateOptions& options) {
  MeshReport report;
  const HalfEdges he = collect_half_edges(mesh);
  UnionFind faces(mesh.face_count());
  const EdgeTable table = build_edges(mesh.vertices.size(), he, faces);
  const VertexLinks links = vertex_links(mesh.vertices.size(), he, table);

  int64_t faces_with_edges = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (he.face_first[f + 1] == he.face_first[f]) continue;
    ++faces_with_edges;
    if (faces.find(static_cast<uint32_t>(f)) == f) ++report.components;
  }
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (detail::all_collinear(mesh.vertices, mesh.face(f))) ++report.degenerate_faces;

  report.boundary_edges = table.boundary;
  report.nonmanifold_edges = table.nonmanifold;
  report.closed = table.boundary == 0;
  report.manifold = table.nonmanifold == 0 && links.pinched == 0;
  report.oriented = table.oriented;
  report.volume = signed_volume(mesh);
  report.outward = report.closed && report.oriented && report.volume > 0;
  if (report.closed && report.manifold && report.oriented) {
    const int64_t chi = links.used - static_cast<int64_t>(table.lo.size()) + faces_with_edges;
    report.genus = (2 * report.components - chi) / 2;
  }
  if (options.check_self_intersection) report.self_intersecting = self_intersects(mesh);
  return report;
}

}  // namespace cover
