#include "cover/covering/classify.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <functional>
#include <mutex>
#include <optional>

#include "cover/covering/box_states.h"
#include "cover/covering/bvh_walk.h"
#include "cover/covering/detail/cell_grid.h"
#include "cover/covering/detail/float_bounds.h"
#include "cover/covering/detail/implicit.h"
#include "cover/covering/detail/local.h"
#include "cover/covering/detail/triangles.h"
#include "cover/covering/detail/windings.h"
#include "cover/field/field.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/simd.h"

namespace cover {
namespace {

using detail::LeafTriangles;

/// The grid settles a cell of open leaves where each closure's cones subtend less than this
/// (|w_C| < 0.4 leaves |W − w_C| at least 0.1 from 1/2, far beyond the per-point rounding
/// allowance, so the per-point path decides every point of the cell the same way).
constexpr double kSettledCone = 0.4;

/// An axis-aligned half-line direction s·e_k; u, w are the other two axes in cyclic order.
struct AxisRay {
  int k = 0, u = 1, w = 2;
  int s = 1;
};
AxisRay axis_ray(int k, int s) { return {k, (k + 1) % 3, (k + 2) % 3, s}; }

/// Sign of the projected orientation of (a, b, q) (dropping axis k) with q perturbed to
/// q + ε·e_u + ε²·e_w: o(q) − (b_w − a_w)·ε + (b_u − a_u)·ε².
int perturbed_orient(const Vec3& a, const Vec3& b, const Vec3& q, const AxisRay& r) {
  const int o = orient2d(a, b, q, r.k);
  if (o != 0) return o;
  if (a[r.w] != b[r.w]) return a[r.w] > b[r.w] ? 1 : -1;
  if (a[r.u] != b[r.u]) return b[r.u] > a[r.u] ? 1 : -1;
  return 0;
}

/// Adds the crossing of the half-line q + t·s·e_k (t > 0) with triangle abc to `winding`;
/// returns true when q lies on the triangle. Precondition: abc is not degenerate.
bool visit(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q, const AxisRay& r,
           int& winding) {
  const int k = r.k, u = r.u, w = r.w;
  if (q[u] < std::min({a[u], b[u], c[u]}) || q[u] > std::max({a[u], b[u], c[u]}) ||
      q[w] < std::min({a[w], b[w], c[w]}) || q[w] > std::max({a[w], b[w], c[w]}))
    return false;
  if (r.s > 0 ? q[k] > std::max({a[k], b[k], c[k]}) : q[k] < std::min({a[k], b[k], c[k]}))
    return false;
  const int o3 = orient3d(a, b, c, q);  // sign of n·(q − a)
  if (o3 == 0) return detail::on_triangle(a, b, c, q);
  const int nk = orient2d(a, b, c, k);  // sign of the normal's k component
  // The half-line meets the plane ahead (t > 0) iff q is behind it as seen along s·e_k.
  if (nk == 0 || o3 != -r.s * nk) return false;
  if (perturbed_orient(a, b, q, r) == nk && perturbed_orient(b, c, q, r) == nk &&
      perturbed_orient(c, a, q, r) == nk)
    winding += r.s * nk;  // leaving through an outward face counts +1, entering −1
  return false;
}

/// Per-leaf winding numbers and on-surface flags at q, from every covering triangle.
void brute_windings(const LeafTriangles& lt, const Vec3& q, std::vector<int>& winding,
                    std::vector<uint8_t>& on_surface) {
  const size_t leaves = lt.leaf_start.size() - 1;
  winding.assign(leaves, 0);
  on_surface.assign(leaves, 0);
  for (size_t l = 0; l < leaves; ++l)
    for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i) {
      const detail::CoverTri& t = lt.tris[i];
      on_surface[l] |= visit(t.a, t.b, t.c, q, axis_ray(0, 1), winding[l]);
    }
}

/// A classification query: the point, its half-line — along the axis direction that leaves the
/// solid's box soonest (fewer nodes to visit; the winding number does not depend on the choice)
/// — and the half-line's bounding box (a point in u and w, unbounded along s·e_k) as float
/// bounds rounded outward (float_bounds.h) in the lane order of a node's first and second 16
/// bytes, (lo0, lo1, lo2, hi0) and (hi0, hi1, hi2, first): a node box meets the half-line iff
/// lo <= hi_q and hi >= lo_q on every axis, which these float bounds decide exactly.
struct alignas(16) HalfLineQuery {
  detail::v4f hi_q, lo_q;
  Vec3 q;
  AxisRay r;
};

HalfLineQuery half_line_query(const Bvh& bvh, const Vec3& q) {
  const Bbox& all = bvh.bounds();
  HalfLineQuery h{};
  h.q = q;
  h.r = axis_ray(0, 1);
  double shortest = all.max.x - q.x;
  for (int k = 0; k < 3; ++k)
    for (int s : {1, -1}) {
      const double len = s > 0 ? all.max[k] - q[k] : q[k] - all.min[k];
      if (len < shortest) {
        shortest = len;
        h.r = axis_ray(k, s);
      }
    }
  const float inf = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const bool along = a == h.r.k;
    h.hi_q[a] = along && h.r.s > 0 ? inf : detail::float_down(q[a]);
    h.lo_q[a] = along && h.r.s < 0 ? -inf : detail::float_up(q[a]);
  }
  h.hi_q[3] = inf;   // lane 3 of the first load is hi0: hi0 <= ∞ always holds
  h.lo_q[3] = -inf;  // lane 3 of the second is `first` (not a bound): masked below
  return h;
}

