#include "cover/covering/gwn.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

#include "cover/covering/classify.h"
#include "cover/covering/detail/triangles.h"
#include "cover/covering/detail/windings.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/union_find.h"

namespace cover {
namespace {

constexpr double kInv4Pi = 0.25 / std::numbers::pi;

Vec3 centroid(const GwnTree::Tri& t) { return (1.0 / 3.0) * (t.a + t.b + t.c); }
double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }

/// Fills node `at` over tris[first, first + count) and its subtree (median splits on the widest
/// centroid axis; children appended as a pair).
void build_node(GwnTree& tree, uint32_t at, uint32_t first, uint32_t count, uint32_t leaf_size) {
  GwnTree::Node node;
  double area = 0;
  Vec3 weighted{0, 0, 0}, dipole{0, 0, 0};
  Bbox box;
  for (uint32_t i = first; i < first + count; ++i) {
    const GwnTree::Tri& t = tree.tris[i];
    const Vec3 n2 = cross(t.b - t.a, t.c - t.a);  // 2·area·n
    const double a = 0.5 * norm(n2);
    area += a;
    weighted = weighted + a * centroid(t);
    dipole = dipole + 0.5 * n2;
    box.add(t.a);
    box.add(t.b);
    box.add(t.c);
  }
  const Vec3 p = area > 0 ? (1.0 / area) * weighted : 0.5 * (box.min + box.max);
  double radius = 0;
  double m[9] = {};
  for (uint32_t i = first; i < first + count; ++i) {
    const GwnTree::Tri& t = tree.tris[i];
    radius = std::max({radius, norm(t.a - p), norm(t.b - p), norm(t.c - p)});
    const Vec3 an = 0.5 * cross(t.b - t.a, t.c - t.a), d = centroid(t) - p;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[3 * r + c] += an[r] * d[c];
  }
  node.center = p;
  node.radius = radius * (1 + 1e-12);  // the rounding of the norms above
  node.dipole = dipole;
  std::copy(m, m + 9, node.moment);
  node.area = area;
  if (count <= leaf_size) {
    node.first = first;
    node.count = count;
    tree.nodes[at] = node;
    return;
  }
  Bbox cbox;
  for (uint32_t i = first; i < first + count; ++i) cbox.add(centroid(tree.tris[i]));
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (cbox.max[k] - cbox.min[k] > cbox.max[axis] - cbox.min[axis]) axis = k;
  const uint32_t half = count / 2;
  std::nth_element(tree.tris.begin() + first, tree.tris.begin() + first + half,
                   tree.tris.begin() + first + count,
                   [axis](const GwnTree::Tri& x, const GwnTree::Tri& y) {
                     return centroid(x)[axis] < centroid(y)[axis];
                   });
  const uint32_t left = static_cast<uint32_t>(tree.nodes.size());
  tree.nodes.resize(tree.nodes.size() + 2);
  node.first = left;
  node.count = 0;
  tree.nodes[at] = node;
  build_node(tree, left, first, half, leaf_size);
  build_node(tree, left + 1, first + half, count - half, leaf_size);
}

/// First-order far field of a node at q (see gwn.h), in steradians.
double far_field(const GwnTree::Node& n, const Vec3& q) {  // NOLINT
  const Vec3 y = n.center - q;
  const double d2 = dot(y, y), d = std::sqrt(d2), inv3 = 1 / (d2 * d), inv5 = inv3 / d2;
  double value = dot(n.dipole, y) * inv3;
  const double* m = n.moment;
  // J:M with J = I/d³ − 3·y yᵀ/d⁵.
  value += (m[0] + m[4] + m[8]) * inv3;
  double yMy = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) yMy += y[r] * m[3 * r + c] * y[c];
  value -= 3 * yMy * inv5;
  return value;
}

}  // namespace

