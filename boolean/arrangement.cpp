// build_arrangement() (boolean/detail/arrangement.h), steps 1–3 of evaluate(): step 1 (leaf
// triangulation, mesh/triangulate.h) and the global point identity here, step 2 in
// intersect.cpp, step 3 in split.cpp. The exactness scheme is described in
// boolean/detail/arrangement.h, the notation in boolean/detail/arrangement_steps.h.
#include <algorithm>
#include <boost/sort/spreadsort/integer_sort.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <span>

#include "cover/boolean/detail/arrangement_steps.h"
#include "cover/mesh/triangulate.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::boolean_detail {
namespace {

// ---- step 1: leaf faces → triangles ---------------------------------------------------------

/// Point ids of the input vertices, deduplicated by exact value (±0 equal), in order of first
/// occurrence. A flat open-addressing table (linear probing, capacity ≥ 2n) rather than
/// std::unordered_map, whose node allocations and byte-wise double hashing would dominate this
/// serial loop.
std::vector<uint32_t> dedup_vertices(const Solid& solid, std::vector<Vec3>& originals) {
  const size_t n = solid.vertices.size();
  size_t cap = 16;
  while (cap < 2 * n) cap *= 2;
  auto bits = [](double d) {
    uint64_t b;
    d = d == 0 ? 0.0 : d;  // −0 hashes as +0 (they compare equal)
    std::memcpy(&b, &d, sizeof b);
    return b;
  };
  auto hash = [&](const Vec3& p) {
    uint64_t h = bits(p.x) * 0x9e3779b97f4a7c15ull;
    h ^= bits(p.y) * 0xc2b2ae3d27d4eb4full + (h >> 29);
    h ^= bits(p.z) * 0x165667b19e3779f9ull + (h >> 31);
    return h ^ (h >> 32);
  };
  std::vector<uint32_t> slot(cap, kNone);
  std::vector<uint32_t> id(n);
  originals.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3& v = solid.vertices[i];
    size_t s = hash(v) & (cap - 1);
    while (slot[s] != kNone && !(originals[slot[s]] == v)) s = (s + 1) & (cap - 1);
    if (slot[s] == kNone) {
      slot[s] = static_cast<uint32_t>(originals.size());
      originals.push_back(v);
    }
    id[i] = slot[s];
  }
  return id;
}

/// The tris of every leaf face (triangulate_face on the deduplicated points, in the leaf's
/// orientation), grouped by leaf in leaf order. `winding` gets one flag per leaf: set when one of
/// its faces winds more than once (a star: self-intersecting by itself). Throws InputError,
/// naming the leaf and the face, when a face's boundary crosses itself (no region to tile).
std::vector<Tri> leaf_tris(const Solid& solid, const std::vector<uint32_t>& id,
                           const std::vector<Vec3>& pos, size_t grain,
                           std::vector<uint8_t>& winding) {
  const size_t faces = solid.face_count();
  // Each chunk of faces triangulates into one buffer (face f's tris from first[f] of its chunk's
  // to the next face's, or the buffer's end), not one vector per face: allocating many small
  // vectors would be most of this step.
  const size_t chunk = grain * 16;
  std::vector<std::vector<std::array<uint32_t, 3>>> chunk_tris((faces + chunk - 1) / chunk);
  std::vector<uint32_t> first(faces, 0);
  std::vector<FaceTiling> tiling(faces, FaceTiling::kSimple);
  parallel_for(faces, chunk, [&](size_t begin, size_t end) {
    std::vector<std::array<uint32_t, 3>>& out = chunk_tris[begin / chunk];
    std::vector<uint32_t> loop;
    for (size_t f = begin; f < end; ++f) {
      auto face = solid.face(f);
      loop.assign(face.begin(), face.end());
      if (solid.face_sign[f] < 0) std::reverse(loop.begin(), loop.end());
      for (uint32_t& v : loop) v = id[v];
      first[f] = static_cast<uint32_t>(out.size());
      tiling[f] = triangulate_face(pos, loop, out);
    }
  });
  auto face_tris = [&](size_t f) {
    const auto& out = chunk_tris[f / chunk];
    const size_t end = (f + 1) % chunk == 0 || f + 1 == faces ? out.size() : first[f + 1];
    return std::span<const std::array<uint32_t, 3>>(out.data() + first[f], end - first[f]);
  };
  winding.assign(solid.leaves.size(), 0);
  std::vector<Tri> tris;
  size_t total = 0;
  for (const auto& t : chunk_tris) total += t.size();
  tris.reserve(total);
  for (uint32_t l = 0; l < solid.leaves.size(); ++l) {
    const Leaf& leaf = solid.leaves[l];
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f) {
      if (tiling[f] == FaceTiling::kCrossing)
        throw InputError((leaf.origin.empty() ? leaf.name : leaf.origin + " (" + leaf.name + ")") +
                         ": face " + std::to_string(f - leaf.first_face) +
                         " has a boundary that crosses itself; evaluate needs faces that bound "
                         "a region");
      if (tiling[f] == FaceTiling::kWinding) winding[l] = 1;
      for (const auto& t : face_tris(f)) tris.push_back({t, l, static_cast<uint32_t>(f)});
    }
  }
  return tris;
}

