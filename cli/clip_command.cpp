// `cover clip` (docs/cli.md): the exact plane clip and patch of brep/clip.h.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "cover/brep/clip.h"
#include "cover/brep/halfedge.h"
#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"

namespace cover::cli {
namespace {

using nlohmann::json;

struct HalfSummary {
  std::optional<double> volume;  ///< empty for .json scene outputs of several leaves
  int64_t faces = 0, rings = 0;
  bool closed = true;
};

json summary_json(const HalfSummary& s) {
  return {{"volume", s.volume ? json(*s.volume) : json(nullptr)},
          {"faces", s.faces},
          {"rings", s.rings},
          {"closed", s.closed}};
}

void add(HalfSummary& s, const brep::ClipHalf& h) {
  s.faces += static_cast<int64_t>(h.mesh.face_count());
  s.rings += h.rings;
  const brep::BrepReport r = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(h.mesh));
  s.closed = s.closed && r.closed && r.manifold;
}

/// Writes text atomically (io/atomic_file.h).
void write_text(const std::filesystem::path& path, const std::string& text) {
  write_atomically(
      path,
      [&](const std::filesystem::path& temp) {
        std::ofstream out(temp, std::ios::binary);
        out << text;
        out.flush();
        return out.good();
      },
      "the scene");
}

/// The scene node of `node` with every leaf replaced by its clipped mesh file; empty when the
/// node's set is empty (a clipped leaf with no faces), simplified through the operations.
std::optional<json> clipped_node(const CsgTree& tree, uint32_t node,
                                 const std::vector<std::optional<std::string>>& leaf_files) {
  const CsgNode& n = tree.nodes[node];
  if (n.op == CsgOp::kLeaf) {
    if (!leaf_files[n.leaf]) return std::nullopt;
    return json{{"mesh", *leaf_files[n.leaf]}};
  }
  if (n.op == CsgOp::kComplement)  // refused by run_clip before any file is written
    throw InternalError("clipped_node: a complement cannot be clipped leaf by leaf");
  std::vector<json> kids;
  for (size_t k = 0; k < n.children.size(); ++k) {
    std::optional<json> c = clipped_node(tree, n.children[k], leaf_files);
    if (!c) {
      if (n.op == CsgOp::kIntersection || (n.op == CsgOp::kDifference && k == 0))
        return std::nullopt;
      continue;  // an empty union member or subtrahend drops out
    }
    kids.push_back(std::move(*c));
  }
  if (kids.empty()) return std::nullopt;
  if (kids.size() == 1) return kids[0];
  const char* key = n.op == CsgOp::kUnion          ? "union"
                    : n.op == CsgOp::kIntersection ? "intersection"
                                                   : "difference";
  return json{{key, kids}};
}

/// A clip (`clip()`) with its messages ("edge 0-1 is used twice ...", "open mesh: ...") after
/// `where`: the input file, and a leaf's JSON path in a scene.
template <typename Clip>
brep::ClipResult clip_named(Clip&& clip, const std::string& where) {
  const std::string prefix = where + ": ";
  // Once: a leaf's own message may already start with it.
  const auto named = [&](const std::exception& e) {
    return std::string_view(e.what()).starts_with(prefix);
  };
  try {
    return clip();
  } catch (const InputError& e) {
    throw named(e) ? e : e.prefixed(prefix);
  } catch (const NotComputable& e) {
    throw named(e) ? e : NotComputable(prefix + e.what());
  }
}

}  // namespace

