// `cover distance INPUT --points FILE [--output D.npy] [--json]` (docs/cli.md): the signed
// distance of each point to the result's boundary (Model::distance): negative inside, the sign
// exact (classify), the magnitude the distance to the evaluated B-rep.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/cli/points.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/npy.h"
#include "cover/io/parse.h"
#include "cover/solid/errors.h"

namespace cover::cli {
namespace {

void write_distances(const std::string& path, const std::vector<double>& d) {
  const std::array<uint64_t, 1> shape{d.size()};
  const std::string header = npy_header("<f8", shape);
  write_atomically(
      path,
      [&](const std::filesystem::path& temporary) {
        std::FILE* file = std::fopen(temporary.c_str(), "wb");
        if (file == nullptr)
          detail::fail_file(path, std::string("cannot write: ") + std::strerror(errno));
        const bool written =
            std::fwrite(header.data(), 1, header.size(), file) == header.size() &&
            (d.empty() || std::fwrite(d.data(), sizeof(double), d.size(), file) == d.size()) &&
            std::fflush(file) == 0;
        const int error = errno;
        if (std::fclose(file) != 0 || !written)
          detail::fail_file(path,
                            std::string("cannot write: ") + std::strerror(written ? errno : error));
        return true;
      },
      "the distances");
}

}  // namespace

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
    write_distances(o.output, d.distance);
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
