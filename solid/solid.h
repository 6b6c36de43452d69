#pragma once
// The non-evaluated solid ([Segura2004 §3–§4]; docs/design.md#data-flow).
//
// Notation
//   V        vertex array shared by every leaf (doubles, transforms already applied)
//   face f   signed index list; face_sign[f] = +1 when the list is in its leaf's own orientation,
//            −1 when complement/difference reversed it. The stored order is always the
//            orientation of the *combined* covering, so Σ over stored faces of the covering
//            tetrahedra = Σ_leaves c_L · w_L (c_L = ±1, w_L = winding number of leaf L).
//   leaf L   one closed mesh or primitive; faces [first_face, first_face + face_count) and
//            vertices [first_vertex, first_vertex + vertex_count) are contiguous.
//   tree     the CSG expression over leaf ids. Classification evaluates the tree on per-leaf
//            memberships (nonzero winding), which is right for any nesting; the paper's single
//            threshold on the summed covering value is right only for one operation.
//
// Union / difference / intersection / complement only concatenate faces and flip signs (§4).

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cover/solid/field_leaf.h"
#include "cover/solid/polygon_mesh.h"
#include "cover/solid/warp_leaf.h"

namespace cover {

enum class CsgOp : uint8_t { kLeaf, kUnion, kIntersection, kDifference, kComplement };

/// One node of the CSG tree. kLeaf nodes carry `leaf`; others carry `children` (node indices).
/// kDifference: first child minus all the others. kComplement: exactly one child.
struct CsgNode {
  CsgOp op = CsgOp::kLeaf;
  uint32_t leaf = 0;
  std::vector<uint32_t> children;
};

/// Expression tree stored as a node array; `root` indexes `nodes`.
struct CsgTree {
  std::vector<CsgNode> nodes;
  uint32_t root = 0;

  /// Evaluates membership given each leaf's membership (inside[leaf]). A tree with no node (the
  /// Solid with no leaf) is the empty set: false.
  bool evaluate(std::span<const uint8_t> inside) const {
    return !nodes.empty() && evaluate(root, inside);
  }
  bool evaluate(uint32_t node, std::span<const uint8_t> inside) const;
  /// evaluate() for every set of inside leaves among `leaves` (bit l of the index: leaf l
  /// inside), 2^leaves entries: a sweep looks a winding mask up instead of walking the tree.
  std::vector<uint8_t> truth_table(size_t leaves) const;
};

/// Per-leaf bookkeeping. `name` is the mesh path or primitive kind, `origin` the scene JSON
/// path of the leaf (empty for a plain mesh input).
struct Leaf {
  std::string name;
  std::string origin;
  uint32_t first_face = 0, face_count = 0;
  uint32_t first_vertex = 0, vertex_count = 0;
  Bbox bbox;
  bool flipped = false;  ///< the input was inside-out and its faces were reversed on load
  /// RGB from the scene's "color" on this leaf's node or its nearest ancestor that has one;
  /// none: the renderer's leaf_colour (render/render.h display_colour).
  std::optional<std::array<uint8_t, 3>> colour;
  /// Boundary edges of the leaf as loaded (mesh/validate.h). 0: a closed leaf, inside by the
  /// exact nonzero rule; > 0: an open leaf, inside where its generalized winding number has
  /// |w| > 1/2 (covering/gwn.h). Only what the loader found: serialize keeps 0 / nonzero.
  int64_t boundary_edges = 0;
  bool open() const { return boundary_edges > 0; }
  /// A field leaf's index in Solid::fields; −1 for a mesh leaf. A field leaf has no faces and
  /// no vertices; its bbox is its support box (field/field.h support_box).
  int32_t field = -1;
  bool is_field() const { return field >= 0; }
  /// A warp leaf's index in Solid::warps; −1 otherwise. A warp leaf has no faces and no
  /// vertices; its bbox encloses the warped child (field/warp.h forward_box).
  int32_t warp = -1;
  bool is_warp() const { return warp >= 0; }
  /// A field or warp leaf: membership from a function of the point, not from faces.
  bool is_implicit() const { return field >= 0 || warp >= 0; }
};

/// A CSG solid with linear storage: vertices + signed faces tagged by leaf, and the tree.
/// A value type, cheap to move.
struct Solid {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> face_start{0};  ///< #F+1 offsets into face_vertices
  std::vector<uint32_t> face_vertices;  ///< concatenated index lists (combined orientation)
  std::vector<uint32_t> face_leaf;      ///< #F leaf id per face
  std::vector<int8_t> face_sign;        ///< #F ±1 (see notation above)
  std::vector<Leaf> leaves;
  std::vector<FieldLeaf> fields;  ///< the field leaves' blends (Leaf::field indexes it)
  std::vector<WarpLeaf> warps;    ///< the warp leaves (Leaf::warp indexes it)
  CsgTree tree;

  size_t face_count() const { return face_leaf.size(); }
  std::span<const uint32_t> face(size_t f) const {
    return {face_vertices.data() + face_start[f], face_start[f + 1] - face_start[f]};
  }
  Bbox bbox() const;
  /// True when some leaf is open (Leaf::open).
  bool has_open_leaf() const {
    for (const Leaf& l : leaves)
      if (l.open()) return true;
    return false;
  }
  /// "NAME: open mesh (N boundary edges)" for the first open leaf, the prefix of the refusals of
  /// what open leaves do not support; empty when every leaf is closed.
  std::string open_leaf_message() const;
  /// True when some leaf is a field leaf (Leaf::is_field).
  bool has_field_leaf() const { return !fields.empty(); }
  /// "ORIGIN: field leaf" (its JSON path, else its name) for the first field leaf, the prefix of
  /// the refusals of what field leaves do not support; empty when there is none.
  std::string field_leaf_message() const;
  /// True when some leaf is a field or a warp leaf (Leaf::is_implicit): the queries answer it
  /// by its membership function, the B-rep commands refuse it.
  bool has_implicit_leaf() const { return !fields.empty() || !warps.empty(); }
  /// "ORIGIN: field leaf" or "ORIGIN: warp leaf" for the first implicit leaf; empty when none.
  std::string implicit_leaf_message() const;
};

/// A solid with one leaf. Precondition: the mesh is closed and outward (callers validate).
Solid make_leaf(PolygonMesh mesh, std::string name, std::string origin = {});

/// A solid with one field leaf, its box the support box (field_support_box).
/// Precondition: the leaf is valid (field/field.h validate).
Solid make_field_leaf(FieldLeaf field, std::string name, std::string origin = {});

/// A solid with one warp leaf whose box is `box` (field/warp.h forward_box of the child's box).
/// Precondition: the warp is valid for its child (field/warp.h validate).
Solid make_warp_leaf(WarpLeaf warp, Bbox box, std::string name, std::string origin = {});

/// The leaf's faces in the leaf's OWN orientation, with its own vertex numbering (0-based).
PolygonMesh leaf_mesh(const Solid& solid, uint32_t leaf);

/// Complement ([Segura2004 §4]): every face reversed, every sign negated.
Solid complement(Solid a);
/// Union of one or more solids (concatenation).
/// \throws PreconditionError for no operands (also intersect(), subtract()).
Solid unite(std::vector<Solid> parts);
/// Intersection of one or more solids (concatenation; De Morgan keeps the signs).
Solid intersect(std::vector<Solid> parts);
/// parts[0] minus parts[1..] (concatenation with the subtrahends reversed).
Solid subtract(std::vector<Solid> parts);

}  // namespace cover
