#pragma once
// cover::info: what `cover info` and Python's Model.info report about a Model and each of its
// leaves, computed here once for every front end (docs/cli.md "info").

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cover/brep/halfedge.h"
#include "cover/mesh/repair.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/types.h"

namespace cover {

struct InfoOptions {
  bool check_self_intersection = true;  ///< false: skip the exact self-intersection test
};

/// One leaf, as stored in the Model (a Model loaded with LoadOptions::repair = false and
/// orient_outward = false keeps the faces as found in the file).
struct LeafInfo {
  std::string name;    ///< the mesh path or primitive kind
  std::string origin;  ///< the leaf's JSON path in its scene; empty for a single mesh
  uint32_t vertices = 0, faces = 0;
  Bbox bbox;
  MeshReport report;  ///< validate_mesh of the leaf's faces (mesh/validate.h)
  /// The half-edge kernel's view (brep/halfedge.h); nullopt where the faces do not form an
  /// oriented surface (an edge used twice in one direction, a face with fewer than 3 vertices).
  std::optional<brep::BrepReport> brep;
  RepairReport repair;  ///< what loading repairs and what is left (mesh/repair.h)
  /// A field leaf's blend (solid/field_leaf.h); then vertices, faces and the mesh reports are
  /// empty and bbox is the support box.
  std::optional<FieldLeaf> field;
  double threshold = 0;  ///< field leaves: T (field/field.h threshold)
  /// A warp leaf (solid/warp_leaf.h); then vertices, faces and the mesh reports are empty, bbox
  /// encloses the warped child and child_leaves counts the child's leaves.
  std::optional<WarpLeaf> warp;
  size_t child_leaves = 0;
};

struct ModelInfo {
  size_t vertices = 0, faces = 0;
  Bbox bbox;  ///< of every stored vertex; empty for the empty Model
  std::vector<LeafInfo> leaves;
};

/// The facts about `model` and each leaf. Exact: the predicates behind validate_mesh and the
/// half-edge kernel's counts are exact; `report.volume` is the leaf's covering volume.
ModelInfo info(const Model& model, const InfoOptions& options = {});

}  // namespace cover
