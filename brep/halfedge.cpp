// HalfedgeMesh construction, conversion and operators (see halfedge.h for the notation).
#include "cover/brep/halfedge.h"

#include <stdexcept>
#include <string>

#include "cover/solid/errors.h"

namespace cover::brep {

HalfedgeMesh HalfedgeMesh::from_polygon_mesh(const PolygonMesh& mesh) {
  HalfedgeMesh m;
  const uint32_t nv = static_cast<uint32_t>(mesh.vertices.size());
  const size_t nc = mesh.face_vertices.size();  // corners = directed face sides
  m.position_.assign(mesh.vertices.begin(), mesh.vertices.end());
  m.vertex_halfedge_.assign(nv, kNone);
  m.vertex_deleted_.assign(nv, 0);
  // Corner c of face f goes face_vertices[c] → the next index of the same face.
  std::vector<uint32_t> corner_head(nc), corner_face(nc);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t s = mesh.face_start[f], e = mesh.face_start[f + 1];
    if (e - s < 3) throw InputError("face " + std::to_string(f) + ": fewer than 3 vertices");
    for (uint32_t c = s; c < e; ++c) {
      corner_head[c] = mesh.face_vertices[c + 1 < e ? c + 1 : s];
      corner_face[c] = static_cast<uint32_t>(f);
      if (corner_head[c] == mesh.face_vertices[c])
        throw InputError("face " + std::to_string(f) + ": repeated consecutive vertex " +
                         std::to_string(corner_head[c]));
    }
  }
  // Corners bucketed by origin vertex (CSR) to find each corner's opposite in O(degree).
  std::vector<uint32_t> start(nv + 1, 0), bucket(nc);
  for (size_t c = 0; c < nc; ++c) ++start[mesh.face_vertices[c] + 1];
  for (uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t c = 0; c < nc; ++c)
      bucket[fill[mesh.face_vertices[c]]++] = static_cast<uint32_t>(c);
  }
  std::vector<uint32_t> corner_he(nc, kNone);
  m.origin_.reserve(2 * nc);
  for (size_t c = 0; c < nc; ++c) {
    const uint32_t a = mesh.face_vertices[c], b = corner_head[c];
    for (uint32_t i = start[a]; i < start[a + 1]; ++i)
      if (bucket[i] != c && corner_head[bucket[i]] == b)
        throw InputError("edge " + std::to_string(a) + "-" + std::to_string(b) +
                         " is used twice in the same direction (not an oriented 2-manifold)");
    if (corner_he[c] != kNone) continue;
    const uint32_t h = m.new_edge(a, b);
    corner_he[c] = h;
    for (uint32_t i = start[b]; i < start[b + 1]; ++i)
      if (corner_head[bucket[i]] == a) {
        corner_he[bucket[i]] = h ^ 1;
        break;
      }
  }
  m.face_halfedge_.resize(mesh.face_count());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t s = mesh.face_start[f], e = mesh.face_start[f + 1];
    m.face_halfedge_[f] = corner_he[s];
    for (uint32_t c = s; c < e; ++c) {
      m.face_[corner_he[c]] = static_cast<uint32_t>(f);
      m.link(corner_he[c], corner_he[c + 1 < e ? c + 1 : s]);
    }
  }
  return m;
}

PolygonMesh HalfedgeMesh::to_polygon_mesh() const {
  PolygonMesh out;
  std::vector<uint32_t> index(vertex_slots(), kNone);
  for (uint32_t v = 0; v < vertex_slots(); ++v)
    if (!vertex_deleted(v)) {
      index[v] = static_cast<uint32_t>(out.vertices.size());
      out.vertices.push_back(position_[v]);
    }
  std::vector<uint32_t> loop;
  for (uint32_t f = 0; f < face_slots(); ++f) {
    if (face_deleted(f)) continue;
    loop.clear();
    uint32_t h = face_halfedge_[f];
    do {
      loop.push_back(index[origin_[h]]);
      h = next_[h];
    } while (h != face_halfedge_[f]);
    out.add_face(loop);
  }
  return out;
}

