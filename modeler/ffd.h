#pragma once
// Free-form deformation (Sederberg & Parry 1986) of a mesh: a trivariate Bernstein lattice of any
// degree maps the lattice box onto itself deformed; the mesh is refined until a certified chord
// bound meets the tolerance, then its vertices are mapped.
//
// Conventions
//   lattice    box [min, max] with edge lengths L; degrees (l, m, n) ≥ 1 per axis; control
//              points P_ijk, index ((i·(m+1)) + j)·(n+1) + k, i along x (slowest).
//   map        X(p) = p + Σ B_i^l(s) B_j^m(t) B_k^n(u) (P_ijk − P⁰_ijk), (s, t, u) = (p − min)/L,
//              P⁰_ijk = min + (i/l, j/m, k/n)·L the undeformed lattice (Bernstein polynomials
//              reproduce linear functions, so X is exactly Sederberg–Parry's Σ B·P, written as a
//              displacement: the lattice P = P⁰ is the identity exactly, in doubles too).
//   chord      a triangle of the refined mesh against the image of its flat preimage: every point
//              of the flat triangle x maps to X(x), and the mesh carries the linear interpolation
//              of its mapped corners; |L(x) − X(x)| ≤ ½·M·e² with e the triangle's longest edge and
//              M ≥ ‖D²_v X‖ for every unit v over the box, from the control points' second
//              differences (the Bernstein convex-hull property): ‖∂ss X‖ ≤ l(l−1)·max‖Δ²_i P‖/Lx²,
//              ‖∂st X‖ ≤ l·m·max‖Δ_iΔ_j P‖/(Lx·Ly), ..., M = Σ over axis pairs of these bounds
//              (off-diagonal pairs twice), from the displacements P − P⁰ (the same differences in
//              exact arithmetic; the rounded undeformed points add nothing).
//              Certified up to the rounding of the map in doubles.
//   refinement every triangle split into 4 at its edge midpoints (shared midpoints, so the mesh
//              stays conforming and 2-manifold), uniformly, until ½·M·e² ≤ tolerance.

#include <array>
#include <string>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover {

struct FfdLattice {
  Vec3 min, max;
  std::array<int, 3> degree{1, 1, 1};
  std::vector<Vec3> points;  ///< (l+1)(m+1)(n+1) control points, index above
};

/// The undeformed lattice of `box` and `degree` (P = P⁰: the identity map).
FfdLattice identity_lattice(const Vec3& min, const Vec3& max, std::array<int, 3> degree);

/// "" when valid, else the problem ("degree: expected 1 to 16 per axis", "points: expected N
/// control points, got M", "min must be below max on every axis", "points: not finite").
std::string validate(const FfdLattice& lattice);

/// X(p) (conventions above). \pre valid lattice; p in the box (outside it, the same polynomial).
Vec3 ffd_map(const FfdLattice& lattice, const Vec3& p);

/// M of the conventions: a bound on ‖D²_v X‖ over the box for every unit direction v.
double ffd_curvature_bound(const FfdLattice& lattice);

struct FfdOptions {
  /// The chord bound asked for; 0: 1e-3 of the lattice box's diagonal.
  double tolerance = 0;
  size_t max_triangles = size_t{1} << 24;  ///< refused beyond (InputError)
};

struct FfdResult {
  PolygonMesh mesh;        ///< triangles: the refined mesh, mapped
  int levels = 0;          ///< rounds of 1→4 refinement
  double chord_bound = 0;  ///< ½·M·e² over the refined triangles (≤ tolerance)
};

/// Deforms `mesh` (polygon faces are triangulated first). \throws InputError for an invalid
/// lattice, a vertex outside the lattice box, a face that cannot be triangulated, a tolerance
/// ≤ 0 or not finite (other than the default 0), or more than max_triangles needed.
FfdResult ffd(const PolygonMesh& mesh, const FfdLattice& lattice, const FfdOptions& options = {});

}  // namespace cover
