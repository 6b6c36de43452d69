#pragma once
// The stages of the stress harness (stress_csg.cpp) and the checks of their outputs. Each stage
// runs in a forked child; what it finds is an Outcome.
//
// Kinds of outcome (docs/benchmarks.md "Random-CSG stress harness"):
//   ok          every output valid, volumes as expected
//   refused     NotComputable: a documented refusal, the reason in the detail
//   bad-input   InputError on a scene whose leaves are all valid (a defect: the input is good)
//   internal    InternalError or any other exception
//   memory      std::bad_alloc under the child's address-space limit
//   invalid     an output mesh fails Cover's exact validity test or CGAL's
//   degenerate  the only defect is a face whose vertices are collinear (zero area; CGAL's test
//               counts it as a self-intersection, Cover's does not)
//   touching    the only defect is a contact at distinct vertices of equal coordinates (the
//               output touches itself there; with those vertices welded nothing intersects)
//   not-convex  a decompose piece with a vertex strictly outside one of its face planes
//   volume      a volume off by more than 1e-9 relative (evaluate vs CGAL corefinement; the
//               cell pieces, the glued pieces and the convex pieces vs evaluate)
//   crash       the child died on a signal;  timeout  the stage ran past its limit
//   skipped     not run: evaluate gave no valid mesh to cut
//   unavailable the CGAL oracle could not compute the reference volume (stage "oracle" only)

#include <optional>
#include <string>
#include <utility>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/solid.h"

namespace cover::stress {

struct Outcome {
  Outcome() = default;
  Outcome(std::string k, std::string d, PolygonMesh e = {})
      : kind(std::move(k)), detail(std::move(d)), evidence(std::move(e)) {}
  std::string kind = "ok";
  std::string detail;    ///< one line: what failed, or for the oracle the volume
  PolygonMesh evidence;  ///< the output mesh that failed its check (empty when none)
};

/// The first problem of an output mesh by Cover's exact checks (mesh/validate.h validate_mesh
/// with the self-intersection test; brep::validate of its half-edge mesh) and CGAL's
/// (cgal_oracle.h); kind "ok", "invalid", "degenerate" or "touching".
Outcome check_mesh(const PolygonMesh& mesh);

/// |value − reference| ≤ 1e-9 · max(|reference|, floor): floor keeps near-empty results from
/// asking for more than the rounding of their points allows (the caller passes 1e-3 of the
/// scene's box volume).
bool volume_matches(double value, double reference, double floor);

/// Stage "evaluate": evaluate(solid), its mesh checked, its volume against `reference` (the
/// oracle's, when there is one). Fills `mesh` with the result when the stage ran.
Outcome stage_evaluate(const Solid& solid, std::optional<double> reference, PolygonMesh& mesh);

/// Stage "cells-N": `mesh` (evaluate's) cut into the n³ cells of the result's voxel bounds
/// (Model::voxel_bounds, as `cover evaluate --cells N`); every piece checked and inside its
/// cell, the pieces' volumes and the glued mesh's against `mesh`'s.
Outcome stage_cells(const Solid& solid, const PolygonMesh& mesh, int n);

/// Stage "decompose": brep::decompose(mesh); every piece checked and exactly convex (CGAL
/// orientation on its doubles), the pieces' volumes summing to `mesh`'s.
Outcome stage_decompose(const Solid& solid, const PolygonMesh& mesh);

/// The outcome of an exception thrown by a stage (the kinds above).
Outcome outcome_of_exception();

}  // namespace cover::stress
