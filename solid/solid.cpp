#include "cover/solid/solid.h"

#include <algorithm>
#include <stdexcept>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover {

std::vector<uint8_t> CsgTree::truth_table(size_t leaves) const {
  std::vector<uint8_t> table(size_t{1} << leaves), inside(leaves);
  for (size_t mask = 0; mask < table.size(); ++mask) {
    for (size_t l = 0; l < leaves; ++l) inside[l] = (mask >> l) & 1;
    table[mask] = evaluate(inside);
  }
  return table;
}

bool CsgTree::evaluate(uint32_t node, std::span<const uint8_t> inside) const {
  const CsgNode& n = nodes[node];
  switch (n.op) {
    case CsgOp::kLeaf:
      return inside[n.leaf] != 0;
    case CsgOp::kComplement:
      return !evaluate(n.children[0], inside);
    case CsgOp::kUnion:
      return std::any_of(n.children.begin(), n.children.end(),
                         [&](uint32_t c) { return evaluate(c, inside); });
    case CsgOp::kIntersection:
      return std::all_of(n.children.begin(), n.children.end(),
                         [&](uint32_t c) { return evaluate(c, inside); });
    case CsgOp::kDifference:
      if (!evaluate(n.children[0], inside)) return false;
      return std::none_of(n.children.begin() + 1, n.children.end(),
                          [&](uint32_t c) { return evaluate(c, inside); });
  }
  return false;
}

std::string Solid::open_leaf_message() const {
  for (const Leaf& l : leaves)
    if (l.open())
      return l.name + ": open mesh (" + std::to_string(l.boundary_edges) + " boundary edges)";
  return {};
}

std::string Solid::field_leaf_message() const {
  for (const Leaf& l : leaves)
    if (l.is_field()) return (l.origin.empty() ? l.name : l.origin) + ": field leaf";
  return {};
}

std::string Solid::implicit_leaf_message() const {
  for (const Leaf& l : leaves)
    if (l.is_implicit())
      return (l.origin.empty() ? l.name : l.origin) +
             (l.is_field() ? ": field leaf" : ": warp leaf");
  return {};
}

Bbox Solid::bbox() const {
  Bbox box;
  for (const Leaf& leaf : leaves) box.add(leaf.bbox);
  return box;
}

Solid make_leaf(PolygonMesh mesh, std::string name, std::string origin) {
  Solid s;
  Leaf leaf;
  leaf.name = std::move(name);
  leaf.origin = std::move(origin);
  leaf.face_count = static_cast<uint32_t>(mesh.face_count());
  leaf.vertex_count = static_cast<uint32_t>(mesh.vertices.size());
  leaf.bbox = face_bbox(mesh);
  s.vertices = std::move(mesh.vertices);
  s.face_start = std::move(mesh.face_start);
  s.face_vertices = std::move(mesh.face_vertices);
  s.face_leaf.assign(leaf.face_count, 0);
  s.face_sign.assign(leaf.face_count, 1);
  s.leaves.push_back(std::move(leaf));
  s.tree.nodes.push_back(CsgNode{CsgOp::kLeaf, 0, {}});
  s.tree.root = 0;
  return s;
}

namespace {

/// A solid of one leaf without faces (a field or warp leaf: `leaf` says which).
Solid faceless_leaf(Leaf leaf, std::string name, std::string origin) {
  Solid s;
  leaf.name = std::move(name);
  leaf.origin = std::move(origin);
  s.leaves.push_back(std::move(leaf));
  s.tree.nodes.push_back(CsgNode{CsgOp::kLeaf, 0, {}});
  s.tree.root = 0;
  return s;
}

}  // namespace

Solid make_field_leaf(FieldLeaf field, std::string name, std::string origin) {
  Leaf leaf;
  leaf.bbox = field_support_box(field);
  leaf.field = 0;
  Solid s = faceless_leaf(std::move(leaf), std::move(name), std::move(origin));
  s.fields.push_back(std::move(field));
  return s;
}

Solid make_warp_leaf(WarpLeaf warp, Bbox box, std::string name, std::string origin) {
  Leaf leaf;
  leaf.bbox = box;
  leaf.warp = 0;
  Solid s = faceless_leaf(std::move(leaf), std::move(name), std::move(origin));
  s.warps.push_back(std::move(warp));
  return s;
}

PolygonMesh leaf_mesh(const Solid& solid, uint32_t leaf_id) {
  const Leaf& leaf = solid.leaves.at(leaf_id);
  PolygonMesh m;
  m.vertices.assign(solid.vertices.begin() + leaf.first_vertex,
                    solid.vertices.begin() + leaf.first_vertex + leaf.vertex_count);
  std::vector<uint32_t> loop;
  for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f) {
    auto face = solid.face(f);
    loop.assign(face.begin(), face.end());
    for (uint32_t& v : loop) v -= leaf.first_vertex;
    if (solid.face_sign[f] < 0) std::reverse(loop.begin(), loop.end());
    m.add_face(loop);
  }
  return m;
}

