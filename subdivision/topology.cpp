#include "cover/subdivision/detail/topology.h"

#include <algorithm>
#include <string>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::subdivision_detail {

namespace {

constexpr size_t kGrain = 4096;

/// The first face with < 3 vertices, an index out of range or a repeated vertex, or kNone.
uint32_t first_bad_face(const PolygonMesh& mesh) {
  const size_t nv = mesh.vertices.size(), nf = mesh.face_count();
  std::vector<uint8_t> bad(nf, 0);
  parallel_for(nf, kGrain, [&](size_t b, size_t e) {
    std::vector<uint32_t> sorted;
    for (size_t f = b; f < e; ++f) {
      const auto face = mesh.face(f);
      if (face.size() == 3) {
        bad[f] = face[0] >= nv || face[1] >= nv || face[2] >= nv || face[0] == face[1] ||
                 face[1] == face[2] || face[2] == face[0];
        continue;
      }
      sorted.assign(face.begin(), face.end());
      std::sort(sorted.begin(), sorted.end());
      bad[f] = face.size() < 3 || sorted.back() >= nv ||
               std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    }
  });
  const auto it = std::find(bad.begin(), bad.end(), 1);
  return it == bad.end() ? kNone : static_cast<uint32_t>(it - bad.begin());
}

/// Throws the InputError that describes bad face f.
[[noreturn]] void refuse_face(const PolygonMesh& mesh, uint32_t f) {
  const auto face = mesh.face(f);
  const std::string name = "face " + std::to_string(f);
  if (face.size() < 3)
    throw InputError(name + " has " + std::to_string(face.size()) +
                     " vertices (subdivision needs at least 3)");
  std::vector<uint32_t> sorted(face.begin(), face.end());
  std::sort(sorted.begin(), sorted.end());
  if (sorted.back() >= mesh.vertices.size())
    throw InputError(name + ": vertex index " + std::to_string(sorted.back()) + " out of range");
  throw InputError(name + " repeats vertex " +
                   std::to_string(*std::adjacent_find(sorted.begin(), sorted.end())));
}

}  // namespace

void require_triangles(const PolygonMesh& mesh, const char* scheme) {
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (mesh.face(f).size() != 3)
      throw InputError("face " + std::to_string(f) + " has " + std::to_string(mesh.face(f).size()) +
                       " vertices (" + scheme + " subdivision needs triangles)");
}

