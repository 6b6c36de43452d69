// `cover subdivide IN -o OUT --scheme S --levels N [--exact-rounding] [--json]` (docs/cli.md):
// `levels` rounds of a subdivision scheme (subdivision/subdivide.h) on a mesh file, written in any
// mesh format, with the result's counts, genus, components and the exact self-intersection flag
// (mesh/validate.h, as `cover info` reports a leaf). Every input problem (unreadable file, a face
// Loop or √3 cannot take, a non-manifold or inconsistently oriented edge, levels beyond
// kMaxSubdivisionEntries) is one InputError naming the input file; nothing is written then.
// An OBJ's texture coordinates (vt) are carried to an OBJ output, interpolated within faces
// (subdivide.h, CornerAttributes).
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "cover/solid/errors.h"
#include "cover/subdivision/subdivide.h"

namespace cover::cli {

int run_subdivide(const SubdivideCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  const std::optional<Scheme> scheme = scheme_from_string(o.scheme);
  if (!scheme)
    throw InputError("--scheme: expected catmull-clark, doo-sabin, loop or sqrt3, got '" +
                     o.scheme + "'");
  if (!is_mesh_output_extension(o.output))
    throw InputError(o.output + ": unsupported output format (use " + kMeshOutputFormats + ")");
  if (lower_extension(o.input) == ".json")
    throw InputError(o.input +
                     ": cover subdivide reads a mesh file (.off .obj .stl .ply); in a scene, "
                     "use a \"subdivide\" node");
  std::vector<std::string> warnings;
  std::vector<double> uvs;  // an OBJ's texture coordinates, 2 per corner (empty: none)
  const PolygonMesh mesh = read_mesh_with_uvs(o.input, uvs, common.max_memory_bytes(), &warnings);
  const bool carry_uvs = !uvs.empty() && lower_extension(o.output) == ".obj";
  if (!uvs.empty() && !carry_uvs)
    warnings.push_back(o.input + ": texture coordinates dropped (" + o.output +
                       " cannot hold them; use .obj)");
  for (const std::string& w : warnings) std::fprintf(stderr, "cover: warning: %s\n", w.c_str());
  if (common.closed_only) {
    const MeshReport in = validate_mesh(mesh, {.check_self_intersection = false});
    if (in.boundary_edges > 0)
      throw InputError(o.input + ": open mesh: " + std::to_string(in.boundary_edges) +
                       " boundary edges (--closed-only)");
  }
  timing.lap(Timing::kLoad);
  SubdivideOptions so;
  so.scheme = *scheme;
  so.levels = o.levels;
  so.exact_rounding = o.exact_rounding;
  PolygonMesh out;
  CornerAttributes attributes{2, std::move(uvs)};
  try {
    out = carry_uvs ? subdivide(mesh, so, attributes) : subdivide(mesh, so);
  } catch (const InputError& e) {
    throw e.prefixed(o.input + ": ");
  }
  const MeshReport r = validate_mesh(out, {.check_self_intersection = o.check_self_intersection});
  timing.lap(Timing::kKernel);
  OutputBatch outputs;
  if (carry_uvs)
    write_mesh_with_uvs(o.output, out, attributes.values);
  else
    write_mesh(o.output, out);
  outputs.commit();
  timing.lap(Timing::kWrite);
  nlohmann::json j;
  j["input"] = o.input;
  j["output"] = o.output;
  j["scheme"] = std::string(to_string(*scheme));
  j["levels"] = o.levels;
  j["exact_rounding"] = o.exact_rounding;
  j["texture_coordinates"] = carry_uvs;
  j["vertices"] = out.vertices.size();
  j["edges"] = r.edges;
  j["faces"] = out.face_count();
  j["closed"] = r.closed;
  j["boundary_edges"] = r.boundary_edges;
  j["components"] = r.components;
  j["genus"] = r.genus >= 0 ? nlohmann::json(r.genus) : nlohmann::json();
  j["self_intersecting"] =
      r.self_intersecting ? nlohmann::json(*r.self_intersecting) : nlohmann::json();
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("wrote %s: %s, %d level(s)%s\n", o.output.c_str(),
              j["scheme"].get<std::string>().c_str(), o.levels,
              o.exact_rounding ? ", exact rounding" : "");
  std::printf("%zu vertices, %lld edges, %zu faces, %lld components, genus %s\n",
              out.vertices.size(), static_cast<long long>(r.edges), out.face_count(),
              static_cast<long long>(r.components),
              r.genus >= 0 ? std::to_string(r.genus).c_str() : "n/a");
  std::printf("closed %s (%lld boundary edges), self-intersecting %s\n", r.closed ? "yes" : "no",
              static_cast<long long>(r.boundary_edges),
              !r.self_intersecting   ? "not checked"
              : *r.self_intersecting ? "yes"
                                     : "no");
  return 0;
}

}  // namespace cover::cli