/// Whether node's box meets the query's half-line (see HalfLineQuery).
bool meets(const HalfLineQuery& h, const Bvh::Node& node) {
  static_assert(offsetof(Bvh::Node, lo) == 0 && offsetof(Bvh::Node, hi) == 12 &&
                sizeof(Bvh::Node) == 32);
  detail::v4f a, b;
  std::memcpy(&a, reinterpret_cast<const char*>(&node), sizeof a);
  std::memcpy(&b, reinterpret_cast<const char*>(&node) + 12, sizeof b);
  const detail::v4i ignore_first = {0, 0, 0, -1};
  return detail::all_lanes((a <= h.hi_q) & ((b >= h.lo_q) | ignore_first));
}

/// The same from the BVH: only nodes whose box meets the half-line (a depth-first walk; the
/// cell grid's queries, one at a time).
void bvh_windings(const Bvh& bvh, const Vec3& q, std::vector<int>& winding,
                  std::vector<uint8_t>& on_surface) {
  std::fill(winding.begin(), winding.end(), 0);
  std::fill(on_surface.begin(), on_surface.end(), 0);
  if (bvh.nodes().empty()) return;
  const HalfLineQuery h = half_line_query(bvh, q);
  walk(
      bvh, [&](const Bvh::Node& node) { return meets(h, node); },
      [&](const Bvh::Tri& t, uint32_t) {
        on_surface[t.leaf] |= visit(t.a, t.b, t.c, q, h.r, winding[t.leaf]);
      });
}