uint32_t HalfedgeMesh::face_degree(uint32_t f) const {
  uint32_t n = 0, h = face_halfedge_[f];
  do {
    ++n;
    h = next_[h];
  } while (h != face_halfedge_[f]);
  return n;
}

uint32_t HalfedgeMesh::add_vertex(const Vec3& p) {
  position_.push_back(p);
  vertex_halfedge_.push_back(kNone);
  vertex_deleted_.push_back(0);
  return static_cast<uint32_t>(position_.size() - 1);
}

void HalfedgeMesh::delete_vertex(uint32_t v) {
  if (vertex_halfedge_[v] != kNone)
    throw PreconditionError("delete_vertex: vertex is not isolated");
  vertex_deleted_[v] = 1;
}

uint32_t HalfedgeMesh::new_edge(uint32_t a, uint32_t b) {
  const uint32_t h = static_cast<uint32_t>(origin_.size());
  origin_.push_back(a);
  origin_.push_back(b);
  for (int i = 0; i < 2; ++i) {
    next_.push_back(kNone);
    prev_.push_back(kNone);
    face_.push_back(kNone);
  }
  if (vertex_halfedge_[a] == kNone) vertex_halfedge_[a] = h;
  if (vertex_halfedge_[b] == kNone) vertex_halfedge_[b] = h ^ 1;
  return h;
}

uint32_t HalfedgeMesh::insert_edge(uint32_t a, uint32_t b) {
  if (a == b) throw PreconditionError("insert_edge: a loop edge");
  return new_edge(a, b);
}

void HalfedgeMesh::delete_edge(uint32_t h) {
  const uint32_t t = h ^ 1, a = origin_[h], b = origin_[t];
  const uint32_t f = face_[h], g = face_[t];
  if (f == kNone && g == kNone) {
    origin_[h] = origin_[t] = kNone;
    // Another outgoing half-edge of a (of b) is not reachable through faces here: scan.
    for (uint32_t v : {a, b}) {
      if (vertex_halfedge_[v] != h && vertex_halfedge_[v] != t) continue;
      vertex_halfedge_[v] = kNone;
      for (uint32_t k = 0; k < halfedge_slots(); ++k)
        if (origin_[k] == v) {
          vertex_halfedge_[v] = k;
          break;
        }
    }
    return;
  }
  if (f == kNone || g == kNone || f == g)
    throw PreconditionError("delete_edge: needs two distinct faces or none");
  for (uint32_t k = next_[t]; k != t; k = next_[k]) face_[k] = f;
  if (vertex_halfedge_[a] == h) vertex_halfedge_[a] = next_[t];
  if (vertex_halfedge_[b] == t) vertex_halfedge_[b] = next_[h];
  face_halfedge_[f] = next_[h];
  face_halfedge_[g] = kNone;
  link(prev_[h], next_[t]);
  link(prev_[t], next_[h]);
  origin_[h] = origin_[t] = kNone;
  next_[h] = prev_[h] = next_[t] = prev_[t] = kNone;
  face_[h] = face_[t] = kNone;
}

uint32_t HalfedgeMesh::make_face(std::span<const uint32_t> loop) {
  const uint32_t f = static_cast<uint32_t>(face_halfedge_.size());
  for (size_t i = 0; i < loop.size(); ++i) {
    const uint32_t h = loop[i], n = loop[i + 1 < loop.size() ? i + 1 : 0];
    if (face_[h] != kNone || head(h) != origin_[n])
      throw PreconditionError("make_face: not a closed chain of border half-edges");
  }
  face_halfedge_.push_back(loop[0]);
  for (size_t i = 0; i < loop.size(); ++i) {
    face_[loop[i]] = f;
    link(loop[i], loop[i + 1 < loop.size() ? i + 1 : 0]);
  }
  return f;
}