int run_clip(const ClipCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  const std::vector<double> p = parse_numbers(o.plane, "--plane", 4, ",");
  const brep::Plane plane{{p[0], p[1], p[2]}, p[3]};
  if (p[0] == 0 && p[1] == 0 && p[2] == 0) throw InputError("--plane: the normal must be non-zero");
  const std::filesystem::path above_path = o.output, below_path = o.below;
  const bool scene_out = above_path.extension() == ".json";
  for (const std::filesystem::path& out : {above_path, below_path}) {
    if (out.empty()) continue;
    if ((out.extension() == ".json") != scene_out)
      throw InputError(out.string() + ": ABOVE and BELOW must both be meshes or both .json scenes");
    if (!scene_out && !is_mesh_output_extension(out))
      throw InputError(out.string() + ": unsupported output format (use " + kMeshOutputFormats +
                       " or .json)");
  }
  const Model model = load_model(o.input, common.load_options());
  const Solid& s = model.solid();
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  if (scene_out && std::any_of(s.tree.nodes.begin(), s.tree.nodes.end(),
                               [](const CsgNode& n) { return n.op == CsgOp::kComplement; }))
    throw InputError(o.input + ": a scene with a complement cannot be clipped leaf by leaf " +
                     "(use a mesh output)");
  brep::ClipOptions co;
  co.triangulate_caps = o.triangulate;
  HalfSummary above, below;
  OutputBatch outputs;
  if (!scene_out) {
    // A scene of several leaves is evaluated first (boolean/evaluate.h: one closed
    // 2-manifold of the CSG result), then that mesh is clipped; a single leaf is clipped directly
    // (Model::clip).
    const brep::ClipResult r = clip_named([&] { return model.clip(plane, co); }, o.input);
    add(above, r.above);
    add(below, r.below);
    above.volume = signed_volume(r.above.mesh);
    below.volume = signed_volume(r.below.mesh);
    timing.lap(Timing::kKernel);
    write_mesh(above_path, r.above.mesh);
    if (!below_path.empty()) write_mesh(below_path, r.below.mesh);
  } else {
    // Intersection with a half-space distributes over union, intersection and difference: clip
    // every leaf and keep the expression. Leaf meshes are written beside each scene.
    std::vector<brep::ClipResult> clipped;
    if (s.has_implicit_leaf())
      throw NotComputable(o.input + ": " + s.implicit_leaf_message() +
                          ": a field or warp leaf cannot be clipped leaf by leaf into a scene "
                          "(use a mesh output: the result is meshed, then clipped)");
    for (uint32_t l = 0; l < s.leaves.size(); ++l) {
      const std::string& origin = s.leaves[l].origin;
      clipped.push_back(clip_named([&] { return brep::clip(leaf_mesh(s, l), plane, co); },
                                   origin.empty() ? o.input : o.input + ": " + origin));
      add(above, clipped.back().above);
      add(below, clipped.back().below);
    }
    timing.lap(Timing::kKernel);
    std::vector<std::optional<std::string>> files[2];
    double volume[2] = {0, 0};
    for (uint32_t l = 0; l < s.leaves.size(); ++l) {
      for (int side = 0; side < 2; ++side) {
        const brep::ClipHalf& h = side == 0 ? clipped[l].above : clipped[l].below;
        const std::filesystem::path& scene = side == 0 ? above_path : below_path;
        volume[side] += signed_volume(h.mesh);
        if (scene.empty() || h.mesh.face_count() == 0) {
          files[side].push_back(std::nullopt);
          continue;
        }
        const std::string name = scene.stem().string() + ".leaf" + std::to_string(l) + ".off";
        write_mesh(scene.parent_path() / name, h.mesh);
        files[side].push_back(name);
      }
    }
    if (s.leaves.size() == 1) {
      above.volume = volume[0];
      below.volume = volume[1];
    }
    for (int side = 0; side < 2; ++side) {
      const std::filesystem::path& scene = side == 0 ? above_path : below_path;
      if (scene.empty()) continue;
      const std::optional<json> root = clipped_node(s.tree, s.tree.root, files[side]);
      if (!root)
        throw NotComputable(scene.string() + ": the clipped scene is empty (a scene needs a leaf)");
      write_text(scene, root->dump(2) + "\n");
    }
  }
  outputs.commit();
  timing.lap(Timing::kWrite);
  if (common.json) {
    json j;
    j["above"] = summary_json(above);
    j["below"] = summary_json(below);
    timing.put(j);
    std::cout << j.dump() << "\n";
  } else {
    for (const auto& [name, h] : {std::pair{"above", &above}, std::pair{"below", &below}}) {
      std::printf("%s: %lld faces, %lld rings, %s", name, static_cast<long long>(h->faces),
                  static_cast<long long>(h->rings), h->closed ? "closed" : "NOT closed");
      if (h->volume) std::printf(", volume %.17g", *h->volume);
      std::printf("\n");
    }
    std::printf("%.3f s\n", timing.total());
  }
  return 0;
}

}  // namespace cover::cli
