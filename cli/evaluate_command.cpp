// `cover evaluate INPUT -o OUT.(off|obj|stl|ply) [--leaf-ids] [--json]` (docs/cli.md): the CSG
// result as one closed, outward-oriented 2-manifold B-rep (boolean/evaluate.h). An empty result
// (e.g. disjoint operands intersected) is not an error: an empty mesh (0 vertices, 0 faces) is
// written, exit 0, with a warning on stderr. --leaf-ids adds each face's source leaf (index into
// the scene's leaves, in load order): PLY face property `int leaf`, OBJ groups `g leaf_K`; the
// JSON then lists the leaf names under `leaf_names`. Field, warp and open-mesh leaves are meshed
// first (mixed evaluation, --mesh-resolution, --mesh-tolerance); the JSON then lists them under
// `meshed` with the certified `tolerance`.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "cover/boolean/evaluate.h"
#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/render/render.h"
#include "cover/solid/errors.h"

namespace cover::cli {

int run_evaluate(const EvaluateCommandOptions& o, const CommonOptions& common) {
  if (o.cells > 0 && o.leaf_ids)
    throw InputError("--leaf-ids: not available with --cells (the pieces carry no leaf ids)");
  if (o.cells > 0) return run_evaluate_cells(o, common);
  if (!o.pieces.empty() || !o.bounds.empty())
    throw InputError(std::string(o.pieces.empty() ? "--bounds" : "--pieces") + ": needs --cells N");
  Timing timing;
  if (!is_mesh_output_extension(o.output))
    throw InputError(o.output + ": unsupported output format (use " + kMeshOutputFormats + ")");
  const std::string ext = lower_extension(o.output);
  const bool gltf = ext == ".gltf" || ext == ".glb" || ext == ".3mf";  // colours per leaf
  if (o.leaf_ids && ext != ".ply" && ext != ".obj" && !gltf)
    throw InputError(o.output + ": --leaf-ids needs a .ply, .obj, .gltf, .glb or .3mf output");
  const Model model = load_model(o.input, common.load_options());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  EvaluateOptions eo;
  eo.mesh_resolution = o.mesh_resolution;
  eo.mesh_tolerance = o.mesh_tolerance;
  const EvaluateResult r = model.evaluate(eo);
  timing.lap(Timing::kKernel);
  if (r.mesh.face_count() == 0)
    std::fprintf(stderr, "cover: warning: the result is empty; writing an empty mesh\n");
  OutputBatch outputs;
  if (o.leaf_ids || gltf) {  // glTF, 3MF: a material per leaf, in its display colour
    FaceLabels labels;
    labels.ply_property = "leaf";
    labels.labels = r.face_leaf;
    for (size_t l = 0; l < model.leaf_count(); ++l) {
      labels.obj_groups.push_back("leaf_" + std::to_string(l));
      labels.colours.push_back(display_colour(model.solid(), static_cast<uint32_t>(l)));
    }
    write_mesh(o.output, r.mesh, labels);
  } else {
    write_mesh(o.output, r.mesh);
  }
  outputs.commit();
  timing.lap(Timing::kWrite);
  nlohmann::json j;
  j["volume"] = r.volume;
  j["area"] = r.area;
  j["vertices"] = r.mesh.vertices.size();
  j["faces"] = r.mesh.face_count();
  j["genus"] = r.genus;
  j["components"] = r.components;
  j["collapsed_edges"] = r.collapsed_edges;
  if (!r.meshed.empty()) {  // mixed evaluation: what was meshed, and how close
    j["tolerance"] = r.tolerance;
    j["meshed"] = nlohmann::json::array();
    for (const MeshedLeaf& m : r.meshed)
      j["meshed"].push_back({{"leaf", m.leaf},
                             {"name", model.solid().leaves[m.leaf].origin.empty()
                                          ? model.solid().leaves[m.leaf].name
                                          : model.solid().leaves[m.leaf].origin},
                             {"triangles", m.triangles},
                             {"cell_size", m.cell_size},
                             {"tolerance", m.tolerance},
                             {"uncertain", m.uncertain},
                             {"clipped", m.clipped}});
  }
  if (o.leaf_ids) {
    j["leaf_names"] = nlohmann::json::array();
    for (const Leaf& leaf : model.solid().leaves) j["leaf_names"].push_back(leaf.name);
  }
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("wrote %s: %zu vertices, %zu faces, %lld components, genus %lld\n",
                o.output.c_str(), r.mesh.vertices.size(), r.mesh.face_count(),
                static_cast<long long>(r.components), static_cast<long long>(r.genus));
    std::printf("volume %.17g\narea %.17g\n", r.volume, r.area);
    if (!r.meshed.empty())
      std::printf("meshed %zu field, warp or open leaves first: vertices within %.3g of them\n",
                  r.meshed.size(), r.tolerance);
  }
  return 0;
}

}  // namespace cover::cli
