#pragma once
// Loading an INPUT (CONTRACT.md "Input"): a mesh file (one leaf) or a JSON scene (a CSG
// expression of mesh / box / sphere / cylinder leaves with transforms).

#include <filesystem>
#include <string>
#include <vector>

#include "solid/solid.h"

namespace cover {

struct LoadOptions {
  bool require_closed = true;  ///< reject leaves with boundary edges (commands that need solids)
  bool orient_outward = true;  ///< reverse inside-out leaves (negative covering volume), warning
};

struct LoadedInput {
  Solid solid;
  std::vector<std::string> warnings;  ///< one line each, e.g. leaf flipped
};

/// Loads a mesh (by extension, see mesh_io.h) or a `.json` scene.
/// Throws InputError naming the file and line / JSON path: unknown or duplicate keys
/// ("scene.json: /union/0/box: duplicate key 'min'"), wrong types, numbers beyond a double,
/// empty operations, singular transforms, a mesh leaf's own errors after its path
/// ("scene.json: /union/1/mesh: m.off: cannot open: ..."), open leaves (when require_closed:
/// "FILE: open mesh: N boundary edges"), unsupported extensions.
LoadedInput load_input(const std::filesystem::path& path, const LoadOptions& options = {});

/// Parses scene JSON text; `scene_path` names the file in messages and anchors relative mesh paths.
LoadedInput parse_scene(const std::string& text, const std::filesystem::path& scene_path,
                        const LoadOptions& options = {});

}  // namespace cover
