// Exact self-intersection test (validate.h). All predicates are CGAL's Epick filtered predicates
// on the input doubles (exact); no point is ever constructed. Notation:
//   triangle   three vertex indices and the face it covers; collinear triangles are dropped
//   tiling     the triangles of one face (solid/triangulate.h) cover exactly the face's region,
//              every loop vertex a tile corner; a face whose boundary crosses itself or winds
//              more than once is an intersection by itself
// Two triangles of the same face never count as intersecting. For other pairs the tests follow
// CGAL::Polygon_mesh_processing::self_intersections (internal::do_faces_intersect), with shared
// vertices decided by index:
//   3 shared  the same triangle twice: intersecting
//   2 shared  intersecting iff coplanar and both third vertices on the same side of the edge
//   1 shared  intersecting iff the edge opposite the shared vertex in one meets the other triangle
//   0 shared  CGAL::do_intersect (touching counts)

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "solid/box_pairs.h"
#include "solid/predicates.h"
#include "solid/triangulate.h"
#include "solid/validate.h"

namespace cover {
namespace {

using K = CGAL::Epick;
using Point3 = K::Point_3;

Point3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t face;
};

/// Whether the corners of `b` not in `skip` lie strictly on one side of the plane of `a`
/// (exact orient3d on the doubles): then b meets a's plane at most in the skipped corners.
bool strictly_aside(const Triangle& a, const Triangle& b, std::span<const Vec3> v,
                    uint32_t skip) {
  int side = 0;
  for (uint32_t c : b.v) {
    if (c == skip) continue;
    const int s = orient3d(v[a.v[0]], v[a.v[1]], v[a.v[2]], v[c]);
    if (s == 0 || (side != 0 && s != side)) return false;
    side = s;
  }
  return true;
}

/// Whether two triangles of different faces meet anywhere beyond their shared vertices.
/// Before CGAL's tests, a filter of at most six exact orient3d: when the unshared corners of one
/// triangle lie strictly on one side of the other's plane, they meet at most in the shared vertex.
bool triangles_meet(const Triangle& a, const Triangle& b, const std::vector<Point3>& p,
                    std::span<const Vec3> v) {
  int shared = 0, ia = 0, ib = 0;
  std::array<bool, 3> a_shared{}, b_shared{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.v[i] == b.v[j]) {
        ++shared;
        a_shared[i] = b_shared[j] = true;
        ia = i;
        ib = j;
      }
  if (shared == 3) return true;
  if (shared == 2) {
    int ra = 0, rb = 0;  // the unshared (third) vertices
    while (a_shared[ra]) ++ra;
    while (b_shared[rb]) ++rb;
    const Point3& q0 = p[a.v[(ra + 1) % 3]];
    const Point3& q1 = p[a.v[(ra + 2) % 3]];
    return CGAL::coplanar(q0, q1, p[a.v[ra]], p[b.v[rb]]) &&
           CGAL::coplanar_orientation(q0, q1, p[a.v[ra]], p[b.v[rb]]) == CGAL::POSITIVE;
  }
  const uint32_t skip = shared == 1 ? a.v[ia] : UINT32_MAX;
  if (strictly_aside(a, b, v, skip) || strictly_aside(b, a, v, skip)) return false;
  const K::Triangle_3 ta(p[a.v[0]], p[a.v[1]], p[a.v[2]]);
  const K::Triangle_3 tb(p[b.v[0]], p[b.v[1]], p[b.v[2]]);
  if (shared == 1) {
    const K::Segment_3 sa(p[a.v[(ia + 1) % 3]], p[a.v[(ia + 2) % 3]]);
    const K::Segment_3 sb(p[b.v[(ib + 1) % 3]], p[b.v[(ib + 2) % 3]]);
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

}  // namespace

bool self_intersects(const PolygonMesh& mesh) {
  std::vector<Point3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.push_back(to_point(v));

  std::vector<Triangle> triangles;
  triangles.reserve(mesh.face_vertices.size());
  std::vector<std::array<uint32_t, 3>> tiles;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    tiles.clear();
    if (triangulate_face(mesh.vertices, mesh.face(f), tiles) != FaceTiling::kSimple) return true;
    for (const auto& t : tiles) triangles.push_back({t, static_cast<uint32_t>(f)});
  }

  // Every pair of meeting triangle boxes (solid/box_pairs.h: a grid, in parallel); the answer
  // does not depend on the order, and a found intersection stops the search.
  std::vector<Bbox> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t].v) boxes[t].add(mesh.vertices[v]);
  std::atomic<bool> found{false};
  box_pairs(boxes, [&](uint32_t x, uint32_t y) {
    const Triangle& a = triangles[x];
    const Triangle& b = triangles[y];
    if (a.face != b.face && triangles_meet(a, b, points, mesh.vertices)) found = true;
    return found.load();
  });
  return found;
}

}  // namespace cover