double triangle_winding(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  const Vec3 A = a - q, B = b - q, C = c - q;
  const double la = norm(A), lb = norm(B), lc = norm(C);
  double det = dot(A, cross(B, C));
  // |det − exact| ≤ about 1e-15·la·lb·lc; below a safe multiple, take the sign exactly
  // (orient3d(a, b, c, q) is the sign of n·(q − a) = −det).
  if (!(std::abs(det) > 1e-13 * la * lb * lc)) {
    const int s = -orient3d(a, b, c, q);
    if (s == 0)
      det = 0;
    else if ((det > 0) != (s > 0) || det == 0)
      det = s * std::max(std::abs(det), 1e-300);
  }
  const double denom = la * lb * lc + dot(A, B) * lc + dot(A, C) * lb + dot(B, C) * la;
  return 2 * std::atan2(det, denom) * kInv4Pi;
}

namespace {

bool vec_less(const Vec3& a, const Vec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

/// Builds tree.nodes over tree.tris.
void build_tree(GwnTree& tree, const GwnOptions& options) {
  if (tree.tris.empty()) return;
  tree.nodes.reserve(2 * tree.tris.size() / std::max<uint32_t>(1, options.leaf_size / 2) + 2);
  tree.nodes.resize(1);
  build_node(tree, 0, 0, static_cast<uint32_t>(tree.tris.size()),
             std::max<uint32_t>(1, options.leaf_size));
}

/// The closure of the leaf whose covering triangles are `tris` (see GwnClosure).
GwnClosure make_closure(const std::vector<GwnTree::Tri>& tris, const GwnOptions& options) {
  // Net multiplicity of each directed edge, by exact coordinates: +1 for a → b, −1 for b → a,
  // kept under the lexicographically smaller endpoint first.
  auto less = [](const std::pair<Vec3, Vec3>& x, const std::pair<Vec3, Vec3>& y) {
    if (x.first != y.first) return vec_less(x.first, y.first);
    return vec_less(x.second, y.second);
  };
  std::map<std::pair<Vec3, Vec3>, int64_t, decltype(less)> net(less);
  auto add = [&](const Vec3& a, const Vec3& b) {
    if (a == b) return;
    if (vec_less(a, b))
      ++net[{a, b}];
    else
      --net[{b, a}];
  };
  for (const GwnTree::Tri& t : tris) {
    add(t.a, t.b);
    add(t.b, t.c);
    add(t.c, t.a);
  }
  // Chain edges u → v (with multiplicity), their vertices numbered, components by union-find.
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  std::map<Vec3, uint32_t, decltype(&vec_less)> index(&vec_less);
  std::vector<Vec3> verts;
  auto id = [&](const Vec3& p) {
    const auto [it, added] = index.try_emplace(p, static_cast<uint32_t>(verts.size()));
    if (added) verts.push_back(p);
    return it->second;
  };
  for (const auto& [e, m] : net) {
    if (m == 0) continue;
    const uint32_t a = id(e.first), b = id(e.second);
    for (int64_t k = 0; k < std::abs(m); ++k)
      edges.push_back(m > 0 ? std::pair{a, b} : std::pair{b, a});
  }
  UnionFind uf(static_cast<uint32_t>(verts.size()));
  for (const auto& [a, b] : edges) uf.unite(a, b);
  std::vector<Vec3> sum(verts.size(), Vec3{0, 0, 0});
  std::vector<double> count(verts.size(), 0);
  for (uint32_t v = 0; v < verts.size(); ++v) {
    sum[uf.find(v)] = sum[uf.find(v)] + verts[v];
    count[uf.find(v)] += 1;
  }
  GwnClosure c;
  PolygonMesh mesh;
  auto push = [&](const Vec3& a, const Vec3& b, const Vec3& d) {
    const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(a);
    mesh.vertices.push_back(b);
    mesh.vertices.push_back(d);
    mesh.add_face({base, base + 1, base + 2});
  };
  for (const GwnTree::Tri& t : tris) push(t.a, t.b, t.c);
  for (const auto& [u, v] : edges) {
    const uint32_t r = uf.find(u);
    const Vec3 apex = (1.0 / count[r]) * sum[r];
    push(verts[v], verts[u], apex);
    c.cone.tris.push_back({verts[v], verts[u], apex});
  }
  c.solid = make_leaf(std::move(mesh), "closure");
  c.bvh = std::make_shared<const Bvh>(c.solid);
  build_tree(c.cone, options);
  return c;
}

}  // namespace

GwnForest build_gwn(const Solid& solid, const GwnOptions& options) {
  GwnForest forest;
  forest.tree_of_leaf.assign(solid.leaves.size(), -1);
  if (!solid.has_open_leaf()) return forest;
  const detail::LeafTriangles lt = detail::covering_triangles(solid);
  for (uint32_t l = 0; l < solid.leaves.size(); ++l) {
    if (!solid.leaves[l].open()) continue;
    forest.tree_of_leaf[l] = static_cast<int32_t>(forest.trees.size());
    GwnTree& tree = forest.trees.emplace_back();
    for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i)
      tree.tris.push_back({lt.tris[i].a, lt.tris[i].b, lt.tris[i].c});
    forest.closures.push_back(make_closure(tree.tris, options));
    build_tree(tree, options);
  }
  return forest;
}

