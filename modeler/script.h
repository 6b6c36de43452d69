#pragma once
// Recorded modeling operations (TopMod-style scripting): a JSON list of user-level operators
// applied in order to a DlflMesh, shared by `cover modify` / `cover pipe` / `cover extrude`
// (docs/cli.md "Modeling"), Python's `cover.modify` and C++.
//
// Script: {"operations": [op, ...]} or a bare [op, ...]; each op is a one-key object:
//   {"create_vertex": {"point": [x, y, z]}}                       (a point-sphere)
//   {"delete_vertex": {"vertex": V}}                              (a point-sphere's)
//   {"insert_edge": {"corners": [C1, C2]}}    C: {"face": F, "vertex": V}, or {"vertex": V} for
//                                             a point-sphere's corner
//   {"delete_edge": {"edge": E}}
//   {"pipe": {"faces": [F1, F2], "segments": 1, "twist": 0}}      (twist in degrees, rounded to
//                whole corners of F1: 360/n degrees each; "curved": true, "weights": [w1, w2],
//                "path": [[x, y, z], ...]: a Hermite handle, PipeOptions)
//   {"extrude": {"face": F, "distance": d, "kind": "straight"}}   (or "cubical": TopMod's
//                Doo–Sabin extrusion, with "twist" in [0, 1] and "scale"; "dodecahedral" and
//                "dome" with "scale"; "stellate": a cone of height d)
//   {"stellate": {"face": F, "height": h}}
//   {"inset": {"face": F, "fraction": 0.2}}
//   {"truncate": {"vertex": V, "fraction": t}}
//   {"chamfer": {"edge": E, "fraction": 0.25}}
//   {"bevel": {"fraction": 0.25}}
//   {"crust": {"faces": [F, ...], "thickness": 0.1, "inset": 0.2}}
//   {"wireframe": {"thickness": 0.1, "inset": 0.2}}
//   {"subdivide_edge": {"edge": E, "points": k}}
//   {"remove_edge": {"edge": E}}
//   {"subdivide": {"scheme": "catmull-clark", "levels": 1}}   (subdivision/subdivide.h)
// A face, vertex or edge is an id of the mesh as it is at that step (the input's face and vertex
// indices until an operation renumbers them: ids of kept elements never change, new ones reuse
// freed ids, last freed first; "subdivide" renumbers everything) or a point [x, y, z]: the
// face whose vertex centroid, the edge whose midpoint, the vertex that is nearest to it (ties
// to the smallest id).

#include <string>
#include <string_view>

#include "cover/modeler/dlfl.h"

namespace cover::modeler {

/// What apply_script did.
struct ScriptReport {
  size_t operations = 0;  ///< operations applied
};

/// Parses `script` (JSON text) and applies its operations to `mesh` in order. `origin` (the
/// script's file name) prefixes every error.
/// \throws InputError "ORIGIN: /operations/K/NAME: problem" for malformed JSON, an unknown
/// operation or key, a wrong type, an id that is not live, or an operation that refuses its
/// arguments (operators.h); the mesh is then left as the operations before K made it.
ScriptReport apply_script(DlflMesh& mesh, std::string_view script, const std::string& origin);

}  // namespace cover::modeler
