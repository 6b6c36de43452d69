// (B) of the octree builder (detail/builder.h): the points each cell's occupancy is classified at,
// grouped by their sides of the cell's planes and shared between cells, sibling sets and the
// sets under one grandparent; the last level's meeting test and grouping in one pass.

#include <cstring>
#include <vector>

#include "cover/octree/detail/builder.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

namespace cover::octree_build {

/// Groups the sub-points of `grid` (all in `box`) by their sides of the planes of `tris`: equal
/// side vectors without a zero share a group; a point on some plane gets a group of its own, and
/// so does every point when there are more than kGroupMax planes. Fills s.first and s.weight.
void group_by_sides(const Bvh& bvh, std::span<const uint32_t> tris, const Bbox& box,
                    const SubGrid& grid, Scratch& s) {
  const size_t n = grid.size(), k = tris.size();
  s.first.clear();
  s.weight.clear();
  if (k > kGroupMax) {
    for (size_t i = 0; i < n; ++i) s.first.push_back(static_cast<uint32_t>(i));
    s.weight.assign(n, 1);
    return;
  }
  s.sides.resize(n * k);
  for (size_t j = 0; j < k; ++j) {
    const Bvh::Tri tri = bvh.triangle(tris[j]);
    detail::PlaneSide(tri.a, tri.b, tri.c, box)
        .grid_signs(grid.xs, grid.ys, grid.zs, grid.n, s.sides.data() + j, k);
  }
  s.keys.clear();
  for (size_t i = 0; i < n; ++i) {
    const int8_t* side = s.sides.data() + i * k;
    bool on_plane = false;
    uint64_t key = 0;  // base 3: exact up to kExactKey planes, a hash beyond
    for (size_t j = 0; j < k; ++j) {
      on_plane |= side[j] == 0;
      key = 3 * key + static_cast<uint64_t>(side[j] + 1);
    }
    uint32_t g = static_cast<uint32_t>(s.first.size());
    if (!on_plane)
      for (uint32_t q = 0; q < s.first.size(); ++q)
        if (s.keys[q] == key &&
            (k <= kExactKey ||
             std::memcmp(side, s.sides.data() + size_t{s.first[q]} * k, k) == 0)) {
          g = q;
          break;
        }
    if (g == s.first.size()) {
      s.first.push_back(static_cast<uint32_t>(i));
      s.weight.push_back(0);
      s.keys.push_back(key);
    }
    ++s.weight[g];
  }
}

Crossing segment_crossing(const Vec3& r, const Vec3& q, const Bvh::Tri& tri) {
  int o[3];
  detail::edge_orientations(r, q, tri.a, tri.b, tri.c, o);
  const int o0 = o[0], o1 = o[1], o2 = o[2];
  const bool some_neg = o0 < 0 || o1 < 0 || o2<0, some_pos = o0> 0 || o1 > 0 || o2 > 0;
  if (some_neg && some_pos) return Crossing::kPasses;
  return o0 == 0 || o1 == 0 || o2 == 0 ? Crossing::kThroughEdge : Crossing::kCrosses;
}

/// True when some covering triangle passes through the centre of crossed cell `parent` (by
/// rank) of the previous level: its list holds every triangle through its interior.
bool Builder::centre_on_surface(size_t parent, int d, std::vector<uint32_t>& candidates) const {
  double x[3];  // the children's common corner: the same grid planes as their boxes
  for (int a = 0; a < 3; ++a)
    x[a] = plane(a, (2 * uint64_t{parents_[parent][a]} + 1) << (depth_ - d));
  Bbox point;
  point.min = point.max = {x[0], x[1], x[2]};
  std::span<const uint32_t> tris = parent_lists_[parent];
  if (tris.size() > kInheritMax) {
    candidates.clear();
    bvh_candidates(bvh_, point, candidates);
    tris = candidates;
  }
  const Vec3 p{x[0], x[1], x[2]};
  for (uint32_t t : tris) {
    const Bvh::Tri tri = bvh_.triangle(t);
    // Off the triangle's plane (the common case, one filtered orient3d) it is off the triangle.
    if (orient3d(tri.a, tri.b, tri.c, p) == 0 &&
        detail::triangle_meets_box(tri.a, tri.b, tri.c, point))
      return true;
  }
  return false;
}

/// The anchor for the sibling set of `parent` (by rank) at level d: `anchor`, reset when the
/// set's grandparent differs from the anchor's; nullptr without grandparents (d < 2), with
/// open leaves (no windings) or when T_G holds more than kAnchorMax triangles (a ray is
/// cheaper than that many plane signs per point).
Anchor* Builder::anchor_of(size_t parent, int d, Anchor& anchor) const {
  if (d < 2 || open_) return nullptr;
  const size_t grand = grand_rank_[parent];
  if (grand_lists_[grand].size() > kAnchorMax) return nullptr;
  anchor.parent = parent;
  anchor.level = d;
  if (grand != anchor.grand) {
    anchor.grand = grand;
    anchor.valid = false;
    anchor.tris = grand_lists_[grand];
    anchor.planes.clear();
    anchor.planes_ready = false;
  }
  return &anchor;
}

/// Makes reference `point` (Requests::refs[ref], in the interior of a cell of the anchor's
/// grandparent) the anchor, when it lies strictly off every plane of T_G.
void Builder::set_anchor(Anchor& anchor, const Vec3& point, uint32_t ref) const {
  if (!anchor.planes_ready) {
    anchor.planes_ready = true;
    const Coord& p = parents_[anchor.parent];  // a child of G
    const Bbox g = box({p[0] / 2, p[1] / 2, p[2] / 2}, anchor.level - 2);
    for (uint32_t t : anchor.tris) {
      const Bvh::Tri tri = bvh_.triangle(t);
      anchor.planes.emplace_back(tri.a, tri.b, tri.c, g);
    }
  }
  anchor.sides.clear();
  for (const detail::PlaneSide& plane : anchor.planes) {
    const int side = plane.sign(point);
    if (side == 0) return;
    anchor.sides.push_back(static_cast<int8_t>(side));
  }
  anchor.point = point;
  anchor.ref = ref;
  anchor.valid = true;
}

/// Appends to `deltas` the signed crossings of the segment from the anchor to r (a reference
/// in the interior of another cell of the anchor's grandparent) with T_G, as sibling_masks
/// does within a set; false (deltas partly written) when r lies on a plane of T_G or the
/// segment passes through a triangle's edge or vertex.
bool Builder::anchor_deltas(const Anchor& anchor, const Vec3& r, std::vector<Delta>& deltas) const {
  for (size_t j = 0; j < anchor.planes.size(); ++j) {
    const int side = anchor.planes[j].sign(r);
    if (side == 0) return false;
    if (side == anchor.sides[j]) continue;
    const Bvh::Tri tri = bvh_.triangle(anchor.tris[j]);
    const Crossing x = segment_crossing(anchor.point, r, tri);
    if (x == Crossing::kThroughEdge) return false;
    if (x == Crossing::kCrosses) deltas.push_back({tri.leaf, anchor.sides[j] > 0 ? 1 : -1});
  }
  return true;
}

/// sibling_representatives for samples³ ≤ 64, on bit masks: the side classes are found by
/// splitting the set of points on no plane by each plane's positive side (a class is an
/// intersection of sides), each class's weight in a cell is a popcount, and its
/// representative its first point; the points on some plane are classified one by one.
void Builder::sibling_masks(size_t g0, std::span<const uint32_t> tris, const Lattice& lattice,
                            uint8_t crossed, Anchor* anchor, Scratch& s, Requests& out) const {
  std::vector<Vec3>& points = out.points;
  std::vector<Entry>& entries = out.entries;
  using Set = std::array<uint64_t, 9>;
  const size_t k = tris.size();
  const int n = samples_;
  const int count = n * n * n;
  const uint64_t all = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
  Set full{}, on{};
  for (int c = 0; c < 8; ++c) {
    if (crossed >> c & 1)
      full[c] = all;
    else
      full[8] |= uint64_t{1} << c;
  }
  // Sub-point coordinates and centres per half of each axis: the values SubGrid::set and
  // centre() give for the cells' boxes (the same grid planes).
  double sub[3][2][kMaxSamples], mid[3][2];
  const double inv_n = 1.0 / n;
  for (int a = 0; a < 3; ++a)
    for (int h = 0; h < 2; ++h) {
      const double lo = lattice.planes[a][h], hi = lattice.planes[a][h + 1];
      // SubGrid::set's step (hi − lo)/n; for n a power of two the product by 1/n is the same
      // double without a division (6 per set).
      const double step = (n & (n - 1)) == 0 ? (hi - lo) * inv_n : (hi - lo) / n;
      for (int i = 0; i < n; ++i) sub[a][h][i] = lo + (i + 0.5) * step;
      mid[a][h] = lo + 0.5 * (hi - lo);
    }
  const double* const halves[3][2] = {
      {sub[0][0], sub[0][1]}, {sub[1][0], sub[1][1]}, {sub[2][0], sub[2][1]}};
  s.pos.resize(k);
  constexpr uint32_t kAll27 = (uint32_t{1} << 27) - 1;
  for (size_t j = 0; j < k; ++j) {
    const detail::PlaneSide& plane = s.planes[j];
    // A cell whose 8 corners lie strictly on one side has all its points there (the sign of
    // orient3d is affine in the point): no per-point signs.
    const uint32_t some_nonpos = detail::spread27(~s.lattice_pos[j] & kAll27);
    const uint32_t some_nonneg = detail::spread27(~s.lattice_neg[j] & kAll27);
    Set& pos = s.pos[j];
    pos.fill(0);
    uint8_t grid = 0;  // the crossed cells the plane passes through: per-point signs
    for (int c = 0; c < 8; ++c) {
      const int corner = detail::kOctantCorner[c];
      if (!(some_nonpos >> corner & 1)) {
        pos[c] = full[c];
        pos[8] |= full[8] & (uint64_t{1} << c);
        continue;
      }
      if (!(some_nonneg >> corner & 1)) continue;
      if (full[c] != 0) {
        grid |= static_cast<uint8_t>(1u << c);
      } else {
        const int side = plane.sign({mid[0][c & 1], mid[1][(c >> 1) & 1], mid[2][c >> 2]});
        pos[8] |= uint64_t{side > 0} << c;
        on[8] |= uint64_t{side == 0} << c;
      }
    }
    if (grid != 0) {
      uint64_t neg[8];
      plane.cell_masks(halves[0], halves[1], halves[2], n, grid, pos.data(), neg);
      for (uint32_t m = grid; m != 0; m &= m - 1) {
        const int c = std::countr_zero(m);
        on[c] |= full[c] & ~(pos[c] | neg[c]);
      }
    }
  }
  // Side classes of the points on no plane: split by every plane's positive side.
  s.sets.clear();
  Set start;
  for (int w = 0; w < 9; ++w) start[w] = full[w] & ~on[w];
  s.sets.push_back(start);
  for (size_t j = 0; j < k; ++j) {
    s.split.clear();
    for (const Set& set : s.sets) {
      Set in, out;
      uint64_t any_in = 0, any_out = 0;
      for (int w = 0; w < 9; ++w) {
        in[w] = set[w] & s.pos[j][w];
        out[w] = set[w] & ~s.pos[j][w];
        any_in |= in[w];
        any_out |= out[w];
      }
      if (any_in) s.split.push_back(in);
      if (any_out) s.split.push_back(out);
    }
    std::swap(s.sets, s.split);
  }
  const auto point = [&](int w, int bit) {
    if (w == 8) return Vec3{mid[0][bit & 1], mid[1][(bit >> 1) & 1], mid[2][bit >> 2]};
    const std::array<uint8_t, 3>& ijk = sub_index_[bit];
    return Vec3{sub[0][w & 1][ijk[0]], sub[1][(w >> 1) & 1][ijk[1]], sub[2][w >> 2][ijk[2]]};
  };
  // A class's representative: its first point, (word, bit).
  const auto first = [](const Set& set) {
    int w = 0;
    while (set[w] == 0) ++w;
    return std::pair<int, int>{w, std::countr_zero(set[w])};
  };
  const auto add_entries = [&](const Set& set, uint32_t rep) {
    for (int c = 0; c < 8; ++c)
      if (set[c] != 0)
        entries.push_back(
            {static_cast<uint32_t>(g0 + c), rep, static_cast<uint32_t>(popcount(set[c]))});
    for (uint64_t m = set[8]; m != 0; m &= m - 1)
      entries.push_back({static_cast<uint32_t>(g0 + std::countr_zero(m)), rep, 1});
  };
  const auto add = [&](const Set& set) {
    const auto [w, bit] = first(set);
    add_entries(set, static_cast<uint32_t>(points.size()));
    points.push_back(point(w, bit));
  };
  // The side classes. With closed leaves, the first class's representative r is the set's
  // reference, classified by its leaves' windings; another class's representative q differs
  // from r by the signed crossings of the segment rq with the triangles of T_P: both points
  // lie in the parent's interior on no plane of T_P, so the segment meets only T_P's
  // triangles, and a triangle whose plane separates r and q is crossed where the three
  // orient3d(r, q, edge) agree strictly (crossing from its outer side, the side its normal
  // points to, adds 1 to its leaf's winding). A segment through a triangle's edge or vertex
  // (some orient3d zero, none disagreeing) leaves q to classify().
  // With an anchor (last_level), r itself may be derived from the anchor's windings: the
  // deltas base_begin .. + base_count, which every other class of the set then starts with.
  int ref_w = -1, ref_bit = 0;
  Vec3 r;
  uint32_t ref = 0, base_begin = 0, base_count = 0;
  for (const Set& set : s.sets) {
    if (!std::any_of(set.begin(), set.end(), [](uint64_t x) { return x != 0; })) continue;
    if (open_) {
      add(set);
      continue;
    }
    const auto [w, bit] = first(set);
    const Vec3 q = point(w, bit);
    const uint32_t delta_begin = static_cast<uint32_t>(out.deltas.size());
    if (ref_w < 0) {
      ref_w = w;
      ref_bit = bit;
      r = q;
      if (anchor != nullptr && anchor->valid && anchor_deltas(*anchor, r, out.deltas)) {
        ref = anchor->ref;
        base_begin = delta_begin;
        base_count = static_cast<uint32_t>(out.deltas.size()) - delta_begin;
      } else {
        out.deltas.resize(delta_begin);
        ref = static_cast<uint32_t>(out.refs.size());
        out.refs.push_back(r);
        if (anchor != nullptr && !anchor->valid) set_anchor(*anchor, r, ref);
      }
    } else {
      for (uint32_t i = 0; i < base_count; ++i) out.deltas.push_back(out.deltas[base_begin + i]);
      bool through_edge = false;
      for (size_t j = 0; j < k && !through_edge; ++j) {
        const bool r_pos = s.pos[j][ref_w] >> ref_bit & 1, q_pos = s.pos[j][w] >> bit & 1;
        if (r_pos == q_pos) continue;
        const Bvh::Tri tri = bvh_.triangle(tris[j]);
        const Crossing x = segment_crossing(r, q, tri);
        if (x == Crossing::kThroughEdge) through_edge = true;
        if (x == Crossing::kCrosses) out.deltas.push_back({tri.leaf, r_pos ? 1 : -1});
      }
      if (through_edge) {
        out.deltas.resize(delta_begin);
        add(set);
        continue;
      }
    }
    add_entries(set, static_cast<uint32_t>(out.derived.size()) | Entry::kDerived);
    out.derived.push_back(
        {q, ref, delta_begin, static_cast<uint32_t>(out.deltas.size()) - delta_begin});
  }
  // Points on some plane (they may be on a surface): one by one.
  for (int w = 0; w < 9; ++w)
    for (uint64_t m = on[w]; m != 0; m &= m - 1) {
      Set one{};
      one[w] = m & (~m + 1);
      add(one);
    }
}

/// (B) at the last level, for the sibling set g0 .. g0 + 7 (cells of the block) whose parent's
/// list T_P is short (s.planes: its planes over the parent's box; `crossed`: bit c for each
/// crossed cell g0 + c): the sub-points of its partial cells and the centres of its uncrossed
/// cells, grouped by their sides of the planes of T_P. T_P holds every triangle that meets
/// the parent's interior, so a side class is a convex part of it no surface meets, where
/// membership is constant: one point per class is classified for all the set's cells, and a
/// point ON a plane alone (it may be on a surface).
void Builder::sibling_representatives(int d, size_t b0, size_t g0, uint8_t crossed, Scratch& s,
                                      SubGrid& subs, std::vector<Vec3>& points,
                                      std::vector<Entry>& entries) const {
  const size_t k = s.planes.size();
  s.keys.clear();  // per group: its side vector in base 3 (exact: k ≤ kExactKey), or
  s.rep.clear();   // kOnPlane for a point on some plane, never matched
  s.entry.clear();
  constexpr uint64_t kOnPlane = UINT64_MAX;
  const size_t sub_count = size_t(samples_) * samples_ * samples_;
  s.sides.resize(sub_count * k);
  std::vector<uint64_t>& key = s.point_keys;
  for (uint32_t cell = static_cast<uint32_t>(g0); cell < g0 + 8; ++cell) {
    const Bbox b = box(coord(d, b0 + cell), d);
    const bool partial = crossed >> (cell - g0) & 1;
    Vec3 c;
    size_t count = 1;
    if (partial) {
      subs.set(b, samples_);
      count = sub_count;
      for (size_t j = 0; j < k; ++j)
        s.planes[j].grid_signs(subs.xs, subs.ys, subs.zs, subs.n, s.sides.data() + j * count, 1);
    } else {
      c = centre(b);
      for (size_t j = 0; j < k; ++j) s.sides[j] = static_cast<int8_t>(s.planes[j].sign(c));
    }
    key.assign(count, 0);
    for (size_t j = 0; j < k; ++j) {
      const int8_t* side = s.sides.data() + j * count;
      for (size_t p = 0; p < count; ++p)
        key[p] =
            side[p] == 0 ? kOnPlane : (key[p] == kOnPlane ? kOnPlane : 3 * key[p] + (side[p] + 1));
    }
    // Runs of equal keys (neighbouring sub-points) skip the search; each group's weight in
    // this cell is counted in s.entry (reset below), its first touch listed in s.last_cell.
    s.last_cell.clear();  // the groups this cell touches, in order of first touch
    uint32_t g = UINT32_MAX;
    uint64_t last = kOnPlane;
    for (size_t p = 0; p < count; ++p) {
      const uint64_t kp = key[p];
      if (kp == kOnPlane || kp != last) {
        g = static_cast<uint32_t>(s.keys.size());
        if (kp != kOnPlane)
          for (uint32_t q = 0; q < s.keys.size(); ++q)
            if (s.keys[q] == kp) {
              g = q;
              break;
            }
        if (g == s.keys.size()) {
          s.keys.push_back(kp);
          s.rep.push_back(static_cast<uint32_t>(points.size()));
          points.push_back(partial ? subs.point(p) : c);
          s.entry.push_back(0);
        }
        last = kp;
      }
      if (s.entry[g]++ == 0) s.last_cell.push_back(g);
    }
    for (uint32_t q : s.last_cell) {
      entries.push_back({cell, s.rep[q], s.entry[q]});
      s.entry[q] = 0;
    }
  }
}

/// (B) The points to classify for the sibling set g0 .. g0 + siblings − 1 of level d (cells
/// of the block starting at b0; cell i's triangles list(i)): one centre for its uncrossed
/// cells (one per cell when the parent's centre is on a surface) and, at the last level, one
/// sub-point per side class of each partial cell. With an anchor (anchor_of) the centres are
/// derived from its windings, or become references (leaf_windings): an uncrossed cell's
/// centre is on no surface.
template <typename CellList>
void Builder::cells_representatives(int d, size_t b0, size_t g0, size_t siblings, CellList list,
                                    Scratch& s, SubGrid& subs, std::vector<uint32_t>& candidates,
                                    Anchor* anchor, Requests& out) const {
  std::vector<Vec3>& points = out.points;
  std::vector<Entry>& entries = out.entries;
  size_t uncrossed = 0;
  for (size_t i = g0; i < g0 + siblings; ++i) uncrossed += list(i).empty();
  const bool shared = uncrossed > 1 && !open_ && !centre_on_surface((b0 + g0) / 8, d, candidates);
  // An uncrossed cell's centre c: an entry's `rep`.
  const auto request = [&](const Vec3& c) {
    if (anchor == nullptr) {
      points.push_back(c);
      return static_cast<uint32_t>(points.size() - 1);
    }
    const uint32_t delta_begin = static_cast<uint32_t>(out.deltas.size());
    uint32_t ref = 0;
    if (anchor->valid && anchor_deltas(*anchor, c, out.deltas)) {
      ref = anchor->ref;
    } else {
      out.deltas.resize(delta_begin);
      ref = static_cast<uint32_t>(out.refs.size());
      out.refs.push_back(c);
      if (!anchor->valid) set_anchor(*anchor, c, ref);
    }
    out.derived.push_back(
        {c, ref, delta_begin, static_cast<uint32_t>(out.deltas.size()) - delta_begin});
    return static_cast<uint32_t>(out.derived.size() - 1) | Entry::kDerived;
  };
  uint32_t rep = UINT32_MAX;
  for (size_t i = g0; i < g0 + siblings; ++i) {
    if (!list(i).empty()) continue;
    if (rep == UINT32_MAX || !shared) rep = request(centre(box(coord(d, b0 + i), d)));
    entries.push_back({static_cast<uint32_t>(i), rep, 1});
  }
  if (d < depth_) return;
  for (size_t i = g0; i < g0 + siblings; ++i) {
    if (list(i).empty()) continue;
    const Bbox b = box(coord(d, b0 + i), d);
    subs.set(b, samples_);
    group_by_sides(bvh_, list(i), b, subs, s);
    const uint32_t base = static_cast<uint32_t>(points.size());
    for (uint32_t g = 0; g < s.first.size(); ++g) {
      points.push_back(subs.point(s.first[g]));
      entries.push_back({static_cast<uint32_t>(i), base + g, s.weight[g]});
    }
  }
}

/// (B) The points to classify for the cells [b0, b0 + m) of level d (below the last level,
/// or the root), per chunk: cells_representatives per sibling set.
void Builder::representatives(int d, size_t b0, size_t m, const Lists& lists,
                              std::vector<Requests>& requests) const {
  parallel_for(m, kGrain, [&](size_t begin, size_t end) {
    Requests& out = requests[begin / kGrain];
    Scratch s;
    SubGrid subs;
    std::vector<uint32_t> candidates;
    Anchor anchor;
    const size_t siblings = d == 0 ? 1 : 8;
    for (size_t g0 = begin; g0 < end; g0 += siblings)
      cells_representatives(
          d, b0, g0, siblings, [&](size_t i) { return lists[i]; }, s, subs, candidates,
          d == 0 ? nullptr : anchor_of((b0 + g0) / 8, d, anchor), out);
  });
}

/// (A) and (B) at the last level D ≥ 1, per sibling set of the cells [b0, b0 + m), in one
/// pass: which cells a triangle of the parent's list T_P crosses (bit c of crossed[set] for
/// cell c of the set), and the points to classify. A short T_P (at most kSiblingMax) needs
/// only one witness triangle per cell and shares each triangle's plane signs between the
/// octant tests and the side classes (sibling_masks); a longer one gets full per-cell lists
/// (group_by_sides).
void Builder::last_level(size_t b0, size_t m, std::vector<Requests>& requests,
                         std::vector<uint8_t>& crossed) const {
  const int d = depth_;
  parallel_for(m, kGrain, [&](size_t begin, size_t end) {
    Requests& out = requests[begin / kGrain];
    Scratch s;
    SubGrid subs;
    std::vector<uint32_t> candidates;
    Lists local;  // long lists: the set's per-cell lists
    Anchor anchor;
    std::array<std::vector<uint32_t>, 8> octant;
    for (size_t g0 = begin; g0 < end; g0 += 8) {
      const size_t parent = (b0 + g0) / 8;
      const std::span<const uint32_t> tris = parent_lists_[parent];
      const Lattice lattice = lattice_of(parent, d);
      uint8_t open = 0xFF;  // the octants without a witness yet
      if (tris.size() <= kSiblingMax) {
        const Bbox parent_box = lattice.box();
        s.planes.clear();
        s.lattice_pos.clear();
        s.lattice_neg.clear();
        for (uint32_t t : tris) {
          const Bvh::Tri tri = bvh_.triangle(t);
          const detail::PlaneSide& plane = s.planes.emplace_back(tri.a, tri.b, tri.c, parent_box);
          uint32_t pos = 0, neg = 0;
          plane.lattice_masks(lattice.planes, pos, neg);
          s.lattice_pos.push_back(pos);
          s.lattice_neg.push_back(neg);
          if (open == 0) continue;
          // A triangle whose box lies inside one octant's open box crosses that octant alone.
          const int o = inside_octant(tri, lattice.planes);
          open &= static_cast<uint8_t>(~(
              o >= 0
                  ? 1u << o
                  : detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, pos, neg, open)));
        }
        const uint8_t cross = static_cast<uint8_t>(~open);
        crossed[g0 / 8] = cross;
        if (samples_ * samples_ * samples_ <= 64)
          sibling_masks(g0, tris, lattice, cross, anchor_of(parent, d, anchor), s, out);
        else
          sibling_representatives(d, b0, g0, cross, s, subs, out.points, out.entries);
        continue;
      }
      for (auto& list : octant) list.clear();
      for (uint32_t t : tris) {
        const Bvh::Tri tri = bvh_.triangle(t);
        const int o = inside_octant(tri, lattice.planes);
        const uint8_t cross =
            o >= 0 ? static_cast<uint8_t>(1u << o)
                   : detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, 0xFF);
        for (uint8_t c = cross; c != 0; c &= static_cast<uint8_t>(c - 1))
          octant[std::countr_zero(c)].push_back(t);
      }
      local.start.assign(1, 0);
      local.tris.clear();
      uint8_t cross = 0;
      for (int c = 0; c < 8; ++c) {
        local.tris.insert(local.tris.end(), octant[c].begin(), octant[c].end());
        local.start.push_back(local.tris.size());
        cross |= static_cast<uint8_t>(!octant[c].empty()) << c;
      }
      crossed[g0 / 8] = cross;
      cells_representatives(
          d, b0, g0, 8, [&](size_t i) { return local[i - g0]; }, s, subs, candidates,
          anchor_of(parent, d, anchor), out);
    }
  });
}

}  // namespace cover::octree_build