uint32_t HalfedgeMesh::split_edge(uint32_t h, const Vec3& p) {
  const uint32_t t = h ^ 1, b = origin_[t];
  const uint32_t m = add_vertex(p);
  const uint32_t u = new_edge(m, b), w = u ^ 1;  // u: m → b beside h, w: b → m beside t
  origin_[t] = m;
  vertex_halfedge_[m] = u;
  if (vertex_halfedge_[b] == t) vertex_halfedge_[b] = w;
  face_[u] = face_[h];
  if (face_[h] != kNone) {
    const uint32_t n = next_[h];
    link(h, u);
    link(u, n);
  }
  face_[w] = face_[t];
  if (face_[t] != kNone) {
    const uint32_t q = prev_[t];
    link(q, w);
    link(w, t);
  }
  return m;
}

uint32_t HalfedgeMesh::split_face(uint32_t a, uint32_t b) {
  const uint32_t f = face_[a];
  if (f == kNone || face_[b] != f || a == b) throw PreconditionError("split_face: bad corners");
  const uint32_t pa = prev_[a], pb = prev_[b];
  const uint32_t x = new_edge(origin_[a], origin_[b]), y = x ^ 1;
  link(pa, x);
  link(x, b);
  link(pb, y);
  link(y, a);
  const uint32_t nf = static_cast<uint32_t>(face_halfedge_.size());
  face_halfedge_.push_back(y);
  for (uint32_t k = a; k != y; k = next_[k]) face_[k] = nf;
  face_[y] = nf;
  face_[x] = f;
  face_halfedge_[f] = x;
  return x;
}

void HalfedgeMesh::detach_edge(uint32_t h) {
  const uint32_t t = h ^ 1;
  if (face_[h] == kNone || face_[t] == kNone) throw PreconditionError("detach_edge: a border edge");
  const uint32_t y = new_edge(origin_[h], origin_[t]) ^ 1;  // y: head(h) → origin(h), like t
  const uint32_t g = face_[t], p = prev_[t], n = next_[t];
  face_[y] = g;
  link(p, y);
  link(y, n);
  if (face_halfedge_[g] == t) face_halfedge_[g] = y;
  face_[t] = kNone;
  next_[t] = prev_[t] = kNone;
}

uint32_t HalfedgeMesh::border_next(uint32_t h) const {
  const uint32_t start = h ^ 1;
  if (face_[start] == kNone) return kNone;
  uint32_t g = start;
  while (true) {
    g = prev_[g] ^ 1;
    if (face_[g] == kNone) return g;
    if (g == start) return kNone;
  }
}

uint32_t HalfedgeMesh::split_nonmanifold_vertices() {
  // Outgoing half-edges of every vertex (CSR), then one walk per fan.
  const uint32_t nv = vertex_slots(), nh = halfedge_slots();
  std::vector<uint32_t> start(nv + 1, 0), out(nh);
  for (uint32_t h = 0; h < nh; ++h)
    if (origin_[h] != kNone) ++start[origin_[h] + 1];
  for (uint32_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t h = 0; h < nh; ++h)
      if (origin_[h] != kNone) out[fill[origin_[h]]++] = h;
  }
  std::vector<uint8_t> seen(nh, 0);
  std::vector<uint32_t> stack;
  uint32_t added = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    if (start[v + 1] - start[v] < 2) continue;
    bool first = true;
    for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
      if (seen[out[i]]) continue;
      // Collect the fan of out[i]: rotate across faces in both directions.
      const uint32_t target = first ? v : add_vertex(position_[v]);
      if (!first) ++added;
      first = false;
      stack.assign(1, out[i]);
      seen[out[i]] = 1;
      vertex_halfedge_[target] = out[i];
      while (!stack.empty()) {
        const uint32_t g = stack.back();
        stack.pop_back();
        origin_[g] = target;
        uint32_t nb[2] = {kNone, kNone};
        if (face_[g] != kNone) nb[0] = prev_[g] ^ 1;
        if (face_[g ^ 1] != kNone) nb[1] = next_[g ^ 1];
        for (uint32_t k : nb)
          if (k != kNone && !seen[k]) {
            seen[k] = 1;
            stack.push_back(k);
          }
      }
    }
  }
  return added;
}

}  // namespace cover::brep