namespace {

/// Decides |W − w_C(q)| > 1/2 by bounds alone where it can: unexpanded nodes are bounded by
/// |w_node| ≤ A/(4π·gap²) (a surface of area A seen from at least gap away subtends at most
/// A/gap² sr), leaves are summed exactly; the node with the largest bound is expanded first,
/// at most kMaxExpansions times. Returns false when undecided.
bool decide_by_bounds(const GwnTree& cone, const Vec3& q, int32_t W, bool& inside) {
  constexpr int kMaxExpansions = 48;
  struct Item {
    double bound;
    uint32_t node;
  };
  auto lower = [](const Item& x, const Item& y) { return x.bound < y.bound; };
  Item heap[2 * kMaxExpansions + 2];
  int size = 0, unbounded = 0;  // unbounded: nodes whose sphere contains q (no bound)
  double exact = 0, open_bound = 0, rounding = 0, peak = 0;
  auto push = [&](uint32_t id) {
    const GwnTree::Node& n = cone.nodes[id];
    const double gap = norm(n.center - q) - n.radius;
    const double b = gap > 0 ? n.area / (gap * gap) * kInv4Pi * (1 + 1e-12) : INFINITY;
    heap[size++] = {b, id};
    std::push_heap(heap, heap + size, lower);
    if (std::isinf(b)) {
      ++unbounded;
    } else {
      open_bound += b;
      peak = std::max(peak, open_bound);
    }
  };
  auto decided = [&] {
    if (unbounded > 0) return false;
    // The running sum (additions and removals, < 200 of them) is off by at most 1e-12·peak.
    const double slack = std::max(open_bound, 0.0) + 1e-12 * peak + rounding;
    const double lo = W - exact - slack, hi = W - exact + slack;
    if (hi < 0.5 && lo > -0.5) return inside = false, true;
    if (lo > 0.5 || hi < -0.5) return inside = true, true;
    return false;
  };
  push(0);
  for (int e = 0; e < kMaxExpansions && size > 0; ++e) {
    if (decided()) return true;
    std::pop_heap(heap, heap + size, lower);
    const Item top = heap[--size];
    if (std::isinf(top.bound))
      --unbounded;
    else
      open_bound -= top.bound;
    const GwnTree::Node& n = cone.nodes[top.node];
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        const GwnTree::Tri& t = cone.tris[i];
        exact += triangle_winding(t.a, t.b, t.c, q);
      }
      rounding += n.count * kGwnRoundingPerTerm;
    } else {
      push(n.first);
      push(n.first + 1);
    }
  }
  return decided();
}

