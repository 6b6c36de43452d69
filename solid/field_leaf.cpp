#include "cover/solid/field_leaf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_map>

#include "cover/solid/vec3_hash.h"

namespace cover {

Bbox primitive_support_box(const FieldPrimitive& prim) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Bbox box;
  if (prim.points.empty()) return box;
  const bool circle = prim.kind == SkeletonKind::kCircle;
  // Each rounded sum is within half an ulp; one step outward after each covers it. A mesh
  // skeleton's g > 0 inside M and within R − r_T of ∂M outside (its pseudo-distance < R).
  const double grow = circle ? std::nextafter(prim.circle_radius + prim.influence, kInf)
                      : prim.kind == SkeletonKind::kMesh
                          ? std::nextafter(prim.influence - prim.radius, kInf)
                          : prim.influence;
  Bbox skeleton;
  if (circle)
    skeleton.add(prim.points[0]);
  else
    for (const Vec3& p : prim.points) skeleton.add(p);
  const Vec3 lo = skeleton.min, hi = skeleton.max;
  box.add(Vec3{std::nextafter(lo.x - grow, -kInf), std::nextafter(lo.y - grow, -kInf),
               std::nextafter(lo.z - grow, -kInf)});
  box.add(Vec3{std::nextafter(hi.x + grow, kInf), std::nextafter(hi.y + grow, kInf),
               std::nextafter(hi.z + grow, kInf)});
  return box;
}

namespace {

/// Median split on the longest axis of the centroids' box (centroids compared as sums, exact
/// enough for ordering: any order gives a correct hierarchy), leaves of at most 4 triangles.
void build(const std::vector<Vec3>& points, std::vector<SkeletonMeshIndex::Node>& nodes,
           std::vector<uint32_t>& order, uint32_t first, uint32_t count) {
  const uint32_t id = static_cast<uint32_t>(nodes.size());
  nodes.emplace_back();
  Bbox box, centres;
  for (uint32_t i = first; i < first + count; ++i) {
    const uint32_t t = order[i];
    for (int k = 0; k < 3; ++k) box.add(points[3 * size_t{t} + k]);
    centres.add(points[3 * size_t{t}] + points[3 * size_t{t} + 1] + points[3 * size_t{t} + 2]);
  }
  nodes[id].box = box;
  if (count <= 4) {
    nodes[id].first = first;
    nodes[id].count = count;
    return;
  }
  const Vec3 extent = centres.max - centres.min;
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t half = count / 2;
  auto key = [&](uint32_t t) {
    return points[3 * size_t{t}][axis] + points[3 * size_t{t} + 1][axis] +
           points[3 * size_t{t} + 2][axis];
  };
  std::nth_element(
      order.begin() + first, order.begin() + first + half, order.begin() + first + count,
      [&](uint32_t a, uint32_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
  build(points, nodes, order, first, half);
  nodes[id].right = static_cast<uint32_t>(nodes.size());
  build(points, nodes, order, first + half, count - half);
}

std::string coordinates(const Vec3& v) {
  std::string out = "(";
  out += std::to_string(v.x);
  out += ", ";
  out += std::to_string(v.y);
  out += ", ";
  out += std::to_string(v.z);
  out += ")";
  return out;
}

}  // namespace

std::shared_ptr<const SkeletonMeshIndex> index_skeleton_mesh(const std::vector<Vec3>& points) {
  auto index = std::make_shared<SkeletonMeshIndex>();
  const uint32_t triangles = static_cast<uint32_t>(points.size() / 3);
  index->order.resize(triangles);
  std::iota(index->order.begin(), index->order.end(), 0u);
  if (triangles > 0) build(points, index->nodes, index->order, 0, triangles);
  // Closedness: +1 for each directed edge, −1 for each reversed one, per unordered pair.
  struct PairHash {
    size_t operator()(const std::pair<Vec3, Vec3>& e) const {
      return detail::Vec3Hash{}(e.first) * 31 + detail::Vec3Hash{}(e.second);
    }
  };
  std::unordered_map<std::pair<Vec3, Vec3>, int64_t, PairHash> balance;
  balance.reserve(points.size());
  for (size_t t = 0; t < triangles; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = points[3 * t + k], &b = points[3 * t + (k + 1) % 3];
      if (std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z))
        ++balance[{a, b}];
      else
        --balance[{b, a}];
    }
  for (size_t t = 0; t < triangles && index->open_edge.empty(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = points[3 * t + k], &b = points[3 * t + (k + 1) % 3];
      const bool forward = std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
      if (balance[forward ? std::pair{a, b} : std::pair{b, a}] != 0) {
        index->open_edge = "triangle " + std::to_string(t) + ": edge " + coordinates(a) + " -> " +
                           coordinates(b) + " has no opposite";
        break;
      }
    }
  return index;
}

Bbox field_support_box(const FieldLeaf& leaf) {
  Bbox box;
  for (const FieldPrimitive& prim : leaf.primitives)
    if (prim.weight > 0) box.add(primitive_support_box(prim));
  return box;
}

}  // namespace cover
