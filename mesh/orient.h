#pragma once
// Repairs of a closed leaf's face structure before it becomes a solid (docs/cli.md#semantics).
//
// The covering theorem ([Segura2004 §2 Theorem 2]) needs the faces to form a closed 2-cycle: every
// undirected edge {u, v} must be traversed as often from u to v as from v to u, counting every
// face side (false edges inside one face cancel by themselves). Then the winding number is an
// integer independent of the covering origin, and every kernel (volume, classification, rays,
// voxels, evaluation) sees the same solid. A mesh that breaks the rule gives each kernel a
// different answer, so it is repaired here or refused:
//   repeated loop     a face whose index list is one loop written k ≥ 2 times ("0 3 2 1 0 3 2 1")
//                     winds its polygon k times; it is read as the loop once.
//   re-orientation    faces are flipped so that every edge with exactly two sides in different
//                     faces has them in opposite directions (breadth first over those edges, one
//                     parity per connected component; the component keeps the orientation of the
//                     majority of its faces, ties keep the first face's). A conflict in that
//                     walk means the surface is not orientable.
//   membranes         an edge with three sides (two solids glued along a ring where one kept
//                     the cap disk that the other lost) stays unbalanced under any orientation.
//                     The patches meeting unbalanced edges (≤ 10 of them) are then each kept,
//                     flipped or dropped, choosing the assignment that balances every edge they
//                     touch and drops the least area (the spanning membrane, as a minimal surface
//                     would), then flips the least area: the two solids' union remains.
// Any edge that no such choice balances is an error naming a face and the edge.

#include <cstddef>
#include <string>

#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Collapses every face whose index list is a shorter loop repeated k ≥ 2 times to one copy of
/// that loop. Returns the number of faces changed. The first such face index goes to *first.
size_t collapse_repeated_loops(PolygonMesh& mesh, size_t* first = nullptr);

struct OrientResult {
  size_t flipped_faces = 0;  ///< faces reversed to make the orientation consistent
  size_t components = 0;     ///< patches (components through two-sided edges) flipped
  size_t dropped_faces = 0;  ///< faces of dropped membrane patches (see above)
};

/// Makes every edge balanced by flipping faces (rules above). `where` names the leaf in errors.
/// Precondition: the mesh has no boundary edge (validate_mesh().boundary_edges == 0).
/// \throws InputError "WHERE: non-orientable surface: ..." when the two-sided edges admit no
/// consistent orientation, "WHERE: face F: edge U-V ..." when an edge stays unbalanced.
OrientResult orient_consistently(PolygonMesh& mesh, const std::string& where);

}  // namespace cover