Solid complement(Solid a) {
  for (size_t f = 0; f < a.face_count(); ++f) {
    std::reverse(a.face_vertices.begin() + a.face_start[f],
                 a.face_vertices.begin() + a.face_start[f + 1]);
    a.face_sign[f] = static_cast<int8_t>(-a.face_sign[f]);
  }
  CsgNode node{CsgOp::kComplement, 0, {a.tree.root}};
  a.tree.nodes.push_back(std::move(node));
  a.tree.root = static_cast<uint32_t>(a.tree.nodes.size() - 1);
  return a;
}

namespace {

/// Concatenates parts ([Segura2004 §4] union) and roots them under a new node of kind `op`.
/// Reverses the faces of parts[1..] when `flip_rest` (difference). The arrays are reserved once
/// for all parts (so no part is copied twice or into fresh memory again) and filled in parallel
/// chunks (each element on its own: the same for any threads).
Solid concatenate(std::vector<Solid> parts, CsgOp op, bool flip_rest) {
  if (parts.empty()) throw PreconditionError("CSG operation without operands");
  Solid out = std::move(parts[0]);
  std::vector<uint32_t> roots{out.tree.root};
  size_t vertices = out.vertices.size(), indices = out.face_vertices.size(),
         faces = out.face_count();
  for (size_t p = 1; p < parts.size(); ++p) {
    vertices += parts[p].vertices.size();
    indices += parts[p].face_vertices.size();
    faces += parts[p].face_count();
  }
  out.vertices.reserve(vertices);
  out.face_vertices.reserve(indices);
  out.face_start.reserve(faces + 1);
  out.face_leaf.reserve(faces);
  out.face_sign.reserve(faces);
  constexpr size_t kGrain = size_t{1} << 16;
  for (size_t p = 1; p < parts.size(); ++p) {
    Solid& s = parts[p];
    const size_t nf = s.face_count();
    if (flip_rest) {
      parallel_for(nf, kGrain, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f) {
          std::reverse(s.face_vertices.begin() + s.face_start[f],
                       s.face_vertices.begin() + s.face_start[f + 1]);
          s.face_sign[f] = static_cast<int8_t>(-s.face_sign[f]);
        }
      });
    }
    const auto v_off = static_cast<uint32_t>(out.vertices.size());
    const auto f_off = static_cast<uint32_t>(out.face_count());
    const auto l_off = static_cast<uint32_t>(out.leaves.size());
    const auto n_off = static_cast<uint32_t>(out.tree.nodes.size());
    const auto i_off = static_cast<uint32_t>(out.face_vertices.size());
    out.vertices.insert(out.vertices.end(), s.vertices.begin(), s.vertices.end());
    out.face_sign.insert(out.face_sign.end(), s.face_sign.begin(), s.face_sign.end());
    out.face_vertices.resize(i_off + s.face_vertices.size());
    parallel_for(s.face_vertices.size(), kGrain, [&](size_t begin, size_t end) {
      for (size_t k = begin; k < end; ++k)
        out.face_vertices[i_off + k] = s.face_vertices[k] + v_off;
    });
    out.face_start.resize(f_off + 1 + nf);
    out.face_leaf.resize(f_off + nf);
    parallel_for(nf, kGrain, [&](size_t begin, size_t end) {
      for (size_t f = begin; f < end; ++f) {
        out.face_start[f_off + 1 + f] = s.face_start[f + 1] + i_off;
        out.face_leaf[f_off + f] = s.face_leaf[f] + l_off;
      }
    });
    const auto fl_off = static_cast<int32_t>(out.fields.size());
    for (FieldLeaf& field : s.fields) out.fields.push_back(std::move(field));
    const auto wl_off = static_cast<int32_t>(out.warps.size());
    for (WarpLeaf& warp : s.warps) out.warps.push_back(std::move(warp));
    for (Leaf leaf : s.leaves) {
      leaf.first_face += f_off;
      leaf.first_vertex += v_off;
      if (leaf.is_field()) leaf.field += fl_off;
      if (leaf.is_warp()) leaf.warp += wl_off;
      out.leaves.push_back(std::move(leaf));
    }
    for (CsgNode node : s.tree.nodes) {
      if (node.op == CsgOp::kLeaf) node.leaf += l_off;
      for (uint32_t& c : node.children) c += n_off;
      out.tree.nodes.push_back(std::move(node));
    }
    roots.push_back(s.tree.root + n_off);
  }
  out.tree.nodes.push_back(CsgNode{op, 0, std::move(roots)});
  out.tree.root = static_cast<uint32_t>(out.tree.nodes.size() - 1);
  return out;
}

}  // namespace

Solid unite(std::vector<Solid> parts) {
  return concatenate(std::move(parts), CsgOp::kUnion, false);
}
Solid intersect(std::vector<Solid> parts) {
  return concatenate(std::move(parts), CsgOp::kIntersection, false);
}
Solid subtract(std::vector<Solid> parts) {
  return concatenate(std::move(parts), CsgOp::kDifference, true);
}

}  // namespace cover
