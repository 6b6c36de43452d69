#pragma once
// The CGAL side of the random-CSG stress harness (stress_csg.cpp), kept in one translation unit
// (cgal_oracle.cpp) because CGAL is slow to compile. Everything here is independent of Cover's
// own Booleans, validity test and convexity test: only cgal_convexity_problem shares the
// triangulation of polygon faces (mesh/triangulate.h, exact).

#include <optional>
#include <string>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/solid.h"

namespace cover::stress {

/// The volume of `solid`'s expression computed by CGAL corefinement (Polygon_mesh_processing::
/// corefine_and_compute_union / _intersection / _difference with the Epeck kernel, folded
/// bottom-up over the tree; a difference subtracts its operands one by one) on every leaf's own
/// doubles (leaf_mesh, faces triangulated by CGAL). nullopt, with the reason in `why`, when CGAL
/// cannot compute it (a complement, an operation CGAL refuses, an exception).
std::optional<double> corefined_volume(const Solid& solid, std::string& why);

/// CGAL's verdict on one output mesh (its faces and vertex indices as they are): empty when the
/// faces form a 2-manifold polygon Surface_mesh that is closed and, triangulated by
/// PMP::triangulate_faces, free of self-intersections (PMP::does_self_intersect) and bounds a
/// volume with every component oriented by its nesting (PMP::does_bound_a_volume); else a short
/// description of the first problem found. An empty mesh is valid.
std::string cgal_mesh_problem(const PolygonMesh& mesh);

/// The sign of the signed volume of `mesh` (Σ over the fan triangles of every face of the
/// tetrahedra with the origin) in exact rationals: +1, 0 or −1.
int exact_volume_sign(const PolygonMesh& mesh);

/// Is every vertex of `piece` on the inner side of, or on, the plane of every one of its
/// triangles (CGAL::orientation, exact, on the stored doubles)? Polygon faces are triangulated
/// exactly first; empty when so, else a description of the worst vertex.
std::string cgal_convexity_problem(const PolygonMesh& piece);

}  // namespace cover::stress
