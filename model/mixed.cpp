// Mixed evaluation (detail/mixed.h).

#include "cover/model/detail/mixed.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "cover/covering/prepared.h"
#include "cover/polygonize/polygonize.h"

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
    const Solid one = single_leaf(s, l);
    const Prepared prepared(one);
    PolygonizeResult p = polygonize(prepared, from.bbox, po);
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