Topology build_topology(const PolygonMesh& mesh) {
  if (const uint32_t f = first_bad_face(mesh); f != kNone) refuse_face(mesh, f);
  Topology t;
  t.mesh = &mesh;
  const size_t nv = mesh.vertices.size(), nf = mesh.face_count();
  const size_t nh = mesh.face_vertices.size();
  t.face_of.resize(nh);
  parallel_for(nf, kGrain, [&](size_t b, size_t e) {
    for (size_t f = b; f < e; ++f)
      for (uint32_t h = mesh.face_start[f]; h < mesh.face_start[f + 1]; ++h)
        t.face_of[h] = static_cast<uint32_t>(f);
  });
  // Outgoing corners per vertex (counting sort by source vertex, ascending corner order).
  t.ring_start.assign(nv + 1, 0);
  for (uint32_t v : mesh.face_vertices) ++t.ring_start[v + 1];
  for (size_t v = 0; v < nv; ++v) t.ring_start[v + 1] += t.ring_start[v];
  Buffer<uint32_t> out(nh);
  {
    std::vector<uint32_t> fill(t.ring_start.begin(), t.ring_start.end() - 1);
    for (uint32_t h = 0; h < nh; ++h) out[fill[mesh.face_vertices[h]]++] = h;
  }
  // Opposites: the corner b -> a among b's outgoing corners; a -> b must be a's only one.
  // out_to: the target of each outgoing corner, in the same order (contiguous per vertex).
  Buffer<uint32_t> out_to(nh);
  parallel_for(nh, kGrain, [&](size_t b0, size_t e0) {
    for (size_t i = b0; i < e0; ++i) out_to[i] = t.vertex(t.next(out[i]));
  });
  // Each pair is found from its smaller vertex, which writes both corners' opposites.
  t.opposite.resize(nh);
  parallel_for(nh, kGrain, [&](size_t b, size_t e) {
    std::fill(t.opposite.begin() + b, t.opposite.begin() + e, kNone);
  });
  std::vector<uint8_t> duplicate(nh, 0);
  parallel_for(nv, kGrain, [&](size_t b0, size_t e0) {
    for (size_t a = b0; a < e0; ++a) {
      const uint32_t lo = t.ring_start[a], hi = t.ring_start[a + 1];
      for (uint32_t i = lo; i < hi; ++i) {
        const uint32_t b = out_to[i];
        uint32_t same = 0, opp = kNone, opp_count = 0;
        for (uint32_t j = lo; j < hi; ++j) same += out_to[j] == b;
        if (same > 1) duplicate[out[i]] = 1;
        if (b < a) continue;
        for (uint32_t j = t.ring_start[b]; j < t.ring_start[b + 1]; ++j)
          if (out_to[j] == a) opp = out[j], ++opp_count;
        if (opp_count > 1) duplicate[out[i]] = 1;
        if (opp_count == 1 && same == 1) t.opposite[out[i]] = opp, t.opposite[opp] = out[i];
      }
    }
  });
  if (const auto it = std::find(duplicate.begin(), duplicate.end(), 1); it != duplicate.end()) {
    const auto h = static_cast<uint32_t>(it - duplicate.begin());
    throw InputError("edge (" + std::to_string(t.vertex(h)) + ", " +
                     std::to_string(t.vertex(t.next(h))) + ") of face " +
                     std::to_string(t.face_of[h]) + " is non-manifold or inconsistently oriented");
  }
  // Edges: a corner starts one when it has no opposite or precedes it; numbered per chunk of
  // corners, the chunks' counts summed in order.
  const auto starts_edge = [&](uint32_t h) {
    const uint32_t o = t.opposite[h];
    return o == kNone || h < o;
  };
  const size_t chunks = (nh + kGrain - 1) / kGrain;
  std::vector<uint32_t> chunk_first(chunks + 1, 0);
  parallel_for(chunks, 1, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c)
      for (size_t h = c * kGrain; h < std::min(nh, (c + 1) * kGrain); ++h)
        chunk_first[c + 1] += starts_edge(static_cast<uint32_t>(h));
  });
  for (size_t c = 0; c < chunks; ++c) chunk_first[c + 1] += chunk_first[c];
  t.edge_of.resize(nh);
  t.edge_half.resize(chunk_first[chunks]);
  parallel_for(chunks, 1, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c) {
      uint32_t edge = chunk_first[c];
      for (size_t i = c * kGrain; i < std::min(nh, (c + 1) * kGrain); ++i) {
        const auto h = static_cast<uint32_t>(i);
        if (!starts_edge(h)) continue;
        t.edge_half[edge] = h;
        t.edge_of[h] = edge;
        if (t.opposite[h] != kNone) t.edge_of[t.opposite[h]] = edge;
        ++edge;
      }
    }
  });
  // Rings: rotate h -> opposite(prev(h)) from the border corner (or the smallest corner).
  t.ring.resize(nh);
  t.border.assign(nv, 0);
  std::vector<uint8_t> bad(nv, 0);
  parallel_for(nv, kGrain, [&](size_t b0, size_t e0) {
    for (size_t v = b0; v < e0; ++v) {
      const uint32_t lo = t.ring_start[v], hi = t.ring_start[v + 1];
      if (lo == hi) continue;
      uint32_t start = out[lo], borders = 0;
      for (uint32_t i = lo; i < hi; ++i)
        if (t.opposite[out[i]] == kNone) start = out[i], ++borders;
      t.border[v] = borders > 0;
      uint32_t h = start, count = 0;
      do {
        t.ring[lo + count++] = h;
        h = t.opposite[t.prev(h)];
      } while (h != kNone && h != start && count < hi - lo);
      bad[v] = borders > 1 || count != hi - lo || h != (borders == 0 ? start : kNone);
    }
  });
  for (size_t v = 0; v < nv; ++v)
    if (bad[v])
      throw InputError("vertex " + std::to_string(v) +
                       " is non-manifold (its faces do not form one fan)");
  return t;
}

}  // namespace cover::subdivision_detail