/// Lower bound of the distance between two boxes (0 when they meet).
double box_gap(const Bbox& a, const double* lo, const double* hi) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max({lo[k] - a.max[k], a.min[k] - hi[k], 0.0});
    d2 += g * g;
  }
  return std::sqrt(d2) * (1 - 1e-12);
}

}  // namespace

bool winding_below(const GwnTree& tree, const Bbox& box, double limit, int budget) {
  if (tree.nodes.empty()) return true;
  constexpr int kMaxBudget = 128;
  budget = std::clamp(budget, 1, kMaxBudget);
  struct Item {
    double bound;
    int64_t node;  ///< node id, or −1 − triangle index (not expandable)
  };
  auto lower = [](const Item& x, const Item& y) { return x.bound < y.bound; };
  thread_local std::vector<Item> heap;
  heap.clear();
  double total = 0;  // Σ bounds of the items in the heap (kept as a fresh sum below)
  auto push_node = [&](uint32_t id) {
    const GwnTree::Node& n = tree.nodes[id];
    const Vec3 p = n.center;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double g = std::max({box.min[k] - p[k], p[k] - box.max[k], 0.0});
      d2 += g * g;
    }
    const double dist = std::sqrt(d2);
    const double gap = dist * (1 - 1e-12) - n.radius;
    // A margin against rounding: a sphere within 1e-9 of the box counts as meeting it.
    const double b = gap > 1e-9 * (dist + n.radius) ? n.area / (gap * gap) * kInv4Pi : INFINITY;
    heap.push_back({b, id});
    std::push_heap(heap.begin(), heap.end(), lower);
    total += b;
  };
  auto push_tri = [&](uint32_t i) {
    const GwnTree::Tri& t = tree.tris[i];
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min({t.a[k], t.b[k], t.c[k]});
      hi[k] = std::max({t.a[k], t.b[k], t.c[k]});
    }
    bool apart = false;  // exact: the triangle's box and `box` are disjoint along some axis
    for (int k = 0; k < 3; ++k) apart |= lo[k] > box.max[k] || hi[k] < box.min[k];
    const double area = 0.5 * norm(cross(t.b - t.a, t.c - t.a)) * (1 + 1e-12);
    const double gap = box_gap(box, lo, hi);
    const double b = !apart      ? INFINITY
                     : area == 0 ? 0
                     : gap > 0   ? area / (gap * gap) * kInv4Pi
                                 : INFINITY;
    heap.push_back({b, -1 - static_cast<int64_t>(i)});
    std::push_heap(heap.begin(), heap.end(), lower);
    total += b;
  };
  // The bounds and their sum are formed with relative errors far below this factor.
  auto below = [&] { return total * (1 + 1e-9) < limit; };
  push_node(0);
  for (int e = 0; e < budget; ++e) {
    if (below()) return true;
    std::pop_heap(heap.begin(), heap.end(), lower);
    const Item top = heap.back();
    heap.pop_back();
    if (top.node < 0) return false;  // the largest is a triangle: no expansion helps
    const GwnTree::Node& n = tree.nodes[top.node];
    if (n.count > 0)
      for (uint32_t i = n.first; i < n.first + n.count; ++i) push_tri(i);
    else {
      push_node(n.first);
      push_node(n.first + 1);
    }
    total = 0;  // re-summed: no cancellation of infinities
    for (const Item& it : heap) total += it.bound;
  }
  return below();
}

std::vector<uint8_t> open_inside(const GwnForest& forest, size_t k, std::span<const Vec3> points,
                                 const GwnOptions& options) {
  const GwnTree& tree = forest.trees[k];
  const GwnClosure& c = forest.closures[k];
  std::vector<uint8_t> inside(points.size(), 0);
  if (tree.nodes.empty()) return inside;
  const LeafWindings lw = detail::crossing_windings(c.solid, *c.bvh, points);
  parallel_for(points.size(), 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (lw.on_surface[i] == 0) {
        bool in = false;
        if (decide_by_bounds(c.cone, points[i], lw.winding[i], in)) {
          inside[i] = in;
          continue;
        }
        const GwnValue v = generalized_winding(c.cone, points[i], options.cone_beta);
        const double w = lw.winding[i] - v.w;  // w_S = W − w_C
        if (std::abs(std::abs(w) - 0.5) > v.error) {
          inside[i] = std::abs(w) > 0.5;
          continue;
        }
      }
      inside[i] = gwn_inside(tree, points[i], options);
    }
  });
  return inside;
}

