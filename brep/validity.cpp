// validate(HalfedgeMesh): link invariants, closedness, fans per vertex, Euler characteristic,
// components, boundary loops and genus (χ = 2C − 2g − B for an orientable surface).
#include "cover/brep/halfedge.h"
#include "cover/solid/union_find.h"

namespace cover::brep {

BrepReport validate(const HalfedgeMesh& m) {
  BrepReport r;
  const uint32_t nv = m.vertex_slots(), nh = m.halfedge_slots(), nf = m.face_slots();
  bool ok = true;
  int64_t face_sides = 0, border = 0;
  std::vector<uint32_t> degree(nv, 0);
  for (uint32_t h = 0; h < nh && ok; ++h) {
    if (m.edge_deleted(h)) {
      ok = m.edge_deleted(h ^ 1);
      continue;
    }
    const uint32_t v = m.origin(h);
    ok = v < nv && !m.vertex_deleted(v) && !m.edge_deleted(h ^ 1);
    if (!ok) break;
    ++degree[v];
    if (m.is_border(h)) {
      ++border;
      ok = m.next(h) == kNone && m.prev(h) == kNone;
    } else {
      ++face_sides;
      const uint32_t n = m.next(h);
      ok = m.face(h) < nf && !m.face_deleted(m.face(h)) && n < nh && m.prev(n) == h &&
           m.face(n) == m.face(h) && m.origin(n) == m.head(h);
    }
  }
  int64_t loop_sides = 0;
  for (uint32_t f = 0; f < nf && ok; ++f) {
    if (m.face_deleted(f)) continue;
    ++r.faces;
    uint32_t h = m.face_halfedge(f), n = 0;
    do {
      ok = m.face(h) == f && ++n <= nh;
      h = m.next(h);
    } while (ok && h != m.face_halfedge(f));
    ok = ok && n >= 2;
    loop_sides += n;
  }
  ok = ok && loop_sides == face_sides;
  for (uint32_t v = 0; v < nv && ok; ++v) {
    if (m.vertex_deleted(v)) continue;
    const uint32_t h = m.vertex_halfedge(v);
    ok = (h == kNone) == (degree[v] == 0) && (h == kNone || (h < nh && m.origin(h) == v));
    if (degree[v] > 0) ++r.vertices;
  }
  r.consistent = ok;
  if (!ok) return r;
  r.edges = (face_sides + border) / 2;
  r.closed = border == 0;
  r.euler = r.vertices - r.edges + r.faces;

  // Fans: each vertex's outgoing half-edges must be one orbit of the face rotations.
  std::vector<uint8_t> seen(nh, 0);
  std::vector<uint32_t> fans(nv, 0), stack;
  for (uint32_t h = 0; h < nh; ++h) {
    if (m.edge_deleted(h) || seen[h]) continue;
    ++fans[m.origin(h)];
    stack.assign(1, h);
    seen[h] = 1;
    while (!stack.empty()) {
      const uint32_t g = stack.back();
      stack.pop_back();
      const uint32_t nb[2] = {m.is_border(g) ? kNone : m.prev(g) ^ 1,
                              m.is_border(g ^ 1) ? kNone : m.next(g ^ 1)};
      for (uint32_t k : nb)
        if (k != kNone && !seen[k]) {
          seen[k] = 1;
          stack.push_back(k);
        }
    }
  }
  r.manifold = true;
  for (uint32_t v = 0; v < nv; ++v) r.manifold = r.manifold && fans[v] <= 1;

  UnionFind sets(nv);
  for (uint32_t h = 0; h < nh; h += 2)
    if (!m.edge_deleted(h)) sets.unite(m.origin(h), m.head(h));
  for (uint32_t v = 0; v < nv; ++v)
    if (!m.vertex_deleted(v) && degree[v] > 0 && sets.find(v) == v) ++r.components;

  std::vector<uint8_t> walked(nh, 0);
  for (uint32_t h = 0; h < nh; ++h) {
    if (m.edge_deleted(h) || !m.is_border(h) || walked[h]) continue;
    ++r.boundary_loops;
    for (uint32_t g = h; g != kNone && !walked[g]; g = m.border_next(g)) walked[g] = 1;
  }
  if (r.manifold) r.genus = (2 * r.components - r.euler - r.boundary_loops) / 2;
  return r;
}

}  // namespace cover::brep
