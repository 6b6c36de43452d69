#include "cover/covering/volume.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "cover/covering/bounds.h"
#include "cover/covering/classify.h"
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

VolumeResult ray_volume(const Prepared& prepared, const VolumeOptions& options) {
  const Solid& s = prepared.solid();
  const std::optional<Bbox> box = result_bounds(s);
  if (!box) throw NotComputable("the result is unbounded (a complement at the root)");
  VolumeResult r;
  r.method = "rays";
  r.target_met = true;
  if (box->empty() || box->min.x >= box->max.x || box->min.y >= box->max.y ||
      box->min.z >= box->max.z)
    return r;  // operands' boxes share no interior: empty result
  detail::RayVolumeOptions ro;
  ro.target_relative_error = options.target_relative_error;
  ro.max_rays = options.max_rays;
  ro.progress = options.progress;
  if (options.rays > 0) ro.fixed_level = static_cast<int>(std::ceil(std::log2(options.rays)));
  const detail::RayVolume v = detail::ray_volume(prepared, *box, ro);
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

/// volume() of closed leaves: the covering's value, else the ray method's.
VolumeResult closed_volume(const Prepared& prepared, const VolumeOptions& options) {
  const Solid& s = prepared.solid();
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
    return ray_volume(prepared, options);
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

/// Open leaves: the winding method. The centres of an n³ grid over the result's box (default
/// n = 128; options.rays > 0: n = rays, clamped to 2..1024), classified as classify() does:
/// volume = h³·(centres not outside); error bound = h³·(voxels whose class differs from a face
/// neighbour's, or on the grid's border while not outside): each voxel the region's boundary
/// crosses counts fully, assuming the grid resolves the boundary (no feature thinner than a
/// voxel between two centres of the same class).
VolumeResult winding_volume(const Prepared& prepared, const VolumeOptions& options) {
  VolumeResult r;
  r.method = "winding";
  const std::optional<Bbox> box = result_bounds(prepared.solid());
  if (!box) throw NotComputable("volume: the result is unbounded (a complement at the root)");
  if (box->empty()) return r;
  const int n = options.rays > 0 ? std::clamp(options.rays, 2, 1024) : 128;
  const VoxelLattice lattice = cubic_lattice(default_voxel_bounds(*box, n), n);
  // One bit per centre, (i·n + j)·n + k.
  std::vector<uint64_t> bits((static_cast<size_t>(n) * n * n + 63) / 64, 0);
  const auto at = [n](int i, int j, int k) {
    return (static_cast<size_t>(i) * n + j) * n + static_cast<size_t>(k);
  };
  classify_lattice(prepared, lattice, whole_box(lattice), [&](int i, int j, int k) {
    const size_t b = at(i, j, k);
    bits[b / 64] |= uint64_t{1} << (b % 64);
  });
  const auto get = [&](int i, int j, int k) {
    const size_t b = at(i, j, k);
    return (bits[b / 64] >> (b % 64) & 1) != 0;
  };
  const double h3 = lattice.spacing * lattice.spacing * lattice.spacing;
  size_t in = 0, border = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const bool v = get(i, j, k);
        in += v;
        bool differs = false;
        const int nb[6][3] = {{i - 1, j, k}, {i + 1, j, k}, {i, j - 1, k},
                              {i, j + 1, k}, {i, j, k - 1}, {i, j, k + 1}};
        for (const auto& q : nb) {
          if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n || q[1] >= n || q[2] >= n) {
            differs |= v;
            continue;
          }
          differs |= get(q[0], q[1], q[2]) != v;
        }
        border += differs;
      }
  r.volume = h3 * static_cast<double>(in);
  r.error_bound = h3 * static_cast<double>(border);
  r.rays = static_cast<size_t>(n) * n * n;  // points classified
  r.target_met = r.error_bound <= options.target_relative_error * std::abs(r.volume);
  return r;
}

}  // namespace

namespace detail {
VolumeResult bracket_volume(const Prepared& prepared, const VolumeOptions& options);
}  // namespace detail

VolumeResult volume(const Prepared& prepared, const VolumeOptions& options) {
  const Solid& s = prepared.solid();
  // Curved solids have no exact volume in doubles: options.exact takes the bracket too, whose
  // certified bound settles mesh leaves exactly inside it (open leaves: by their closures).
  if (s.has_implicit_leaf()) return detail::bracket_volume(prepared, options);
  if (s.has_open_leaf()) {
    if (options.exact)
      throw InputError(s.open_leaf_message() +
                       ": no exact volume; the winding method estimates it (without " +
                       parameter("exact") + ")");
    return winding_volume(prepared, options);
  }
  return closed_volume(prepared, options);
}

VolumeResult volume(const Solid& s, const VolumeOptions& options) {
  const Prepared prepared(s);
  return volume(prepared, options);
}

}  // namespace cover
