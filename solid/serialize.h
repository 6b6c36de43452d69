#pragma once
// A Solid as bytes and back: how a Model travels to other processes (Python pickling, Dask
// workers; DESIGN.md §10) without re-reading its files or re-applying transforms, so every
// process sees the same doubles and the same expression.
//
// Format (little-endian, version 1):
//   "COVERSOL" u32 version
//   u64 vertices, faces, face_vertices, leaves, nodes; u32 root
//   f64[3·vertices]  u32[faces + 1] face_start  u32[face_vertices]  u32[faces] face_leaf
//   i8[faces] face_sign
//   per leaf: u32 name bytes, name, u32 origin bytes, origin, u32 first_face, face_count,
//             first_vertex, vertex_count, u8 flags (1: flipped, 2: open; boxes are recomputed on reading)
//   per node: u8 op, u32 leaf, u32 children, u32[children]
// Reading checks everything a kernel relies on (solid.h notation): offsets non-decreasing and in
// range, indices below their counts, signs ±1, leaf ranges inside the arrays, finite vertices
// within ±kMaxCoordinate, each node's children before it (so the tree is acyclic) with the arity
// of its operation; counts are checked against the byte length before anything is allocated.

#include <string>
#include <string_view>

#include "solid/solid.h"

namespace cover {

/// The bytes of `solid` (format above).
std::string solid_to_bytes(const Solid& solid);

/// The solid of solid_to_bytes(). \throws InputError "WHAT: ..." (WHAT names the source) for
/// bytes that are not such a solid: a wrong magic or version, truncated or trailing bytes, or
/// any check above.
Solid solid_from_bytes(std::string_view bytes, const std::string& what = "solid bytes");

}  // namespace cover