namespace cover {

namespace {

/// For every overlapping pair (x in `probe`, y in `base`) calls on_pair(slab, x, y), in parallel
/// over slabs of kSlab probe boxes taken in order of their lower z bound; each slab meets the
/// base boxes whose z range overlaps its own (found by binary search on the lower z bounds,
/// widened by the tallest base box). `slab` indexes per-slab results. Returns the slab count.
template <class OnPair>
size_t bipartite_slabs(std::vector<const Box*> probe, std::vector<const Box*> base,
                       const OnPair& on_pair) {
  constexpr size_t kSlab = 1024;
  constexpr std::ptrdiff_t kCutoff = 2000;  // as in CGAL's self_intersections
  auto by_zmin = [](const Box* x, const Box* y) {
    return x->min_coord(2) < y->min_coord(2) || (x->min_coord(2) == y->min_coord(2) && x < y);
  };
  std::sort(probe.begin(), probe.end(), by_zmin);
  std::sort(base.begin(), base.end(), by_zmin);
  double tallest = 0;
  for (const Box* b : base) tallest = std::max(tallest, b->max_coord(2) - b->min_coord(2));
  const size_t slabs = (probe.size() + kSlab - 1) / kSlab;
  parallel_for(slabs, 1, [&](size_t s0, size_t s1) {
    std::vector<const Box*> mine, others;
    for (size_t s = s0; s < s1; ++s) {
      const size_t lo = s * kSlab, hi = std::min(probe.size(), lo + kSlab);
      mine.assign(probe.begin() + lo, probe.begin() + hi);
      const double zlo = mine.front()->min_coord(2);
      double zhi = zlo;
      for (const Box* b : mine) zhi = std::max(zhi, b->max_coord(2));
      auto first = std::lower_bound(base.begin(), base.end(), zlo - tallest,
                                    [](const Box* b, double z) { return b->min_coord(2) < z; });
      auto last = std::upper_bound(base.begin(), base.end(), zhi,
                                   [](double z, const Box* b) { return z < b->min_coord(2); });
      others.clear();
      for (auto it = first; it != last; ++it)
        if ((*it)->max_coord(2) >= zlo) others.push_back(*it);
      CGAL::box_intersection_d(mine.begin(), mine.end(), others.begin(), others.end(),
                               [&](const Box* x, const Box* y) { on_pair(s, x, y); }, kCutoff);
    }
  });
  return slabs;
}

/// For every overlapping pair of `boxes` calls on_pair(slab, x, y) once, in parallel over slabs
/// of kSlab boxes in order of their lower z bound (as self_intersects does). Returns the slab
/// count.
template <class OnPair>
size_t self_slabs(std::vector<const Box*> boxes, const OnPair& on_pair) {
  constexpr size_t kSlab = 4096;
  constexpr std::ptrdiff_t kCutoff = 2000;  // as in CGAL's self_intersections
  std::sort(boxes.begin(), boxes.end(), [](const Box* x, const Box* y) {
    return x->min_coord(2) < y->min_coord(2) || (x->min_coord(2) == y->min_coord(2) && x < y);
  });
  const size_t slabs = (boxes.size() + kSlab - 1) / kSlab;
  parallel_for(slabs, 1, [&](size_t s0, size_t s1) {
    std::vector<const Box*> mine, later;
    for (size_t s = s0; s < s1; ++s) {
      const size_t lo = s * kSlab, hi = std::min(boxes.size(), lo + kSlab);
      mine.assign(boxes.begin() + lo, boxes.begin() + hi);
      CGAL::Bbox_3 slab;
      for (const Box* b : mine) slab += b->bbox();
      later.clear();
      for (size_t i = hi; i < boxes.size() && boxes[i]->min_coord(2) <= slab.zmax(); ++i)
        if (CGAL::do_overlap(boxes[i]->bbox(), slab)) later.push_back(boxes[i]);
      auto call = [&](const Box* x, const Box* y) { on_pair(s, x, y); };
      CGAL::box_self_intersection_d(mine.begin(), mine.end(), call, kCutoff);
      CGAL::box_intersection_d(mine.begin(), mine.end(), later.begin(), later.end(), call, kCutoff);
    }
  });
  return slabs;
}

}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> intersecting_face_pairs(
    const PolygonMesh& mesh, std::span<const uint8_t> suspect) {
  const bool all = suspect.empty();
  const size_t faces = mesh.face_count();
  // With suspects, only faces whose box meets a suspect face's box are tiled (face boxes first:
  // most faces of a large mesh are far from the few suspects). Boxes stay in place and are
  // handled by pointer (their ids are their addresses).
  const size_t suspect_faces =
      all ? faces : static_cast<size_t>(std::count(suspect.begin(), suspect.end(), uint8_t{1}));
  if (suspect_faces == 0) return {};
  std::vector<uint8_t> needed(faces, 4 * suspect_faces >= faces ? 1 : 0);
  if (!needed.empty() && !needed[0]) {
    std::vector<Box> face_boxes(faces);
    parallel_for(faces, 4096, [&](size_t f0, size_t f1) {
      for (size_t f = f0; f < f1; ++f) {
        CGAL::Bbox_3 b;
        for (uint32_t v : mesh.face(f)) b += to_point(mesh.vertices[v]).bbox();
        face_boxes[f] = Box(b, static_cast<uint32_t>(f));
      }
    });
    std::vector<const Box*> all_ptrs(faces), suspect_ptrs;
    for (uint32_t f = 0; f < faces; ++f) {
      all_ptrs[f] = &face_boxes[f];
      if (suspect[f]) suspect_ptrs.push_back(&face_boxes[f]), needed[f] = 1;
    }
    if (suspect_ptrs.empty()) return {};
    // Concurrent slabs may mark one face: relaxed atomic byte stores.
    bipartite_slabs(std::move(suspect_ptrs), std::move(all_ptrs),
                    [&](size_t, const Box*, const Box* y) {
                      std::atomic_ref<uint8_t>(needed[y->info()]).store(1, std::memory_order_relaxed);
                    });
  }
  std::vector<Point3> points(mesh.vertices.size());
  for (size_t v = 0; v < points.size(); ++v) points[v] = to_point(mesh.vertices[v]);
  // Tiles of the needed faces, per chunk of faces, then in face order.
  constexpr size_t kGrain = 1024;
  const size_t chunks = (faces + kGrain - 1) / kGrain;
  std::vector<std::vector<Triangle>> chunk_tris(chunks);
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> chunk_bad(chunks);
  parallel_for(faces, kGrain, [&](size_t f0, size_t f1) {
    std::vector<std::array<uint32_t, 3>> tiles;
    const size_t c = f0 / kGrain;
    for (size_t f = f0; f < f1; ++f) {
      if (!needed[f]) continue;
      tiles.clear();
      if (triangulate_face(mesh.vertices, mesh.face(f), tiles) != FaceTiling::kSimple) {
        if (all || suspect[f]) chunk_bad[c].push_back({static_cast<uint32_t>(f), static_cast<uint32_t>(f)});
        continue;
      }
      for (const auto& t : tiles) chunk_tris[c].push_back({t, static_cast<uint32_t>(f)});
    }
  });
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  std::vector<Triangle> triangles;
  for (size_t c = 0; c < chunks; ++c) {
    pairs.insert(pairs.end(), chunk_bad[c].begin(), chunk_bad[c].end());
    triangles.insert(triangles.end(), chunk_tris[c].begin(), chunk_tris[c].end());
  }
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const auto& v = triangles[t].v;
    boxes.emplace_back(points[v[0]].bbox() + points[v[1]].bbox() + points[v[2]].bbox(), t);
  }
  std::vector<const Box*> box_ptrs, suspects;
  for (const Box& b : boxes) {
    box_ptrs.push_back(&b);
    if (!all && suspect[triangles[b.info()].face]) suspects.push_back(&b);
  }
  auto meet = [&](const Box* x, const Box* y) {
    const Triangle& a = triangles[x->info()];
    const Triangle& b = triangles[y->info()];
    return a.face != b.face && triangles_meet(a, b, points, mesh.vertices);
  };
  auto key = [&](const Box* x, const Box* y) {
    const uint32_t f = triangles[x->info()].face, g = triangles[y->info()].face;
    return std::pair{std::min(f, g), std::max(f, g)};
  };
  if (all || 4 * suspects.size() >= box_ptrs.size()) {
    // Mostly suspects: one self-intersection pass over the tiles (each pair once), skipping
    // pairs without a suspect.
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found((box_ptrs.size() + 4095) / 4096);
    self_slabs(std::move(box_ptrs), [&](size_t s, const Box* x, const Box* y) {
      if (!all && !suspect[triangles[x->info()].face] && !suspect[triangles[y->info()].face])
        return;
      if (meet(x, y)) found[s].push_back(key(x, y));
    });
    for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  } else if (!suspects.empty()) {
    // Suspects against every triangle: a pair of two suspects is met twice (deduplicated below).
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found((suspects.size() + 1023) / 1024);
    bipartite_slabs(std::move(suspects), std::move(box_ptrs),
                    [&](size_t s, const Box* x, const Box* y) {
                      if (meet(x, y)) found[s].push_back(key(x, y));
                    });
    for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace cover
