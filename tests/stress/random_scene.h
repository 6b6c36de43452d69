#pragma once
// Seeded random CSG scenes for the stress harness (stress_csg.cpp): 2- or 3-level trees of
// union / intersection / difference over boxes and libcgal-demo meshes, written as scene JSON
// (docs/cli.md "Scenes") so that `cover evaluate SCENE.json` reproduces a case exactly.
//
//   leaf      a mesh (about 2 in 3): scaled into a cube of side 0.8–2 around a random centre in
//             [−0.5, 0.5]³, sometimes with unequal axis factors, rotated about a random axis;
//             written as one "matrix" transform (17 significant digits: the same doubles on
//             reading). Or a box: axis-aligned on the 1/4 grid (coincident faces between leaves,
//             about 2 in 5 of boxes) or centred near the origin, rotated and translated.
//   tree      depth 2 or 3 (a root operation over leaves, or over operations of leaves); 2 or 3
//             operands per operation; the first operand of the root is always an operation in a
//             3-level scene. Operations are drawn uniformly.
// A seed gives the same tree and draws everywhere (std::mt19937_64 with integer draws turned
// into doubles by exact arithmetic, no std distribution); the rotation's matrix entries come from
// the C library's sin / cos, so the JSON text, which is what reproduces a case, is kept.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cover/solid/types.h"

namespace cover::stress {

/// A mesh the generator may place: its file and its box as read.
struct MeshEntry {
  std::filesystem::path path;  ///< absolute path, written into the scene as it is
  Bbox box;
  size_t faces = 0;
};

struct RandomScene {
  std::string json;         ///< the scene text
  std::string description;  ///< one line: the expression with mesh names, e.g. "(cube ∪ box) − cow"
  int depth = 0;            ///< 2 or 3
  int leaves = 0;
};

/// The scene of `seed` over `meshes` (non-empty).
RandomScene random_scene(uint64_t seed, const std::vector<MeshEntry>& meshes);

}  // namespace cover::stress
