// `cover evaluate INPUT -o OUT.ext --cells N [--pieces DIR] [--bounds xmin,ymin,zmin,size]`
// (docs/cli.md): the result evaluated, cut into N×N×N cells by the
// plane patcher (brep/cells.h) and glued back into OUT; with --pieces, DIR/cell_I_J_K.ext (one
// closed piece per non-empty cell, I, J, K without padding) and DIR/pieces.json. OUT and every
// file of DIR are committed together (one OutputBatch; DIR swapped in whole, cli/output.h
// pieces_folder).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "cover/brep/cells.h"
#include "cover/brep/halfedge.h"
#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/memory_limit.h"

namespace cover::cli {
namespace {

using nlohmann::json;

std::string piece_name(const brep::CellPiece& p, const std::string& ext) {
  return "cell_" + std::to_string(p.cell[0]) + "_" + std::to_string(p.cell[1]) + "_" +
         std::to_string(p.cell[2]) + ext;
}

}  // namespace

int run_evaluate_cells(const EvaluateCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!is_mesh_output_extension(o.output))
    throw InputError(o.output + ": unsupported output format (use " + kMeshOutputFormats + ")");
  // The cells' part now, the evaluated mesh's part once it is known (CellsOptions).
  check_memory(brep::cells_memory_bytes(o.cells), common.max_memory_bytes(),
               "--cells " + std::to_string(o.cells) + ": cutting into cells");
  std::optional<VoxelBounds> bounds;
  if (!o.bounds.empty()) {
    const std::vector<double> v = parse_numbers(o.bounds, "--bounds", 4, ",");
    if (!(v[3] > 0))
      throw InputError("--bounds: expected xmin,ymin,zmin,size with size > 0, got '" + o.bounds +
                       "'");
    check_bounds_range({v[0], v[1], v[2]}, v[3]);
    bounds = VoxelBounds{{v[0], v[1], v[2]}, v[3]};
  }
  std::unique_ptr<OutputFolder> folder;
  if (!o.pieces.empty()) folder = pieces_folder(o.pieces);
  const Model model = load_model(o.input, common.load_options());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  brep::CellsOptions cells_options;
  cells_options.max_memory_bytes = common.max_memory_bytes();
  const CellsEvaluation r = model.evaluate_cells(o.cells, bounds, cells_options);
  timing.lap(Timing::kKernel);
  const PolygonMesh& glued = r.cells.glued;
  if (glued.face_count() == 0)
    std::fprintf(stderr, "cover: warning: the result is empty; writing an empty mesh\n");
  const std::string ext = lower_extension(o.output);
  OutputBatch outputs;
  write_mesh(o.output, glued);
  json pieces = json::array();
  for (const brep::CellPiece& p : r.cells.pieces) {
    const std::string name = piece_name(p, ext);
    pieces.push_back({{"cell", p.cell},
                      {"file", name},
                      {"volume", p.volume},
                      {"area", p.area},
                      {"cap_area", p.cap_area},
                      {"faces", p.mesh.face_count()},
                      {"cap_faces", p.cap_faces},
                      {"forced_ears", p.forced_ears},
                      {"collapsed_edges", p.collapsed_edges}});
  }
  if (!o.pieces.empty()) {
    const std::filesystem::path dir = folder->path();
    for (const brep::CellPiece& p : r.cells.pieces) write_mesh(dir / piece_name(p, ext), p.mesh);
    const json index = {{"cells", o.cells},
                        {"bounds", {{"min", to_json(r.grid.min)}, {"size", r.grid.size}}},
                        {"pieces", pieces}};
    const std::string text = index.dump(1) + "\n";
    write_atomically(
        dir / "pieces.json",
        [&](const std::filesystem::path& tmp) {
          std::FILE* f = std::fopen(tmp.c_str(), "wb");
          if (!f) return false;
          const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
          return std::fclose(f) == 0 && ok;
        },
        "the pieces index");
    folder->commit();
  }
  outputs.commit();
  timing.lap(Timing::kWrite);
  const brep::BrepReport rep = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(glued));
  json j;
  j["volume"] = signed_volume(glued);
  j["area"] = surface_area(glued);
  j["vertices"] = glued.vertices.size();
  j["faces"] = glued.face_count();
  j["genus"] = glued.face_count() == 0 ? 0 : rep.genus;
  j["components"] = rep.components;
  j["cells"] = o.cells;
  j["bounds"] = {{"min", to_json(r.grid.min)}, {"size", r.grid.size}};
  j["pieces"] = r.cells.pieces.size();
  j["cap_faces"] = r.cells.cap_faces;
  j["clips"] = r.cells.clips;
  j["forced_ears"] = r.cells.forced_ears;
  j["collapsed_edges"] = r.cells.collapsed_edges;
  j["rounding_contacts"] = r.cells.rounding_contacts;
  j["evaluated_faces"] = r.evaluated.mesh.face_count();
  timing.put(j);
  j["seconds_detail"]["evaluate"] = r.evaluate_seconds;
  j["seconds_detail"]["cut"] = r.cells.cut_seconds;
  j["seconds_detail"]["glue"] = r.cells.glue_seconds;
  j["seconds_detail"]["repair"] = r.cells.repair_seconds;
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("wrote %s: %zu vertices, %zu faces, %lld components, genus %lld\n",
                o.output.c_str(), glued.vertices.size(), glued.face_count(),
                static_cast<long long>(rep.components),
                static_cast<long long>(j["genus"].get<int64_t>()));
    std::printf("%zu pieces of %d³ cells, %lld cap faces%s%s\n", r.cells.pieces.size(), o.cells,
                static_cast<long long>(r.cells.cap_faces), o.pieces.empty() ? "" : " in ",
                o.pieces.c_str());
    std::printf("volume %.17g\narea %.17g\n", j["volume"].get<double>(), j["area"].get<double>());
  }
  return 0;
}

}  // namespace cover::cli
