// `cover polygonize INPUT -o OUT [--resolution N | --cell-size H] [--tolerance T]`
// (docs/cli.md): the whole result's boundary by certified marching tetrahedra
// (polygonize/polygonize.h), for any tree: closed, outward, 2-manifold, free of
// self-intersections, every vertex within the reported tolerance of the surface.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"

namespace cover::cli {

int run_polygonize(const PolygonizeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!is_mesh_output_extension(o.output))
    throw InputError(o.output + ": unsupported output format (use " + kMeshOutputFormats + ")");
  const Model model = load_model(o.input, common.load_options());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  PolygonizeOptions po;
  po.resolution = o.resolution;
  po.cell_size = o.cell_size;
  po.tolerance = o.tolerance;
  po.max_memory_bytes = common.max_memory_bytes();
  const PolygonizeResult r = model.polygonize(po);
  timing.lap(Timing::kKernel);
  if (r.mesh.face_count() == 0)
    std::fprintf(stderr, "cover: warning: the grid found no inside point; writing an empty mesh\n");
  if (r.uncertain > 0)
    std::fprintf(stderr,
                 "cover: warning: %zu points could not be classified with certainty (circle "
                 "skeletons); vertices built from them are not certified\n",
                 r.uncertain);
  OutputBatch outputs;
  write_mesh(o.output, r.mesh);
  outputs.commit();
  timing.lap(Timing::kWrite);
  nlohmann::json j;
  j["vertices"] = r.mesh.vertices.size();
  j["faces"] = r.mesh.face_count();
  j["volume"] = signed_volume(r.mesh);
  j["cell_size"] = r.cell_size;
  j["tolerance"] = r.tolerance;
  j["cells"] = r.cells;
  j["grid_points"] = r.grid_points;
  j["bisections"] = r.bisections;
  j["uncertain"] = r.uncertain;
  j["clipped"] = r.clipped;
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("wrote %s: %zu vertices, %zu faces (cell %.17g)\n", o.output.c_str(),
                r.mesh.vertices.size(), r.mesh.face_count(), r.cell_size);
    std::printf("tolerance %.17g (every vertex within it of the surface)\nvolume %.17g\n",
                r.tolerance, signed_volume(r.mesh));
  }
  return 0;
}

}  // namespace cover::cli
