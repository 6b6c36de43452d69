// Certified marching tetrahedra on an adaptive grid (polygonize.h has the route and the
// guarantees; the step numbers below are its).

#include "cover/polygonize/polygonize.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "cover/covering/box_states.h"
#include "cover/covering/classify.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

namespace cover {
namespace {

constexpr int64_t kMaxCellsPerSide = int64_t{1} << 20;
constexpr int kMaxBisections = 60;

/// Step 1: the grid, in cells of side h; point (I, J, K) (0 ≤ I ≤ n[0], ...) is at
/// ((lo[0] + I)·h, ...), exact: an integer below 2^53 times a power of two.
struct Grid {
  double h = 0;
  std::array<int64_t, 3> lo{}, n{};
  uint64_t key(int64_t i, int64_t j, int64_t k) const {
    return (static_cast<uint64_t>(i) * static_cast<uint64_t>(n[1] + 1) + static_cast<uint64_t>(j)) *
               static_cast<uint64_t>(n[2] + 1) +
           static_cast<uint64_t>(k);
  }
  std::array<int64_t, 3> index(uint64_t key) const {
    const auto nz = static_cast<uint64_t>(n[2] + 1), ny = static_cast<uint64_t>(n[1] + 1);
    return {static_cast<int64_t>(key / nz / ny), static_cast<int64_t>(key / nz % ny),
            static_cast<int64_t>(key % nz)};
  }
  double coord(int a, int64_t i) const { return static_cast<double>(lo[a] + i) * h; }
  Vec3 point(uint64_t key) const {
    const auto ix = index(key);
    return {coord(0, ix[0]), coord(1, ix[1]), coord(2, ix[2])};
  }
  bool on_border(uint64_t key) const {
    const auto ix = index(key);
    for (int a = 0; a < 3; ++a)
      if (ix[a] == 0 || ix[a] == n[a]) return true;
    return false;
  }
};

/// The largest power of two ≤ x (x > 0, finite).
double power_of_two_below(double x) {
  int e = 0;
  std::frexp(x, &e);  // x = m·2^e, m in [0.5, 1)
  return std::ldexp(1.0, e - 1);
}

Grid make_grid(const Bbox& box, const PolygonizeOptions& o) {
  Grid g;
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, box.max[a] - box.min[a]);
  if (!(extent > 0) || !std::isfinite(extent)) extent = 1;
  g.h =
      o.cell_size > 0 ? power_of_two_below(o.cell_size) : power_of_two_below(extent / o.resolution);
  if (g.h < std::ldexp(1.0, -900))
    throw InputError("polygonize: the cell size " + std::to_string(g.h) +
                     " is too small for exact grid points");
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(box.min[a] / g.h) - 1, hi = std::ceil(box.max[a] / g.h) + 1;
    if (!(hi - lo <= static_cast<double>(kMaxCellsPerSide)) || std::abs(lo) > 0x1p50 ||
        std::abs(hi) > 0x1p50)
      throw InputError("polygonize: more than " + std::to_string(kMaxCellsPerSide) +
                       " cells per side; use a larger cell size or a smaller resolution");
    g.lo[a] = static_cast<int64_t>(lo);
    g.n[a] = static_cast<int64_t>(hi - lo);
  }
  return g;
}

struct Block {
  std::array<int64_t, 3> at;  // lowest cell
};

/// Step 2: the cells of side h the box test cannot decide, as sorted cell keys (cell (i, j, k)
/// by its lowest corner's point key). A block inside the solid that touches the grid's border is
/// descended too: its border points count as outside (step 3).
std::vector<uint64_t> undecided_cells(const Prepared& prepared, const Grid& g,
                                      const PolygonizeOptions& o) {
  int64_t side = 1;
  while (side < std::max({g.n[0], g.n[1], g.n[2]})) side *= 2;
  std::vector<Block> level{Block{{0, 0, 0}}}, next;
  std::vector<Bbox> boxes;
  std::vector<uint64_t> cells;
  for (; !level.empty(); side /= 2) {
    boxes.resize(level.size());
    for (size_t b = 0; b < level.size(); ++b) {
      const auto& at = level[b].at;
      auto upper = [&](int a) { return g.coord(a, std::min(at[a] + side, g.n[a])); };
      boxes[b].min = {g.coord(0, at[0]), g.coord(1, at[1]), g.coord(2, at[2])};
      boxes[b].max = {upper(0), upper(1), upper(2)};
    }
    const std::vector<uint8_t> state = box_states(prepared, boxes);
    next.clear();
    for (size_t b = 0; b < level.size(); ++b) {
      const Block& blk = level[b];
      bool border = false;
      for (int a = 0; a < 3; ++a) border |= blk.at[a] == 0 || blk.at[a] + side >= g.n[a];
      if (state[b] == kBoxOutside || (state[b] == kBoxInside && !border)) continue;
      if (side == 1) {
        cells.push_back(g.key(blk.at[0], blk.at[1], blk.at[2]));
        continue;
      }
      const int64_t half = side / 2;
      for (int c = 0; c < 8; ++c) {
        const Block child{{blk.at[0] + (c & 1) * half, blk.at[1] + ((c >> 1) & 1) * half,
                           blk.at[2] + ((c >> 2) & 1) * half}};
        if (child.at[0] < g.n[0] && child.at[1] < g.n[1] && child.at[2] < g.n[2])
          next.push_back(child);
      }
    }
    // Per block of the next level about 80 bytes; per cell of side h about 400 (its corners,
    // tetrahedra, crossings and triangles).
    check_memory(
        80.0 * static_cast<double>(next.size()) + 400.0 * static_cast<double>(cells.size()),
        o.max_memory_bytes,
        "polygonize: " + std::to_string(next.size()) + " cells at side " +
            std::to_string(side / 2) + "h");
    level.swap(next);
  }
  parallel_sort(cells);
  return cells;
}

