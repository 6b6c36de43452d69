#include "cover/covering/volume.h"

#include <cmath>
#include <numeric>
#include <optional>

#include "cover/covering/bounds.h"
#include "cover/covering/detail/ray_volume.h"
#include "cover/covering/ray.h"
#include "cover/mesh/validate.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

constexpr size_t kFaceGrain = 4096;  // faces per chunk: fixed, so sums are thread-independent

/// Why the leaf's winding number can exceed 1 (empty when it cannot).
std::optional<std::string> leaf_not_simple(const Solid& solid, uint32_t l) {
  const PolygonMesh mesh = leaf_mesh(solid, l);
  const std::string name = solid.leaves[l].name;
  if (self_intersects(mesh)) return name + " is self-intersecting";
  ValidateOptions vo;
  vo.check_self_intersection = false;
  const MeshReport report = validate_mesh(mesh, vo);
  if (report.components > 1)
    return name + " has " + std::to_string(report.components) +
           " shells (nesting not analysed for the covering volume)";
  return std::nullopt;
}

Bbox node_box(const Solid& s, uint32_t node) {
  const CsgNode& n = s.tree.nodes[node];
  if (n.op == CsgOp::kLeaf) return s.leaves[n.leaf].bbox;
  Bbox box;
  for (uint32_t c : n.children) box.add(node_box(s, c));
  return box;
}

/// Collects the leaves whose covering volumes add up to the node's volume; returns why there
/// are none when the covering is not exact for this node (rules in volume.h).
std::optional<std::string> collect(const Solid& s, uint32_t node, std::vector<uint32_t>& leaves) {
  const CsgNode& n = s.tree.nodes[node];
  switch (n.op) {
    case CsgOp::kLeaf:
      if (auto why = leaf_not_simple(s, n.leaf)) return why;
      leaves.push_back(n.leaf);
      return std::nullopt;
    case CsgOp::kComplement:
      return std::string("a complement below the root");
    case CsgOp::kUnion:
      for (size_t i = 0; i < n.children.size(); ++i) {
        for (size_t j = 0; j < i; ++j)
          if (node_box(s, n.children[i]).interiors_overlap(node_box(s, n.children[j])))
            return std::string("union operands overlap");
        if (auto why = collect(s, n.children[i], leaves)) return why;
      }
      return std::nullopt;
    case CsgOp::kDifference:
      for (size_t i = 1; i < n.children.size(); ++i)
        if (node_box(s, n.children[i]).interiors_overlap(node_box(s, n.children[0])))
          return std::string("a subtracted operand overlaps the first");
      return collect(s, n.children[0], leaves);
    case CsgOp::kIntersection:
      if (n.children.size() == 1) return collect(s, n.children[0], leaves);
      return std::string("intersection of overlapping operands");
  }
  return std::string("unknown node");
}

/// True when the intersection node is empty because two operand boxes share no interior.
bool empty_intersection(const Solid& s, uint32_t node) {
  const CsgNode& n = s.tree.nodes[node];
  if (n.op != CsgOp::kIntersection || n.children.size() < 2) return false;
  for (size_t i = 0; i < n.children.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (!node_box(s, n.children[i]).interiors_overlap(node_box(s, n.children[j]))) return true;
  return false;
}

/// Sum over faces of one covering measure, chunked for determinism.
template <typename PerFace>
double face_sum(const Solid& s, PerFace per_face) {
  const size_t faces = s.face_count();
  const size_t chunks = (faces + kFaceGrain - 1) / kFaceGrain;
  std::vector<NeumaierSum> partial(chunks);
  parallel_for(faces, kFaceGrain, [&](size_t begin, size_t end) {
    NeumaierSum& sum = partial[begin / kFaceGrain];
    for (size_t f = begin; f < end; ++f) per_face(f, sum);
  });
  NeumaierSum total;
  for (const NeumaierSum& p : partial) total.add(p);
  return total.value();
}

VolumeResult ray_volume(const Solid& s, const Bvh* prebuilt, const VolumeOptions& options) {
  const std::optional<Bbox> box = result_bounds(s);
  if (!box) throw NotComputable("the result is unbounded (a complement at the root)");
  VolumeResult r;
  r.method = "rays";
  r.target_met = true;
  if (box->empty() || box->min.x >= box->max.x || box->min.y >= box->max.y ||
      box->min.z >= box->max.z)
    return r;  // operands' boxes share no interior: empty result
  std::optional<Bvh> own;
  const Bvh& bvh = prebuilt ? *prebuilt : own.emplace(s);
  detail::RayVolumeOptions ro;
  ro.target_relative_error = options.target_relative_error;
  ro.max_rays = options.max_rays;
  ro.progress = options.progress;
  if (options.rays > 0) ro.fixed_level = static_cast<int>(std::ceil(std::log2(options.rays)));
  const detail::RayVolume v = detail::ray_volume(s, bvh, *box, ro);
  r.volume = v.volume;
  r.error_bound = v.error_bound;
  r.rays = v.rays;
  r.target_met = v.target_met;
  return r;
}

}  // namespace

