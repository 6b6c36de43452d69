#pragma once
// Loading an INPUT (docs/cli.md#input): a mesh file (one leaf) or a JSON scene (a CSG
// expression of mesh / box / sphere / cylinder leaves with transforms).

#include <filesystem>
#include <string>
#include <vector>

#include "cover/solid/memory_limit.h"
#include "cover/solid/solid.h"

namespace cover {

struct LoadOptions {
  /// reject leaves with boundary edges (--closed-only); otherwise an open leaf is accepted with a
  /// warning and is inside where its generalized winding number has |w| > 1/2 (covering/gwn.h)
  bool require_closed = false;
  bool orient_outward = true;  ///< reverse inside-out leaves (negative covering volume), warning
  /// read repeated loops once and re-orient inconsistently oriented closed leaves, with a
  /// warning each; refuse non-orientable ones (orient.h). Off only for reports (`cover info`).
  bool repair = true;
  /// Every input file (the scene and each mesh) must be a regular file of at most this size;
  /// larger ones are refused before reading (the --max-memory of the command).
  uint64_t max_file_bytes = kDefaultMaxMemoryBytes;
};

struct LoadedInput {
  Solid solid;
  /// One line each, e.g. leaf flipped; parameters marked as in InputError messages
  /// (show_parameters, solid/errors.h, renders them).
  std::vector<std::string> warnings;
};

/// Loads a mesh (by extension, see mesh_io.h) or a `.json` scene.
/// Throws InputError naming the file and line / JSON path: unknown or duplicate keys
/// ("scene.json: /union/0/box: duplicate key 'min'"), wrong types, numbers beyond a double,
/// empty operations, singular transforms, a mesh leaf's own errors after its path
/// ("scene.json: /union/1/mesh: m.off: cannot open: ..."), open leaves (when require_closed:
/// "FILE: open mesh: N boundary edges"), non-orientable or unbalanced closed leaves (orient.h),
/// vertices outside ±kMaxCoordinate, unsupported extensions, inputs that are not regular files or
/// exceed max_file_bytes (solid/memory_limit.h).
LoadedInput load_input(const std::filesystem::path& path, const LoadOptions& options = {});

/// Makes one mesh a leaf as load_input() does (coordinate range, repeated loops, consistent
/// orientation, inside-out reversal, closedness per `options`); `where` names it in messages,
/// warnings are appended. \throws InputError as load_input().
Solid prepare_leaf(PolygonMesh mesh, std::string name, const std::string& where,
                   const LoadOptions& options, std::vector<std::string>& warnings);

/// Parses scene JSON text; `scene_path` names the file in messages and anchors relative mesh paths.
LoadedInput parse_scene(const std::string& text, const std::filesystem::path& scene_path,
                        const LoadOptions& options = {});

}  // namespace cover
