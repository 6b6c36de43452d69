#include "covering/gwn.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "covering/detail/triangles.h"
#include "solid/predicates.h"

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
double far_field(const GwnTree::Node& n, const Vec3& q) {
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
    if (tree.tris.empty()) continue;
    tree.nodes.reserve(2 * tree.tris.size() / std::max<uint32_t>(1, options.leaf_size / 2) + 2);
    tree.nodes.resize(1);
    build_node(tree, 0, 0, static_cast<uint32_t>(tree.tris.size()),
               std::max<uint32_t>(1, options.leaf_size));
  }
  return forest;
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