double covering_volume(const Solid& s) {
  const Bbox box = s.bbox();
  const Vec3 o = box.empty() ? Vec3{} : 0.5 * (box.min + box.max);
  return face_sum(s, [&](size_t f, NeumaierSum& sum) {
    auto face = s.face(f);
    if (face.size() < 3) return;
    const Vec3 a = s.vertices[face[0]] - o;
    for (size_t i = 1; i + 1 < face.size(); ++i)
      sum.add(dot(a, cross(s.vertices[face[i]] - o, s.vertices[face[i + 1]] - o)) / 6.0);
  });
}

std::optional<std::string> covering_inexact_reason(const Solid& s) {
  std::vector<uint32_t> leaves;
  if (s.tree.nodes.empty() || empty_intersection(s, s.tree.root)) return std::nullopt;
  return collect(s, s.tree.root, leaves);
}

namespace {

/// volume() with the BVH of the ray method when prebuilt (else built there if needed).
VolumeResult volume_with(const Solid& s, const Bvh* bvh, const VolumeOptions& options) {
  if (!is_bounded(s)) throw NotComputable("the result is unbounded (a complement at the root)");
  VolumeResult r;
  r.method = "covering";
  if (s.tree.nodes.empty() || empty_intersection(s, s.tree.root)) {  // no leaf: the empty set
    r.volume = 0;
    r.area = 0;
    return r;
  }
  std::vector<uint32_t> leaves;
  if (auto why = collect(s, s.tree.root, leaves)) {
    if (options.exact)
      throw NotComputable("the covering volume is not exact for this expression (" + *why +
                          "); evaluate() gives the exact volume of its B-rep");
    return ray_volume(s, bvh, options);
  }
  // Σ of the contributing leaves' covering volumes (each in its own, outward orientation).
  NeumaierSum vol, area;
  bool additive = true;  // area adds up when no two contributing leaves' closed boxes touch
  for (size_t i = 0; i < leaves.size(); ++i) {
    const PolygonMesh mesh = leaf_mesh(s, leaves[i]);
    vol.add(signed_volume(mesh));
    area.add(surface_area(mesh));
    const Bbox& a = s.leaves[leaves[i]].bbox;
    for (size_t j = 0; j < i; ++j) {
      const Bbox& b = s.leaves[leaves[j]].bbox;
      additive = additive && (a.max.x < b.min.x || b.max.x < a.min.x || a.max.y < b.min.y ||
                              b.max.y < a.min.y || a.max.z < b.min.z || b.max.z < a.min.z);
    }
  }
  r.volume = vol.value();
  if (additive) r.area = area.value();
  return r;
}

}  // namespace

VolumeResult volume(const Solid& s, const VolumeOptions& options) {
  return volume_with(s, nullptr, options);
}

VolumeResult volume(const Solid& s, const Bvh& bvh, const VolumeOptions& options) {
  return volume_with(s, &bvh, options);
}

}  // namespace cover