/// bvh_windings for a batch of points (walk_batch: their node loads overlap). winding and
/// on_surface hold ids.size() rows of `leaves` entries.
void bvh_windings_batch(const Bvh& bvh, std::span<const Vec3> points, std::span<const uint32_t> ids,
                        size_t leaves, std::vector<int>& winding, std::vector<uint8_t>& on_surface,
                        std::vector<HalfLineQuery>& queries) {
  winding.assign(ids.size() * leaves, 0);
  on_surface.assign(ids.size() * leaves, 0);
  queries.resize(ids.size());
  for (size_t j = 0; j < ids.size(); ++j) queries[j] = half_line_query(bvh, points[ids[j]]);
  walk_batch(
      bvh, static_cast<uint32_t>(ids.size()),
      [&](uint32_t j, const Bvh::Node& l, const Bvh::Node& r) {
        return unsigned{meets(queries[j], l)} | unsigned{meets(queries[j], r)} << 1;
      },
      [&](uint32_t j, uint32_t first, uint32_t count) {
        const HalfLineQuery& h = queries[j];
        for_each_triangle(bvh, first, count, [&](const Bvh::Tri& t, uint32_t) {
          const size_t at = j * leaves + t.leaf;
          int w = winding[at];
          on_surface[at] |= visit(t.a, t.b, t.c, h.q, h.r, w);
          winding[at] = w;
        });
      });
}

/// Leaf memberships → result class; on-surface points go to the exact local analysis.
/// Open leaves off their surface take the generalized winding number's membership (gwn.h):
/// through the forest's trees, or (direct) by the direct sum.
struct OpenRule {
  const GwnForest* forest = nullptr;
  GwnOptions options;
  bool direct = false;
  /// Per tree, every point's membership from open_inside (empty: decide per point).
  std::vector<std::vector<uint8_t>> bulk;
};

/// Field and warp leaves: membership by covering/detail/implicit.h (a field's certified sign of
/// f − T, a warp's child at the preimage). `uncertain` counts the points those leave undecided
/// (then their tie rules decide) and those where several surfaces meet at a point in a way the
/// tree does not settle (then `face`); shared by the threads.
struct FieldRule {
  const Prepared* prepared = nullptr;  ///< nullptr: no field or warp leaf
  std::vector<uint32_t> leaves;        ///< the field and warp leaves' ids
  std::atomic<size_t>* uncertain = nullptr;
};

/// The class of q, on the surface of the field leaves `on_field` (and of the mesh leaves marked
/// in on_surface, if any), from the tree over every membership those leaves can take near q.
/// One field surface and no mesh surface: face where the tree's value changes across it, else
/// that value; q is a regular point of a field's surface unless ∇f(q) = 0, which a double point
/// on a blend's surface meets only by coincidence (docs/design.md "Fields"). Several surfaces at
/// q: the common class when every combination gives inside or every one outside; otherwise face,
/// counted uncertain.
PointClass field_surface_class(const Vec3& q, const CsgTree& tree,
                               std::span<const uint8_t> on_surface, std::vector<uint8_t>& inside,
                               std::span<const uint32_t> on_field,
                               const std::function<const LeafTriangles&()>& triangles,
                               const FieldRule& rule) {
  const bool mesh_on =
      std::any_of(on_surface.begin(), on_surface.end(), [](uint8_t o) { return o != 0; });
  const size_t k = on_field.size();
  bool all_in = true, all_out = true;
  for (uint32_t mask = 0; mask < (1u << k); ++mask) {
    for (size_t i = 0; i < k; ++i) inside[on_field[i]] = (mask >> i) & 1;
    PointClass c;
    if (mesh_on) {
      c = detail::classify_on_surface(triangles(), tree, q, on_surface, inside);
    } else {
      c = tree.evaluate(inside) ? PointClass::kInside : PointClass::kOutside;
    }
    all_in &= c == PointClass::kInside;
    all_out &= c == PointClass::kOutside;
  }
  if (all_in) return PointClass::kInside;
  if (all_out) return PointClass::kOutside;
  if (on_field.size() > 1 || mesh_on) rule.uncertain->fetch_add(1, std::memory_order_relaxed);
  return PointClass::kFace;
}

