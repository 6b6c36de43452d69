#pragma once
// A Solid as bytes and back: how a Model travels to other processes (Python pickling, Dask
// workers; docs/scale-out.md) without re-reading its files or re-applying transforms, so every
// process sees the same doubles and the same expression.
//
// Format (little-endian, version 1):
//   "COVERSOL" u32 version
//   u64 vertices, faces, face_vertices, leaves, nodes; u32 root
//   f64[3·vertices]  u32[faces + 1] face_start  u32[face_vertices]  u32[faces] face_leaf
//   i8[faces] face_sign
//   per leaf: u32 name bytes, name, u32 origin bytes, origin, u32 first_face, face_count,
//             first_vertex, vertex_count, u8 flags (1: flipped, 2: open; boxes are recomputed
//             on reading; 16: a colour, u8[3] RGB, follows)
//   per node: u8 op, u32 leaf, u32 children, u32[children]
// Version 2, written only for solids with field leaves (solid/field_leaf.h), adds leaf flag 4 (a
// field leaf: no faces, no vertices) and, after the nodes, per field leaf in leaf order:
//   u32 primitives; per primitive: u8 skeleton kind (0 point … 5 mesh), u32 points, f64[3·points]
//   (a mesh: its triangle soup),
//   f64 circle_radius, radius, influence, i32 exponent, i32 weight
// checked as field::validate_placed checks a leaf (its box is recomputed); and leaf flag 8 (a
// warp leaf: no faces, no vertices, solid/warp_leaf.h) with, after the fields, per warp leaf
// in leaf order:
//   u8 kind, f64[3] point, direction, toward, f64[9] frame rows, f64 degrees_per_unit,
//   range[2], scale[2], center, radius, u64 child bytes, the child as a solid in this format
// checked as field::validate checks a warp against its child's box (frame rows finite and
// orthonormal to 1e-6; children nested at most 64 deep); its box is recomputed.
// Reading checks everything a kernel relies on (solid.h notation), as loading checks a file:
//   layout     counts against the byte length before anything is allocated; offsets
//              non-decreasing and in range; every face at least 3 vertices; indices below their
//              counts; finite vertices within ±kMaxCoordinate; the leaves tiling the faces and
//              the vertices in order, each face tagged with its leaf and using its vertices.
//   tree       each node's operands before it with the arity of its operation, every node but
//              the root the operand of exactly one operation, each leaf in exactly one node;
//              every face's sign the one its leaf's path from the root gives (−1 under an odd
//              number of complements and later operands of a difference).
//   leaves     validate_mesh with the loader's options (io/scene.h prepare_leaf): the open
//              flag must match the faces (boundary edges; never trusted: an open flag on a
//              closed leaf, or the reverse, is refused), and a closed leaf must be a
//              consistently oriented 2-cycle (every edge traversed equally often each way) whose
//              signed volume is not negative beyond its rounding bound (outward, as loading
//              leaves it). The flipped flag is history only; leaf boxes are recomputed.

#include <string>
#include <string_view>

#include "cover/solid/solid.h"

namespace cover {

/// The bytes of `solid` (format above).
std::string solid_to_bytes(const Solid& solid);

/// The solid of solid_to_bytes(). \throws InputError "WHAT: not a Cover solid: ..." (WHAT names
/// the source) for bytes that are not such a solid: a wrong magic or version, truncated or
/// trailing bytes (naming the byte offset), or any check above (naming the face, leaf or node).
/// Never a solid that a kernel could crash on or answer wrongly for.
Solid solid_from_bytes(std::string_view bytes, const std::string& what = "solid bytes");

}  // namespace cover