// ---- global identity by value ---------------------------------------------------------------

/// Merges points of equal exact value (union to the smallest id). Ids are built canonically, so
/// equal values under different ids arise only at degeneracies (an edge crossing another leaf's
/// edge exactly, a vertex on another leaf's face, triple points, coplanar overlaps); candidates
/// are found by hashing grid cells that each point's interval box meets, then compared exactly
/// within a cell. The cell side h is 2^-36 of the scene's extent or of its largest coordinate,
/// whichever is larger, far above the width of the intervals, which is relative to the
/// coordinates (a unit box at 1e15 has intervals about 0.1 wide). A point whose interval still
/// spans more than two cells on an axis ("wide") is compared with every point whose interval
/// meets its own (all of them, sorted exactly, when there are many wide points).
std::vector<uint32_t> merge_equal(const std::vector<Point>& pts, const std::vector<uint32_t>& ids,
                                  const Bbox& box) {
  UnionFind sets(pts.size());
  const double extent =
      std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z,
                std::abs(box.min.x), std::abs(box.min.y), std::abs(box.min.z), std::abs(box.max.x),
                std::abs(box.max.y), std::abs(box.max.z), 1e-300});
  const double h = extent * 0x1p-36;
  std::vector<std::pair<uint64_t, uint32_t>> cells;
  std::vector<uint32_t> wide;
  cells.reserve(ids.size());
  for (uint32_t id : ids) {
    const auto& ap = CGAL::approx(pts[id]);
    int64_t lo[3], hi[3];
    bool is_wide = false;
    for (int a = 0; a < 3; ++a) {
      const double l = std::floor((ap[a].inf() - box.min[a]) / h),
                   u = std::floor((ap[a].sup() - box.min[a]) / h);
      is_wide = is_wide || !(u - l <= 1) || !(std::abs(l) < 0x1p62 && std::abs(u) < 0x1p62);
      if (is_wide) break;
      lo[a] = static_cast<int64_t>(l);
      hi[a] = static_cast<int64_t>(u);
    }
    if (is_wide) {
      wide.push_back(id);
      continue;
    }
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          uint64_t key = static_cast<uint64_t>(x) * 0x9e3779b97f4a7c15ull;
          key ^= static_cast<uint64_t>(y) * 0xc2b2ae3d27d4eb4full + (key >> 29);
          key ^= static_cast<uint64_t>(z) * 0x165667b19e3779f9ull + (key >> 31);
          cells.emplace_back(key, id);
        }
  }
  auto sorted_group = [&](std::vector<uint32_t>& group) {
    std::sort(group.begin(), group.end(), [&](uint32_t x, uint32_t y) {
      const CGAL::Comparison_result c = CGAL::compare_xyz(pts[x], pts[y]);
      return c == CGAL::SMALLER || (c == CGAL::EQUAL && x < y);
    });
    for (size_t g = 1; g < group.size(); ++g)
      if (group[g] != group[g - 1] &&
          CGAL::compare_xyz(pts[group[g]], pts[group[g - 1]]) == CGAL::EQUAL)
        sets.unite(group[g], group[g - 1]);
  };
  constexpr size_t kMaxWide = 64;
  if (wide.size() > kMaxWide) {
    std::vector<uint32_t> all(ids.begin(), ids.end());
    sorted_group(all);
    std::vector<uint32_t> rep(pts.size());
    for (uint32_t x = 0; x < rep.size(); ++x) rep[x] = sets.find(x);
    return rep;
  }
  for (uint32_t w : wide) {
    const auto& aw = CGAL::approx(pts[w]);
    for (uint32_t id : ids) {
      if (id == w) continue;
      const auto& ap = CGAL::approx(pts[id]);
      bool meet = true;
      for (int a = 0; a < 3 && meet; ++a)
        meet = !(ap[a].sup() < aw[a].inf() || aw[a].sup() < ap[a].inf());
      if (meet && CGAL::compare_xyz(pts[w], pts[id]) == CGAL::EQUAL) sets.unite(w, id);
    }
  }
  // Boost's radix sort on the cell key (the pair order for ties): about twice std::sort here.
  boost::sort::spreadsort::integer_sort(
      cells.begin(), cells.end(),
      [](const std::pair<uint64_t, uint32_t>& x, unsigned offset) { return x.first >> offset; },
      [](const std::pair<uint64_t, uint32_t>& x, const std::pair<uint64_t, uint32_t>& y) {
        return x < y;
      });
  std::vector<uint32_t> group;
  for (size_t i = 0; i < cells.size();) {
    size_t j = i;
    group.clear();
    while (j < cells.size() && cells[j].first == cells[i].first) group.push_back(cells[j++].second);
    i = j;
    if (group.size() >= 2) sorted_group(group);
  }
  std::vector<uint32_t> rep(pts.size());
  for (uint32_t x = 0; x < rep.size(); ++x) rep[x] = sets.find(x);
  return rep;
}

}  // namespace