PointClass finish(const Vec3& q, const CsgTree& tree, std::span<const int> winding,
                  std::span<const uint8_t> on_surface, std::vector<uint8_t>& inside,
                  const std::function<const LeafTriangles&()>& triangles, const OpenRule& open = {},
                  size_t point = 0, const FieldRule& fields = {}) {
  inside.resize(winding.size());
  bool any_on = false;
  constexpr size_t kMaxOn = 12;  // 2^12 combinations at most; more surfaces at q: face, uncertain
  uint32_t on_field_store[kMaxOn];
  size_t on_fields = 0, on_total = 0;
  for (uint32_t l : fields.leaves) {
    const field::Sign s = detail::implicit_member(*fields.prepared, l, q, fields.uncertain);
    inside[l] = s == field::Sign::kInside;
    if (s == field::Sign::kOn && on_total++ < kMaxOn) on_field_store[on_fields++] = l;
  }
  if (on_total > kMaxOn) {
    fields.uncertain->fetch_add(1, std::memory_order_relaxed);
    return PointClass::kFace;
  }
  for (size_t l = 0; l < winding.size(); ++l) {
    if (fields.prepared != nullptr && fields.prepared->solid().leaves[l].is_implicit()) continue;
    inside[l] = winding[l] != 0;
    any_on |= on_surface[l] != 0;
    if (open.forest == nullptr || open.forest->tree_of_leaf[l] < 0 || on_surface[l]) continue;
    const GwnTree& t = open.forest->trees[open.forest->tree_of_leaf[l]];
    if (!open.bulk.empty()) {
      inside[l] = open.bulk[open.forest->tree_of_leaf[l]][point];
    } else if (open.direct) {
      const GwnValue v = generalized_winding_direct(t, q);
      inside[l] = std::abs(std::abs(v.w) - 0.5) > v.error && std::abs(v.w) > 0.5;
    } else {
      inside[l] = gwn_inside(t, q, open.options);
    }
  }
  if (on_fields > 0)
    return field_surface_class(q, tree, on_surface, inside,
                               std::span<const uint32_t>(on_field_store, on_fields), triangles,
                               fields);
  if (!any_on) return tree.evaluate(inside) ? PointClass::kInside : PointClass::kOutside;
  return detail::classify_on_surface(triangles(), tree, q, on_surface, inside);
}

FieldRule field_rule(const Prepared& prepared, std::atomic<size_t>& uncertain) {
  FieldRule rule;
  const Solid& solid = prepared.solid();
  if (!solid.has_implicit_leaf()) return rule;
  rule.prepared = &prepared;
  rule.uncertain = &uncertain;
  for (uint32_t l = 0; l < solid.leaves.size(); ++l)
    if (solid.leaves[l].is_implicit()) rule.leaves.push_back(l);
  return rule;
}

/// Orders `ids` bucket by bucket over a 32³ grid of `box` (counting sort, O(n), stable):
/// consecutive queries then walk the same BVH nodes and triangles, which keeps them in cache
/// (bench_queries BM_ClassifyBulk). Results never depend on the order.
void bucket_order(std::span<const Vec3> points, const Bbox& box, std::vector<uint32_t>& ids) {
  constexpr int kSide = 32;
  std::vector<uint32_t> bucket(ids.size());
  std::vector<uint32_t> count(kSide * kSide * kSide + 1, 0);
  auto cell = [&](double v, int a) {
    const double ext = box.max[a] - box.min[a];
    const double f = ext > 0 ? (v - box.min[a]) / ext * kSide : 0;
    return f <= 0 ? 0 : (f >= kSide - 1 ? kSide - 1 : static_cast<int>(f));
  };
  for (size_t i = 0; i < ids.size(); ++i) {
    const Vec3& p = points[ids[i]];
    bucket[i] = static_cast<uint32_t>((cell(p.z, 2) * kSide + cell(p.y, 1)) * kSide + cell(p.x, 0));
    ++count[bucket[i] + 1];
  }
  for (size_t b = 1; b < count.size(); ++b) count[b] += count[b - 1];
  std::vector<uint32_t> sorted(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) sorted[count[bucket[i]]++] = ids[i];
  ids.swap(sorted);
}

}  // namespace