namespace {

/// round(w) when no half-integer lies within v.error of v.w (then it is the rounding of the
/// true w), else nullopt.
std::optional<double> settled_round(const GwnValue& v) {
  const double r = std::round(v.w);
  const double half = r + (v.w >= r ? 0.5 : -0.5);  // the nearest half-integer
  if (!(std::abs(v.w - half) > v.error)) return std::nullopt;
  return r;
}

}  // namespace

std::vector<int32_t> open_windings(const GwnForest& forest, size_t k, std::span<const Vec3> points,
                                   const GwnOptions& options) {
  const std::vector<uint8_t> inside = open_inside(forest, k, points, options);
  const GwnTree& tree = forest.trees[k];
  std::vector<int32_t> out(points.size(), 0);
  parallel_for(points.size(), 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (!inside[i]) continue;
      GwnValue v = generalized_winding(tree, points[i], options.beta);
      std::optional<double> r = settled_round(v);
      if (!r) r = settled_round(v = generalized_winding(tree, points[i], options.refine_beta));
      if (!r) r = settled_round(v = generalized_winding_direct(tree, points[i]));
      // Undecided: toward zero (|w| within the allowance of m + 1/2 counts as m).
      const double w = r ? *r : std::copysign(std::floor(std::abs(v.w)), v.w);
      const double clamped = std::clamp(w, -2147483647.0, 2147483647.0);
      out[i] = clamped != 0 ? static_cast<int32_t>(clamped) : (v.w < 0 ? -1 : 1);
    }
  });
  return out;
}

GwnValue generalized_winding(const GwnTree& tree, const Vec3& q, double beta) {
  GwnValue out;
  if (tree.nodes.empty()) return out;
  double omega = 0, error = 0;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const GwnTree::Node& n = tree.nodes[stack[--top]];
    const Vec3 y = n.center - q;
    const double d = std::sqrt(dot(y, y));
    if (d > beta * n.radius && n.area > 0) {
      omega += far_field(n, q) * kInv4Pi;
      const double gap = d - n.radius;
      error += 3 * n.area * n.radius * n.radius / (gap * gap * gap * gap) * kInv4Pi +
               kGwnRoundingPerTerm;
      continue;
    }
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        const GwnTree::Tri& t = tree.tris[i];
        omega += triangle_winding(t.a, t.b, t.c, q);
      }
      error += n.count * kGwnRoundingPerTerm;
      continue;
    }
    stack[top++] = n.first + 1;
    stack[top++] = n.first;
  }
  out.w = omega;  // in units of 4π sr
  out.error = error;
  return out;
}

GwnValue generalized_winding_direct(const GwnTree& tree, const Vec3& q) {
  GwnValue out;
  for (const GwnTree::Tri& t : tree.tris) out.w += triangle_winding(t.a, t.b, t.c, q);
  out.error = static_cast<double>(tree.tris.size()) * kGwnRoundingPerTerm;
  return out;
}

bool gwn_inside(const GwnTree& tree, const Vec3& q, const GwnOptions& options) {
  auto decided = [](const GwnValue& v) { return std::abs(std::abs(v.w) - 0.5) > v.error; };
  GwnValue v = generalized_winding(tree, q, options.beta);
  if (!decided(v)) v = generalized_winding(tree, q, options.refine_beta);
  if (!decided(v)) v = generalized_winding_direct(tree, q);
  if (!decided(v)) return false;  // within the rounding allowance of ±1/2: the tie rule
  return std::abs(v.w) > 0.5;
}

}  // namespace cover
