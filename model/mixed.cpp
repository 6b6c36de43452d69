// Mixed evaluation (detail/mixed.h).

#include "cover/model/detail/mixed.h"

#include <algorithm>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cover/covering/prepared.h"
#include "cover/field/field.h"
#include "cover/polygonize/polygonize.h"
#include "cover/solid/primitives.h"
#include "cover/solid/vec3_hash.h"

namespace cover::detail {
namespace {

/// Per leaf, true when its faces are stored reversed in the combined covering (an odd number of
/// complements and subtrahend positions above it): solid/solid.h's face_sign of its faces.
std::vector<uint8_t> reversed_leaves(const Solid& s) {
  std::vector<uint8_t> reversed(s.leaves.size(), 0);
  if (s.tree.nodes.empty()) return reversed;
  std::vector<std::pair<uint32_t, uint8_t>> stack{{s.tree.root, 0}};
  while (!stack.empty()) {
    const auto [node, odd] = stack.back();
    stack.pop_back();
    const CsgNode& n = s.tree.nodes[node];
    if (n.op == CsgOp::kLeaf) {
      reversed[n.leaf] = odd;
      continue;
    }
    for (size_t c = 0; c < n.children.size(); ++c) {
      const bool flip = n.op == CsgOp::kComplement || (n.op == CsgOp::kDifference && c > 0);
      stack.emplace_back(n.children[c], static_cast<uint8_t>(odd ^ flip));
    }
  }
  return reversed;
}

/// The leaf alone, as a solid of one leaf.
Solid single_leaf(const Solid& s, uint32_t l) {
  const Leaf& leaf = s.leaves[l];
  if (leaf.is_field()) return make_field_leaf(s.fields[leaf.field], leaf.name, leaf.origin);
  if (leaf.is_warp()) return make_warp_leaf(s.warps[leaf.warp], leaf.bbox, leaf.name, leaf.origin);
  Solid one = make_leaf(leaf_mesh(s, l), leaf.name, leaf.origin);
  one.leaves[0].boundary_edges = leaf.boundary_edges;
  return one;
}

bool curved(const Leaf& l) { return l.is_implicit() || l.open(); }

bool meet(const Bbox& a, const Bbox& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

/// A mesh skeleton's triangle soup welded into a mesh (equal coordinates, one vertex).
PolygonMesh welded(const FieldPrimitive& prim) {
  PolygonMesh m;
  std::unordered_map<Vec3, uint32_t, Vec3Hash> index;
  for (const Vec3& p : prim.points) {
    const auto [it, fresh] = index.try_emplace(p, static_cast<uint32_t>(m.vertices.size()));
    if (fresh) m.vertices.push_back(p);
    m.face_vertices.push_back(it->second);
    if (m.face_vertices.size() % 3 == 0)
      m.face_start.push_back(static_cast<uint32_t>(m.face_vertices.size()));
  }
  return m;
}

/// A blend with mesh skeletons (solid/field_leaf.h kMesh), the mesh kept exact where it alone
/// decides: with Q the union of every other primitive's support box and of the overlaps of two
/// mesh skeletons' support boxes, at most one mesh primitive has g > 0 outside Q, so the leaf
/// there is the union of its positive meshes M_k (f > T ⇔ p ∈ M_k when their thresholds equal
/// the leaf's, exactly). The leaf is ((∪ M_k) − Q) ∪ (L ∩ Q): L polygonized over Q's box only, at
/// the step the whole leaf would get, and the exact Booleans join them. Nothing when the leaf
/// has no mesh skeleton or its primitives' thresholds differ (the transform rounded them).
std::optional<PolygonizeResult> mesh_with_exact_skeletons(const Solid& s, uint32_t l,
                                                          const PolygonizeOptions& options) {
  const Leaf& leaf = s.leaves[l];
  if (!leaf.is_field()) return std::nullopt;
  const FieldLeaf& f = s.fields[leaf.field];
  const auto is_mesh = [](const FieldPrimitive& p) { return p.kind == SkeletonKind::kMesh; };
  if (std::none_of(f.primitives.begin(), f.primitives.end(), is_mesh) ||
      !field::validate(f).empty())
    return std::nullopt;
  std::vector<Solid> q, meshes;
  Bbox q_box;
  for (size_t i = 0; i < f.primitives.size(); ++i) {
    const FieldPrimitive& a = f.primitives[i];
    const Bbox ba = primitive_support_box(a);
    if (!is_mesh(a)) {
      q.push_back(make_leaf(make_box(ba.min, ba.max), "Q"));
      q_box.add(ba);
      continue;
    }
    if (a.weight > 0) meshes.push_back(make_leaf(welded(a), leaf.name));
    for (size_t j = i + 1; j < f.primitives.size(); ++j) {
      const Bbox bb = primitive_support_box(f.primitives[j]);
      if (!is_mesh(f.primitives[j]) || !meet(ba, bb)) continue;
      const Vec3 lo{std::max(ba.min.x, bb.min.x), std::max(ba.min.y, bb.min.y),
                    std::max(ba.min.z, bb.min.z)};
      const Vec3 hi{std::min(ba.max.x, bb.max.x), std::min(ba.max.y, bb.max.y),
                    std::min(ba.max.z, bb.max.z)};
      if (lo.x < hi.x && lo.y < hi.y && lo.z < hi.z) {
        q.push_back(make_leaf(make_box(lo, hi), "Q"));
        q_box.add(Bbox{lo, hi});
      } else {
        // Boxes touching in a face, edge or corner: Q must still hold the contact; the whole
        // of the smaller box is simplest.
        const Bbox& small = ba.max.x - ba.min.x < bb.max.x - bb.min.x ? ba : bb;
        q.push_back(make_leaf(make_box(small.min, small.max), "Q"));
        q_box.add(small);
      }
    }
  }
  PolygonizeResult out;
  Solid exact = meshes.empty() ? Solid{} : unite(std::move(meshes));
  Solid whole;
  if (q.empty()) {
    whole = std::move(exact);
  } else {
    const Bbox& lb = leaf.bbox;
    const Vec3 e = lb.max - lb.min;
    PolygonizeOptions po = options;
    if (po.cell_size <= 0) po.cell_size = std::max({e.x, e.y, e.z}) / options.resolution;
    const Solid one = single_leaf(s, l);
    const Prepared prepared(one);
    const Bbox region{{std::max(q_box.min.x, lb.min.x), std::max(q_box.min.y, lb.min.y),
                       std::max(q_box.min.z, lb.min.z)},
                      {std::min(q_box.max.x, lb.max.x), std::min(q_box.max.y, lb.max.y),
                       std::min(q_box.max.z, lb.max.z)}};
    out = polygonize(prepared, region, po);
    out.clipped = 0;  // the region cuts L on purpose: Q cuts it again below
    Solid region_q = unite(std::move(q));
    std::vector<Solid> parts;
    if (!exact.leaves.empty()) parts.push_back(subtract({std::move(exact), region_q}));
    if (out.mesh.face_count() > 0)
      parts.push_back(intersect({make_leaf(std::move(out.mesh), leaf.name), region_q}));
    if (parts.empty()) {
      out.mesh = {};
      return out;
    }
    whole = unite(std::move(parts));
  }
  out.mesh = whole.leaves.empty() ? PolygonMesh{} : evaluate(whole, {}).mesh;
  return out;
}

}  // namespace

MeshedSolid mesh_curved_leaves(const Solid& s, const EvaluateOptions& options) {
  MeshedSolid out;
  const std::vector<uint8_t> reversed = reversed_leaves(s);
  PolygonizeOptions po;
  po.resolution = options.mesh_resolution;
  po.tolerance = options.mesh_tolerance;
  Solid& r = out.solid;
  r.tree = s.tree;
  r.leaves.reserve(s.leaves.size());
  for (uint32_t l = 0; l < s.leaves.size(); ++l) {
    const Leaf& from = s.leaves[l];
    Leaf leaf = from;
    leaf.field = leaf.warp = -1;
    leaf.boundary_edges = 0;
    leaf.first_face = static_cast<uint32_t>(r.face_count());
    leaf.first_vertex = static_cast<uint32_t>(r.vertices.size());
    const auto base = leaf.first_vertex;
    if (!curved(from)) {  // copied as stored (combined orientation and signs kept)
      r.vertices.insert(r.vertices.end(), s.vertices.begin() + from.first_vertex,
                        s.vertices.begin() + from.first_vertex + from.vertex_count);
      for (uint32_t f = from.first_face; f < from.first_face + from.face_count; ++f) {
        for (uint32_t v : s.face(f)) r.face_vertices.push_back(v - from.first_vertex + base);
        r.face_start.push_back(static_cast<uint32_t>(r.face_vertices.size()));
        r.face_leaf.push_back(l);
        r.face_sign.push_back(s.face_sign[f]);
      }
      r.leaves.push_back(std::move(leaf));
      continue;
    }
    std::optional<PolygonizeResult> skeletal = mesh_with_exact_skeletons(s, l, po);
    PolygonizeResult p;
    if (skeletal) {
      p = std::move(*skeletal);
    } else {
      const Solid one = single_leaf(s, l);
      const Prepared prepared(one);
      p = polygonize(prepared, from.bbox, po);
    }
    out.meshed.push_back(
        {l, p.mesh.face_count(), p.cell_size, p.tolerance, p.uncertain, p.clipped});
    r.vertices.insert(r.vertices.end(), p.mesh.vertices.begin(), p.mesh.vertices.end());
    const int8_t sign = reversed[l] ? -1 : 1;
    for (size_t f = 0; f < p.mesh.face_count(); ++f) {
      const auto face = p.mesh.face(f);
      const size_t at = r.face_vertices.size();
      for (uint32_t v : face) r.face_vertices.push_back(v + base);
      if (reversed[l]) std::reverse(r.face_vertices.begin() + at, r.face_vertices.end());
      r.face_start.push_back(static_cast<uint32_t>(r.face_vertices.size()));
      r.face_leaf.push_back(l);
      r.face_sign.push_back(sign);
    }
    leaf.face_count = static_cast<uint32_t>(p.mesh.face_count());
    leaf.vertex_count = static_cast<uint32_t>(p.mesh.vertices.size());
    leaf.bbox = face_bbox(p.mesh);
    r.leaves.push_back(std::move(leaf));
  }
  return out;
}

EvaluateResult evaluate_mixed(const Solid& s, const EvaluateOptions& options) {
  if (!s.has_open_leaf() && !s.has_implicit_leaf()) return evaluate(s, options);
  MeshedSolid m = mesh_curved_leaves(s, options);
  EvaluateResult r = evaluate(m.solid, options);
  r.meshed = std::move(m.meshed);
  for (const MeshedLeaf& l : r.meshed) r.tolerance = std::max(r.tolerance, l.tolerance);
  return r;
}

}  // namespace cover::detail