std::string_view to_string(PointClass c) {
  switch (c) {
    case PointClass::kOutside:
      return "outside";
    case PointClass::kInside:
      return "inside";
    case PointClass::kFace:
      return "face";
    case PointClass::kEdge:
      return "edge";
    case PointClass::kVertex:
      return "vertex";
  }
  return "?";
}

std::vector<PointClass> classify(const Prepared& prepared, std::span<const Vec3> points,
                                 const ClassifyOptions& options) {
  return classify_counted(prepared, points, options).classes;
}

Classification classify_counted(const Prepared& prepared, std::span<const Vec3> points,
                                const ClassifyOptions& options) {
  const Solid& solid = prepared.solid();
  std::atomic<size_t> uncertain{0};
  const FieldRule fields = field_rule(prepared, uncertain);
  const Bvh& bvh = prepared.bvh();
  // Per-leaf covering triangles, built on first use (only points on a surface need them).
  std::once_flag once;
  LeafTriangles lazy;
  const std::function<const LeafTriangles&()> triangles = [&]() -> const LeafTriangles& {
    std::call_once(once, [&] { lazy = detail::covering_triangles(solid); });
    return lazy;
  };
  std::vector<PointClass> out(points.size());
  // Open leaves: their generalized winding number trees (gwn.h).
  OpenRule open;
  if (solid.has_open_leaf()) {
    open.forest = prepared.gwn();
    open.options = options.gwn_options;
  }
  // Many queries: first label the grid cells no surface touches (exact, see cell_grid.h). With
  // open leaves, only cells where every closure's cones provably subtend |w_C| < 0.4 (there the
  // membership is W ≠ 0, constant on the cell like a closed leaf's; docs/design.md "Open
  // leaves"); a component's label is the per-point membership at one cell centre.
  std::optional<detail::CellGrid> grid;
  if (points.size() >= options.grid_min_points) {
    const int res = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(points.size()))), 8,
                               options.grid_max_resolution);
    // Field and warp leaves: a cell is settled where each one's state on it is certain (a
    // field's enclosure excludes T: the sign of f − T is constant on the closed cell, and equal
    // across a shared face).
    std::function<bool(const Bbox&)> settled;
    if (open.forest != nullptr || fields.prepared != nullptr)
      settled = [&](const Bbox& box) {
        if (open.forest != nullptr)
          for (const GwnClosure& c : open.forest->closures)
            if (!winding_below(c.cone, box, kSettledCone)) return false;
        for (uint32_t l : fields.leaves)
          if (detail::implicit_box_state(prepared, l, box) == kBoxUndecided) return false;
        return true;
      };
    grid.emplace(
        bvh, res,
        [&](const Vec3& c) {
          std::vector<int> w(solid.leaves.size());
          std::vector<uint8_t> on(solid.leaves.size()), in;
          bvh_windings(bvh, c, w, on);
          return finish(c, solid.tree, w, on, in, triangles, open, 0, fields) ==
                 PointClass::kInside;
        },
        settled);
  }
  // Points the grid answers are done; the rest go through the BVH in spatial order.
  std::vector<uint32_t> todo;
  if (grid && points.size() <= UINT32_MAX) {
    std::vector<int8_t> known(points.size());
    parallel_for(points.size(), 4096, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) known[i] = static_cast<int8_t>(grid->lookup(points[i]));
    });
    for (size_t i = 0; i < points.size(); ++i) {
      if (known[i] >= 0)
        out[i] = known[i] ? PointClass::kInside : PointClass::kOutside;
      else
        todo.push_back(static_cast<uint32_t>(i));
    }
  } else {
    todo.resize(points.size());
    for (size_t i = 0; i < todo.size(); ++i) todo[i] = static_cast<uint32_t>(i);
  }
  if (todo.size() >= 4096 && !bvh.nodes().empty()) bucket_order(points, bvh.bounds(), todo);
  // Open leaves: every remaining point at once through the closure (open_inside), by its
  // position in todo.
  if (open.forest != nullptr) {
    std::vector<Vec3> rest(todo.size());
    for (size_t i = 0; i < todo.size(); ++i) rest[i] = points[todo[i]];
    for (size_t k = 0; k < open.forest->trees.size(); ++k)
      open.bulk.push_back(open_inside(*open.forest, k, rest, open.options));
  }
  // Batches of points walk the BVH together (walk_batch); per-point results are the same.
  const size_t leaves = solid.leaves.size();
  const size_t batch = std::clamp<size_t>(16384 / std::max<size_t>(leaves, 1), 1, 256);
  parallel_for(todo.size(), options.grain, [&](size_t begin, size_t end) {
    std::vector<int> winding;
    std::vector<uint8_t> on_surface, inside;
    std::vector<HalfLineQuery> queries;
    for (size_t b = begin; b < end; b += batch) {
      const std::span<const uint32_t> ids(todo.data() + b, std::min(end, b + batch) - b);
      bvh_windings_batch(bvh, points, ids, leaves, winding, on_surface, queries);
      for (size_t j = 0; j < ids.size(); ++j)  // point j's row of each table
        out[ids[j]] = finish(points[ids[j]], solid.tree,
                             std::span<const int>(winding).subspan(j * leaves, leaves),
                             std::span<const uint8_t>(on_surface).subspan(j * leaves, leaves),
                             inside, triangles, open, b + j, fields);
    }
  });
  return {std::move(out), uncertain.load()};
}

