#pragma once
// Mixed evaluation (docs/design.md "Mixed evaluation"): a tree with field, warp or open-mesh
// leaves reaches the exact Booleans through certified meshes of those leaves.

#include "cover/boolean/evaluate.h"
#include "cover/solid/solid.h"

namespace cover::detail {

/// `solid` with each field, warp and open-mesh leaf replaced, in place (same leaf ids, names and
/// tree), by its polygonized mesh (polygonize/polygonize.h over the leaf's box, at
/// options.mesh_resolution and options.mesh_tolerance); `meshed` says which and how well. Leaves
/// are meshed one after another, each in parallel.
struct MeshedSolid {
  Solid solid;
  std::vector<MeshedLeaf> meshed;
};
MeshedSolid mesh_curved_leaves(const Solid& solid, const EvaluateOptions& options);

/// evaluate() of mesh_curved_leaves(solid), with `meshed` and `tolerance` filled in; plain
/// evaluate() when every leaf is a closed mesh.
EvaluateResult evaluate_mixed(const Solid& solid, const EvaluateOptions& options);

}  // namespace cover::detail
