// (A) of the octree builder (detail/builder.h): the triangles that meet the interior of each cell.

#include <vector>

#include "cover/covering/bvh_walk.h"
#include "cover/octree/detail/builder.h"
#include "cover/solid/parallel.h"

namespace cover::octree_build {

/// Appends every triangle whose box (the BVH's float bounds contain the exact ones) meets the
/// closed box (a superset of those that meet its interior).
void bvh_candidates(const Bvh& bvh, const Bbox& box, std::vector<uint32_t>& out) {
  walk(
      bvh,
      [&](const Bvh::Node& node) {
        for (int a = 0; a < 3; ++a)
          if (node.lo[a] > box.max[a] || node.hi[a] < box.min[a]) return false;
        return true;
      },
      [&](const Bvh::Tri&, uint32_t i) { out.push_back(i); });
}

/// (A) The triangles that meet the interior of each cell of [b0, b0 + m) at level d, one list
/// per cell (levels above the last, and the root; the last level runs last_level).
Lists Builder::meeting(int d, size_t b0, size_t m) const {
  std::vector<std::vector<uint32_t>> chunk_tris((m + kGrain - 1) / kGrain);
  LargeVector<uint32_t> count(m);
  parallel_for(m, kGrain, [&](size_t begin, size_t end) {
    std::vector<uint32_t>& out = chunk_tris[begin / kGrain];
    std::vector<uint32_t> candidates;
    std::array<std::vector<uint32_t>, 8> octant;
    const size_t siblings = d == 0 ? 1 : 8;
    for (size_t g0 = begin; g0 < end; g0 += siblings) {
      const size_t parent = (b0 + g0) / 8;
      if (d > 0) {
        // The parent's triangles against its 8 octants at once.
        const Lattice lattice = lattice_of(parent, d);
        for (auto& list : octant) list.clear();
        for (uint32_t t : parent_lists_[parent]) {
          const Bvh::Tri tri = bvh_.triangle(t);
          // A triangle whose box lies inside one octant's open box crosses that octant and
          // no other (no exact test): most triangles, above the last levels.
          if (const int o = inside_octant(tri, lattice.planes); o >= 0) {
            octant[o].push_back(t);
            continue;
          }
          const uint8_t crossed =
              detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, 0xFF);
          for (uint8_t c = crossed; c != 0; c &= static_cast<uint8_t>(c - 1))
            octant[std::countr_zero(c)].push_back(t);
        }
        for (int c = 0; c < 8; ++c) {
          out.insert(out.end(), octant[c].begin(), octant[c].end());
          count[g0 + c] = static_cast<uint32_t>(octant[c].size());
        }
        continue;
      }
      for (size_t i = g0; i < g0 + siblings; ++i) {
        const Bbox b = box(coord(d, b0 + i), d);
        candidates.clear();
        bvh_candidates(bvh_, b, candidates);
        const size_t before = out.size();
        const double planes[3][3] = {
            {b.min.x, b.max.x, b.max.x}, {b.min.y, b.max.y, b.max.y}, {b.min.z, b.max.z, b.max.z}};
        for (uint32_t t : candidates) {
          const Bvh::Tri tri = bvh_.triangle(t);
          if (inside_octant(tri, planes) == 0 ||
              detail::triangle_crosses_box(tri.a, tri.b, tri.c, b))
            out.push_back(t);
        }
        count[i] = static_cast<uint32_t>(out.size() - before);
      }
    }
  });
  Lists lists;
  lists.start.resize(m + 1, 0);
  for (size_t i = 0; i < m; ++i) lists.start[i + 1] = lists.start[i] + count[i];
  lists.tris.reserve(lists.start[m]);
  for (auto& c : chunk_tris) {
    lists.tris.insert(lists.tris.end(), c.begin(), c.end());
    std::vector<uint32_t>().swap(c);
  }
  return lists;
}

}  // namespace cover::octree_build