std::vector<PointClass> classify(const Solid& solid, std::span<const Vec3> points,
                                 const ClassifyOptions& options) {
  PrepareOptions prepare;
  prepare.gwn = options.gwn_options;  // the trees built as this call evaluates them
  const Prepared prepared(solid, prepare);
  return classify(prepared, points, options);
}

void classify_lattice(const Prepared& prepared, const VoxelLattice& lattice, const IndexBox& box,
                      const std::function<void(int i, int j, int k)>& member) {
  const auto d = box.dims();
  // Whole x slabs, about 2^20 centres at a time: bounded memory, and classify's empty-cell grid
  // (which settles the cells far from the holes) is built once per batch.
  const size_t slab = static_cast<size_t>(d[1]) * d[2];
  const int per_batch =
      static_cast<int>(std::max<size_t>(1, (size_t{1} << 20) / std::max<size_t>(slab, 1)));
  std::vector<Vec3> centres;
  for (int i0 = box.lo[0]; i0 < box.hi[0]; i0 += per_batch) {
    const int i1 = std::min(box.hi[0], i0 + per_batch);
    centres.clear();
    for (int i = i0; i < i1; ++i)
      for (int j = box.lo[1]; j < box.hi[1]; ++j)
        for (int k = box.lo[2]; k < box.hi[2]; ++k) centres.push_back(lattice.centre(i, j, k));
    const std::vector<PointClass> c = classify(prepared, centres);
    size_t at = 0;
    for (int i = i0; i < i1; ++i)
      for (int j = 0; j < d[1]; ++j)
        for (int k = 0; k < d[2]; ++k)
          if (c[at++] != PointClass::kOutside) member(i - box.lo[0], j, k);
  }
}

