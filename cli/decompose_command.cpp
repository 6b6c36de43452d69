// `cover decompose INPUT -o DIR [--ext .off] [--json]` (docs/cli.md):
// exact convex decomposition by reflex-edge plane cuts (brep/decompose.h). A scene is evaluated
// first (boolean/evaluate.h, as `cover evaluate`); a single leaf is decomposed as it is.
// DIR/piece_NNNN.EXT (closed, outward, exactly convex triangle meshes) and DIR/pieces.json
// are written as one batch: all or nothing, DIR swapped in whole (cli/output.h pieces_folder).
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/brep/decompose.h"
#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"

namespace cover::cli {

int run_decompose(const DecomposeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  const std::string ext = o.ext.empty() || o.ext[0] == '.' ? o.ext : "." + o.ext;
  if (!is_mesh_extension("piece" + ext))
    throw InputError("--ext " + o.ext + ": unsupported mesh format (use .off, .obj or .ply)");
  std::string lower = ext;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".stl")
    throw InputError("--ext " + o.ext + ": STL stores float32 coordinates, so pieces written as " +
                     "STL would not be exactly convex (use .off, .obj or .ply)");
  const std::filesystem::path dir = o.output;
  const auto folder = pieces_folder(o.output);
  const Model model = load_model(o.input, common.load_options());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  brep::DecomposeResult r;
  try {
    r = model.decompose();
  } catch (const InputError& e) {
    throw e.prefixed(o.input + ": ");
  } catch (const NotComputable& e) {
    throw NotComputable(o.input + ": " + e.what());
  }
  timing.lap(Timing::kKernel);
  if (r.pieces.empty())
    std::fprintf(stderr, "cover: warning: the result is empty; no piece written\n");

  nlohmann::json list = nlohmann::json::array();
  OutputBatch outputs;
  for (size_t i = 0; i < r.pieces.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "piece_%04zu", i);
    const std::string file = name + ext;
    write_mesh(folder->path() / file, r.pieces[i]);
    list.push_back({{"file", file},
                    {"volume", signed_volume(r.pieces[i])},
                    {"vertices", r.pieces[i].vertices.size()},
                    {"faces", r.pieces[i].face_count()}});
  }
  nlohmann::json j;
  j["pieces"] = r.pieces.size();
  j["reflex_edges"] = r.reflex_edges;
  j["nearly_flat_edges"] = r.nearly_flat_edges;
  j["cuts"] = r.cuts;
  j["uncut_pieces"] = r.uncut_pieces;
  j["fallback_nodes"] = r.fallback_nodes;
  j["volume"] = r.volume;
  j["input_volume"] = r.input_volume;
  j["hull_change"] = r.hull_change;
  nlohmann::json doc = j;
  doc["pieces"] = list;
  write_atomically(
      folder->path() / "pieces.json",
      [&](const std::filesystem::path& temp) {
        std::ofstream out(temp, std::ios::binary);
        out << doc.dump(1) << "\n";
        out.flush();
        return out.good();
      },
      "the piece list");
  folder->commit();
  outputs.commit();
  timing.lap(Timing::kWrite);
  timing.put(j);
  j["seconds_detail"]["cut"] = r.cut_seconds;
  j["seconds_detail"]["hull"] = r.hull_seconds;
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("wrote %zu convex pieces to %s (%lld reflex edges, %lld cuts)\n", r.pieces.size(),
                dir.string().c_str(), static_cast<long long>(r.reflex_edges),
                static_cast<long long>(r.cuts));
    std::printf("volume %.17g (input %.17g)\n", r.volume, r.input_volume);
  }
  return 0;
}

}  // namespace cover::cli