/// One triangle before its vertices exist: three crossing edges (point-index pairs) in some
/// order, and the corner whose side fixes the orientation (inside: the normal points away).
struct PendingTri {
  std::array<uint64_t, 3> edge;
  uint32_t ref = 0;
  bool ref_inside = true;
};

uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t{a} << 32) | b : (uint64_t{b} << 32) | a;
}

bool not_outside(PointClass c) { return c != PointClass::kOutside; }
bool on_boundary(PointClass c) {
  return c == PointClass::kFace || c == PointClass::kEdge || c == PointClass::kVertex;
}

}  // namespace

PolygonizeResult polygonize(const Prepared& prepared, const Bbox& box, const PolygonizeOptions& o) {
  if (o.cell_size <= 0 && (o.resolution < 2 || o.resolution > 65536))
    throw InputError("polygonize: resolution: expected 2 to 65536, got " +
                     std::to_string(o.resolution));
  if (!(o.cell_size >= 0) || !std::isfinite(o.cell_size))
    throw InputError("polygonize: cell size: expected a finite number ≥ 0");
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance))
    throw InputError("polygonize: tolerance: expected a finite number ≥ 0");
  PolygonizeResult r;
  if (box.empty() || prepared.solid().tree.nodes.empty()) return r;
  const Grid g = make_grid(box, o);
  r.cell_size = g.h;

  // Step 2.
  const std::vector<uint64_t> cells = undecided_cells(prepared, g, o);
  r.cells = cells.size();
  if (cells.empty()) return r;

  // Step 3: the corners, classified.
  std::vector<uint64_t> keys(cells.size() * 8);
  parallel_for(cells.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) {
      const auto ix = g.index(cells[c]);
      for (int k = 0; k < 8; ++k)
        keys[8 * c + k] = g.key(ix[0] + (k & 1), ix[1] + ((k >> 1) & 1), ix[2] + ((k >> 2) & 1));
    }
  });
  parallel_sort(keys);
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<Vec3> points(keys.size());
  parallel_for(keys.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) points[i] = g.point(keys[i]);
  });
  Classification corner_class = classify_counted(prepared, points);
  r.grid_points = points.size();
  r.uncertain += corner_class.uncertain;
  std::vector<uint8_t> inside(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    inside[i] = not_outside(corner_class.classes[i]);
    if (inside[i] && g.on_border(keys[i])) {
      inside[i] = 0;
      ++r.clipped;
    }
  }
  corner_class = {};
  auto point_index = [&](uint64_t key) {
    return static_cast<uint32_t>(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
  };

  // Step 4: tetrahedra to pending triangles, per chunk of cells, concatenated in cell order.
  constexpr size_t kGrain = 1024;
  const size_t chunks = (cells.size() + kGrain - 1) / kGrain;
  std::vector<std::vector<PendingTri>> pending(chunks);
  static constexpr int kPerm[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  parallel_for(cells.size(), kGrain, [&](size_t begin, size_t end) {
    std::vector<PendingTri>& out = pending[begin / kGrain];
    for (size_t c = begin; c < end; ++c) {
      const auto ix = g.index(cells[c]);
      uint32_t corner[8];
      for (int k = 0; k < 8; ++k)
        corner[k] =
            point_index(g.key(ix[0] + (k & 1), ix[1] + ((k >> 1) & 1), ix[2] + ((k >> 2) & 1)));
      bool any_in = false, any_out = false;
      for (uint32_t p : corner) (inside[p] ? any_in : any_out) = true;
      if (!(any_in && any_out)) continue;
      for (const auto& perm : kPerm) {
        const int first = 1 << perm[0];
        const uint32_t t[4] = {corner[0], corner[first], corner[first | (1 << perm[1])], corner[7]};
        int in_count = 0;
        for (uint32_t p : t) in_count += inside[p];
        if (in_count == 0 || in_count == 4) continue;
        if (in_count == 1 || in_count == 3) {
          const bool odd_label = in_count == 1;  // the lone corner is inside when one is
          int v = 0;
          while (static_cast<bool>(inside[t[v]]) != odd_label) ++v;
          PendingTri tri;
          for (int k = 1, e = 0; k < 4; ++k) tri.edge[e++] = edge_key(t[v], t[(v + k) % 4]);
          tri.ref = t[v];
          tri.ref_inside = odd_label;
          out.push_back(tri);
        } else {
          uint32_t in[2], ou[2];
          for (int k = 0, a = 0, b = 0; k < 4; ++k) (inside[t[k]] ? in[a++] : ou[b++]) = t[k];
          // Quad on edges (a,c), (a,d), (b,d), (b,c); split along (a,c)–(b,d), each half with
          // two edges from one inside corner.
          out.push_back({{edge_key(in[0], ou[0]), edge_key(in[0], ou[1]), edge_key(in[1], ou[1])},
                         in[0],
                         true});
          out.push_back({{edge_key(in[0], ou[0]), edge_key(in[1], ou[1]), edge_key(in[1], ou[0])},
                         in[1],
                         true});
        }
      }
    }
  });
  size_t tri_count = 0;
  for (const auto& p : pending) tri_count += p.size();
  std::vector<uint64_t> edges;
  edges.reserve(tri_count * 3 / 2 + 1);
  for (const auto& p : pending)
    for (const PendingTri& t : p) edges.insert(edges.end(), t.edge.begin(), t.edge.end());
  parallel_sort(edges);
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // Step 5: certified bisection on every crossing edge, all edges one round at a time. The
  // midpoints stay exact while the lattice of the last round fits 52 bits.
  double max_index = 0;
  for (int a = 0; a < 3; ++a)
    max_index = std::max({max_index, std::abs(static_cast<double>(g.lo[a])),
                          std::abs(static_cast<double>(g.lo[a] + g.n[a]))});
  const int exact_rounds = std::max(0, 52 - static_cast<int>(std::ceil(std::log2(max_index + 2))));
  const double longest = g.h * std::sqrt(3.0);
  const double wanted = o.tolerance > 0 ? o.tolerance : g.h / 1024;
  int rounds = 0;
  while (rounds < kMaxBisections && rounds < exact_rounds &&
         std::ldexp(longest, -(rounds + 1)) > wanted)
    ++rounds;
  std::vector<Vec3> lo_end(edges.size()), hi_end(edges.size());  // inside, outside
  std::vector<uint8_t> exact(edges.size(), 0);
  for (size_t e = 0; e < edges.size(); ++e) {
    const auto a = static_cast<uint32_t>(edges[e] >> 32), b = static_cast<uint32_t>(edges[e]);
    lo_end[e] = points[inside[a] ? a : b];
    hi_end[e] = points[inside[a] ? b : a];
  }
  std::vector<uint32_t> active(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) active[e] = static_cast<uint32_t>(e);
  std::vector<Vec3> mids;
  for (int round = 0; round < rounds && !active.empty(); ++round) {
    mids.resize(active.size());
    for (size_t i = 0; i < active.size(); ++i)
      mids[i] = 0.5 * (lo_end[active[i]] + hi_end[active[i]]);
    const Classification mc = classify_counted(prepared, mids);
    r.bisections += mids.size();
    r.uncertain += mc.uncertain;
    size_t kept = 0;
    for (size_t i = 0; i < active.size(); ++i) {
      const uint32_t e = active[i];
      if (on_boundary(mc.classes[i])) {
        lo_end[e] = hi_end[e] = mids[i];
        exact[e] = 1;
        continue;
      }
      (not_outside(mc.classes[i]) ? lo_end[e] : hi_end[e]) = mids[i];
      active[kept++] = e;
    }
    active.resize(kept);
  }
  r.mesh.vertices.resize(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    r.mesh.vertices[e] = exact[e] ? lo_end[e] : 0.5 * (lo_end[e] + hi_end[e]);
    if (!exact[e]) {
      const Vec3 d = hi_end[e] - lo_end[e];
      // Half the final interval, rounded up (the differences are exact; the square root and
      // the sum carry a few ulps).
      r.tolerance =
          std::max(r.tolerance, 0.5 * std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) * (1 + 0x1p-48));
    }
  }

  // Triangles, oriented by the exact orient3d against their reference corner.
  r.mesh.face_vertices.resize(3 * tri_count);
  r.mesh.face_start.resize(tri_count + 1);
  std::vector<size_t> offset(chunks + 1, 0);
  for (size_t c = 0; c < chunks; ++c) offset[c + 1] = offset[c] + pending[c].size();
  parallel_for(chunks, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c)
      for (size_t i = 0; i < pending[c].size(); ++i) {
        const PendingTri& t = pending[c][i];
        uint32_t v[3];
        for (int k = 0; k < 3; ++k)
          v[k] = static_cast<uint32_t>(std::lower_bound(edges.begin(), edges.end(), t.edge[k]) -
                                       edges.begin());
        const int side = orient3d(r.mesh.vertices[v[0]], r.mesh.vertices[v[1]],
                                  r.mesh.vertices[v[2]], points[t.ref]);
        if ((side > 0) == t.ref_inside) std::swap(v[1], v[2]);
        const size_t f = offset[c] + i;
        for (int k = 0; k < 3; ++k) r.mesh.face_vertices[3 * f + k] = v[k];
        r.mesh.face_start[f + 1] = static_cast<uint32_t>(3 * (f + 1));
      }
  });
  return r;
}

}  // namespace cover
