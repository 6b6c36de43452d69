// `cover distance INPUT --points FILE [--output D.npy] [--json]` (docs/cli.md): the signed
// distance of each point to the result's boundary (Model::distance): negative inside, the sign
// exact (classify), the magnitude the distance to the evaluated B-rep.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/cli/points.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/solid/errors.h"

namespace cover::cli {
int run_distance(const DistanceCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!o.output.empty()) check_classes_path(o.output);  // an .npy path
  const Model model = load_model(o.input, common.load_options());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  const std::vector<Vec3> points =
      read_points(o.points, common.max_memory_bytes(),
                  sizeof(Vec3) + sizeof(double) + 1 + (common.json ? 64 : 26));
  timing.lap(Timing::kLoad);
  const Model::Distances d = model.distance(points);
  timing.lap(Timing::kKernel);
  if (!o.output.empty()) {
    OutputBatch outputs;
    static_assert(sizeof(double) == 8, "distances are written as <f8");
    write_npy_vector(o.output, "<f8", d.distance.data(), d.distance.size(), sizeof(double),
                     "the distances");
    outputs.commit();
  }
  double tolerance = 0;
  for (const MeshedLeaf& m : d.meshed) tolerance = std::max(tolerance, m.tolerance);
  if (common.json) {
    nlohmann::json j;
    if (o.output.empty()) j["distances"] = d.distance;
    j["points"] = points.size();
    j["uncertain"] = d.uncertain;
    j["meshed"] = d.meshed.size();
    j["mesh_tolerance"] = tolerance;
    timing.lap(Timing::kWrite);
    timing.put(j);
    std::cout << j.dump() << "\n";
  } else if (o.output.empty()) {
    std::string out;
    char buffer[32];
    for (double x : d.distance) {
      std::snprintf(buffer, sizeof buffer, "%.17g\n", x);
      out += buffer;
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
  } else {
    std::printf("%s: %zu distances\n", o.output.c_str(), d.distance.size());
  }
  return 0;
}

}  // namespace cover::cli
