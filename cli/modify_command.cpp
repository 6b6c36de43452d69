// `cover modify IN -o OUT --ops FILE`, `cover pipe IN -o OUT --faces F1,F2`, `cover extrude IN
// -o OUT --face F --distance D` (docs/cli.md "Modeling"): the mesh is read into the DLFL
// (modeler/dlfl.h), the operations of a script (modeler/script.h; pipe and extrude build a
// one-step script from their flags) are applied, and the result is written in any mesh format,
// with its counts, genus, components and the exact self-intersection flag (mesh/validate.h).
// Every problem is one InputError naming the input or the script and the operation; nothing is
// written then.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "cover/modeler/script.h"
#include "cover/solid/errors.h"

namespace cover::cli {
namespace {

using Json = nlohmann::json;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the operations file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Faces given by id (--faces / --face) or by points near them (--near): `count` of them.
Json face_list(const ModifyCommandOptions& o, size_t count, const char* flag) {
  Json out = Json::array();
  if (!o.near.empty()) {
    if (!o.faces.empty()) throw InputError(std::string(flag) + " and --near: give one of them");
    if (o.near.size() != 3 * count)
      throw InputError("--near: expected " + std::to_string(3 * count) +
                       " numbers (x,y,z per face)");
    for (size_t i = 0; i < count; ++i)
      out.push_back(Json::array({o.near[3 * i], o.near[3 * i + 1], o.near[3 * i + 2]}));
    return out;
  }
  if (o.faces.size() != count)
    throw InputError(std::string(flag) + ": expected " + std::to_string(count) +
                     (count == 1 ? " face id" : " face ids") + " (or --near)");
  for (int f : o.faces) out.push_back(f);
  return out;
}

}  // namespace

int run_modify(std::string_view command, const ModifyCommandOptions& o,
               const CommonOptions& common) {
  Timing timing;
  if (!is_mesh_output_extension(o.output))
    throw InputError(o.output + ": unsupported output format (use " + kMeshOutputFormats + ")");
  std::string script, origin;
  if (command == "modify") {
    script = read_text(o.ops);
    origin = o.ops;
  } else if (command == "pipe") {
    const Json faces = face_list(o, 2, "--faces");
    Json pipe = {{"faces", faces}, {"segments", o.segments}, {"twist", o.twist}};
    if (o.curved) pipe["curved"] = true;
    if (!o.weights.empty()) pipe["weights"] = o.weights;
    if (o.through.size() % 3 != 0)
      throw InputError("--through: expected x,y,z (three numbers per point)");
    if (!o.through.empty()) {
      Json path = Json::array();
      for (size_t i = 0; i < o.through.size(); i += 3)
        path.push_back({o.through[i], o.through[i + 1], o.through[i + 2]});
      pipe["path"] = path;
    }
    script = Json::array({{{"pipe", pipe}}}).dump();
    origin = "cover pipe";
  } else {
    const Json face = face_list(o, 1, "--face")[0];
    script =
        Json::array({{{"extrude", {{"face", face}, {"distance", o.distance}, {"kind", o.kind}}}}})
            .dump();
    origin = "cover extrude";
  }
  std::vector<std::string> warnings;
  const PolygonMesh mesh = read_mesh(o.input, common.max_memory_bytes(), &warnings);
  for (const std::string& w : warnings) std::fprintf(stderr, "cover: warning: %s\n", w.c_str());
  modeler::DlflMesh dlfl;
  try {
    dlfl = modeler::from_polygon_mesh(mesh);
  } catch (const InputError& e) {
    throw e.prefixed(o.input + ": ");
  }
  timing.lap(Timing::kLoad);
  const modeler::ScriptReport report = modeler::apply_script(dlfl, script, origin);
  const PolygonMesh out = modeler::to_polygon_mesh(dlfl);
  const std::vector<modeler::ComponentInfo> parts = modeler::components(dlfl);
  const MeshReport r = validate_mesh(out, {.check_self_intersection = o.check_self_intersection});
  timing.lap(Timing::kKernel);
  OutputBatch outputs;
  write_mesh(o.output, out);
  outputs.commit();
  timing.lap(Timing::kWrite);
  int genus = 0;
  for (const modeler::ComponentInfo& c : parts) genus += c.genus;
  Json j;
  j["input"] = o.input;
  j["output"] = o.output;
  j["operations"] = report.operations;
  j["vertices"] = dlfl.vertex_count();
  j["edges"] = dlfl.edge_count();
  j["faces"] = dlfl.face_count();
  j["components"] = parts.size();
  j["genus"] = genus;
  j["self_intersecting"] = r.self_intersecting ? Json(*r.self_intersecting) : Json();
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("wrote %s: %zu operation(s)\n", o.output.c_str(), report.operations);
  std::printf("%zu vertices, %zu edges, %zu faces, %zu components, genus %d\n", dlfl.vertex_count(),
              dlfl.edge_count(), dlfl.face_count(), parts.size(), genus);
  std::printf("self-intersecting %s\n", !r.self_intersecting   ? "not checked"
                                        : *r.self_intersecting ? "yes"
                                                               : "no");
  return 0;
}

}  // namespace cover::cli