std::vector<PointClass> classify_brute_force(const Solid& solid, std::span<const Vec3> points,
                                             const ClassifyOptions& options) {
  const LeafTriangles lt = detail::covering_triangles(solid);
  const std::function<const LeafTriangles&()> triangles = [&]() -> const LeafTriangles& {
    return lt;
  };
  std::optional<GwnForest> forest;
  OpenRule open;
  if (solid.has_open_leaf()) {
    forest = build_gwn(solid, options.gwn_options);
    open.forest = &*forest;
    open.direct = true;
  }
  std::atomic<size_t> uncertain{0};
  const Prepared prepared(solid);  // field and warp leaves' structures (warp children)
  const FieldRule fields = field_rule(prepared, uncertain);
  std::vector<PointClass> out(points.size());
  parallel_for(points.size(), options.grain, [&](size_t begin, size_t end) {
    std::vector<int> winding;
    std::vector<uint8_t> on_surface, inside;
    for (size_t i = begin; i < end; ++i) {
      brute_windings(lt, points[i], winding, on_surface);
      out[i] =
          finish(points[i], solid.tree, winding, on_surface, inside, triangles, open, 0, fields);
    }
  });
  return out;
}

namespace detail {

LeafWindings crossing_windings(const Solid& solid, const Bvh& bvh, std::span<const Vec3> points,
                               size_t grain) {
  LeafWindings out;
  out.leaves = solid.leaves.size();
  out.winding.assign(points.size() * out.leaves, 0);
  out.on_surface.assign(points.size() * out.leaves, 0);
  if (out.leaves == 0 || bvh.nodes().empty()) return out;
  const size_t batch = std::clamp<size_t>(16384 / out.leaves, 1, 256);
  parallel_for(points.size(), grain, [&](size_t begin, size_t end) {
    std::vector<int> winding;
    std::vector<uint8_t> on_surface;
    std::vector<HalfLineQuery> queries;
    std::vector<uint32_t> ids;
    for (size_t b = begin; b < end; b += batch) {
      ids.resize(std::min(end, b + batch) - b);  // batch-local ids: any number of points
      for (size_t j = 0; j < ids.size(); ++j) ids[j] = static_cast<uint32_t>(j);
      bvh_windings_batch(bvh, points.subspan(b, ids.size()), ids, out.leaves, winding, on_surface,
                         queries);
      std::copy(winding.begin(), winding.end(), out.winding.begin() + b * out.leaves);
      std::copy(on_surface.begin(), on_surface.end(), out.on_surface.begin() + b * out.leaves);
    }
  });
  return out;
}

}  // namespace detail

LeafWindings leaf_windings(const Prepared& prepared, std::span<const Vec3> points,
                           const ClassifyOptions& options) {
  LeafWindings out =
      detail::crossing_windings(prepared.solid(), prepared.bvh(), points, options.grain);
  // Field and warp leaves: 1 inside, 0 outside, on_surface on the surface (as classify()
  // decides them, tie rules included).
  const Solid& solid = prepared.solid();
  for (size_t l = 0; l < out.leaves; ++l) {
    const Leaf& leaf = solid.leaves[l];
    if (!leaf.is_implicit()) continue;
    parallel_for(points.size(), options.grain, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        const field::Sign s =
            detail::implicit_member(prepared, static_cast<uint32_t>(l), points[i]);
        out.winding[i * out.leaves + l] = s == field::Sign::kInside;
        out.on_surface[i * out.leaves + l] = s == field::Sign::kOn;
      }
    });
  }
  // Open leaves: the crossing count above means nothing; their generalized winding number,
  // rounded (decided as classify() decides membership).
  const GwnForest* forest = prepared.gwn();
  if (forest == nullptr) return out;
  for (size_t l = 0; l < out.leaves; ++l) {
    const int32_t k = forest->tree_of_leaf[l];
    if (k < 0) continue;
    const std::vector<int32_t> w =
        open_windings(*forest, static_cast<size_t>(k), points, options.gwn_options);
    for (size_t i = 0; i < points.size(); ++i) {
      const size_t at = i * out.leaves + l;
      out.winding[at] = out.on_surface[at] ? 0 : w[i];
    }
  }
  return out;
}

void leaf_windings(const Solid& solid, const Vec3& q, std::vector<int>& winding,
                   std::vector<uint8_t>& on_surface) {
  brute_windings(detail::covering_triangles(solid), q, winding, on_surface);
}

}  // namespace cover