Arrangement build_arrangement(const Solid& solid, bool check_leaves, size_t grain,
                              EvaluatePhases& seconds, std::vector<uint8_t>& self) {
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  auto lap = [&t0](double& into) {
    const auto now = Clock::now();
    into = std::chrono::duration<double>(now - t0).count();
    t0 = now;
  };
  Arrangement arr;
  const std::vector<uint32_t> id = dedup_vertices(solid, arr.originals);
  // The input vertices as lazy points, made per chunk in parallel and moved into place (each
  // is an allocation).
  {
    constexpr size_t kChunk = 4096;
    const size_t n = arr.originals.size();
    std::vector<std::vector<Point>> made((n + kChunk - 1) / kChunk);
    parallel_for(n, kChunk, [&](size_t begin, size_t end) {
      std::vector<Point>& out = made[begin / kChunk];
      out.reserve(end - begin);
      for (size_t i = begin; i < end; ++i)
        out.emplace_back(arr.originals[i].x, arr.originals[i].y, arr.originals[i].z);
    });
    arr.points.reserve(n);
    for (std::vector<Point>& chunk : made)
      for (Point& p : chunk) arr.points.push_back(std::move(p));
  }
  std::vector<uint8_t> winding;
  arr.tris = leaf_tris(solid, id, arr.originals, grain, winding);
  const std::vector<Tri>& tris = arr.tris;
  const std::vector<Vec3>& pos = arr.originals;
  lap(seconds.triangulate);

  // Candidate pairs; with check_leaves the leaf self-intersection test rides the same grid pass.
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  if (check_leaves) {
    self = winding;
    pairs = candidate_pairs_and_self(tris, pos, self);
    lap(seconds.check);
  } else {
    self.clear();
    pairs = candidate_pairs(tris, pos);
  }
  arr.candidate_pairs = pairs.size();
  // ---- self-intersecting leaves (self_pairs.cpp): their own pairs join, in pair order.
  const bool any_self = std::find(self.begin(), self.end(), 1) != self.end();
  if (any_self) {
    const auto own = same_leaf_pairs(tris, pos, self);
    const size_t mid = pairs.size();
    pairs.insert(pairs.end(), own.begin(), own.end());
    std::inplace_merge(pairs.begin(), pairs.begin() + mid, pairs.end());
    arr.candidate_pairs = pairs.size();
  }
  // ----
  lap(seconds.pairs);
  arr.first_crossing = static_cast<uint32_t>(arr.points.size());
  std::vector<Hit> hits = intersect_pairs(tris, pos, pairs, arr.points, arr.crossings, grain);
  // ---- self-intersecting leaves: contacts at shared vertices / edges are no hits; tris that
  // overlap a coplanar tri of their own leaf are marked solo.
  if (any_self) {
    drop_shared(tris, pairs, arr.points, hits);
    arr.solo.assign(tris.size(), 0);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (tris[pairs[p].first].leaf == tris[pairs[p].second].leaf && !hits[p].empty() &&
          hits[p].ends[0].id == kNone)
        arr.solo[pairs[p].first] = arr.solo[pairs[p].second] = 1;
  }
  // ----
  lap(seconds.intersect);

  // Hits per tri (CSR, pair order).
  std::vector<uint32_t> start(tris.size() + 1, 0);
  for (size_t p = 0; p < pairs.size(); ++p)
    if (!hits[p].empty()) {
      ++arr.intersecting_pairs;
      ++start[pairs[p].first + 1];
      ++start[pairs[p].second + 1];
    }
  for (size_t t = 0; t < tris.size(); ++t) start[t + 1] += start[t];
  std::vector<TriHit> by_tri(start.back());
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (!hits[p].empty()) {
        by_tri[fill[pairs[p].first]++] = {&hits[p], true, pairs[p].second};
        by_tri[fill[pairs[p].second]++] = {&hits[p], false, pairs[p].first};
      }
  }
  std::vector<uint32_t> touched;
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (start[t + 1] > start[t]) touched.push_back(t);

  std::vector<Local> locals(touched.size());
  parallel_for(touched.size(), std::max<size_t>(1, grain / 8), [&](size_t begin, size_t end) {
    std::vector<TriHit> h;
    for (size_t x = begin; x < end; ++x) {
      const uint32_t t = touched[x];
      h.assign(by_tri.begin() + start[t], by_tri.begin() + start[t + 1]);
      locals[x] = split_tri(tris[t], h, arr, self);
    }
  });
  lap(seconds.split);

  // Value-only points get ids in touched-tri order; then equal values merge (deterministic).
  for (size_t x = 0; x < touched.size(); ++x) {
    Local& local = locals[x];
    size_t next = 0;
    for (uint32_t& q : local.ids)
      if (q == kNone) {
        q = static_cast<uint32_t>(arr.points.size());
        arr.points.push_back(std::move(local.points[next++]));
      }
  }
  std::vector<uint32_t> used;  // the ids the pieces use, increasing (a flag per point, no sort)
  {
    std::vector<uint8_t> flag(arr.points.size(), 0);
    for (const Local& local : locals)
      for (uint32_t q : local.ids) flag[q] = 1;
    for (uint32_t q = 0; q < flag.size(); ++q)
      if (flag[q]) used.push_back(q);
  }
  Bbox box;
  for (const Vec3& p : pos) box.add(p);
  const std::vector<uint32_t> rep = merge_equal(arr.points, used, box);

  size_t next_touched = 0;
  for (uint32_t t = 0; t < tris.size(); ++t) {
    if (next_touched < touched.size() && touched[next_touched] == t) {
      Local& local = locals[next_touched++];
      auto map = [&](uint32_t q) { return rep[local.ids[q]]; };
      for (const auto& lt : local.tris)
        arr.pieces.push_back({{map(lt[0]), map(lt[1]), map(lt[2])}, t});
      for (const auto& [x, y] : local.cuts) arr.cuts.push_back(edge_key(map(x), map(y)));
      local = Local{};
    } else {
      arr.pieces.push_back({tris[t].v, t});
    }
  }
  parallel_sort(arr.cuts);
  arr.cuts.erase(std::unique(arr.cuts.begin(), arr.cuts.end()), arr.cuts.end());
  lap(seconds.identify);
  return arr;
}

}  // namespace cover::boolean_detail
