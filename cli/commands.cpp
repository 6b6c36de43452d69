#include "cli/commands.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/output.h"
#include "cli/points.h"
#include "covering/classify.h"
#include "covering/volume.h"
#include "solid/scene.h"
#include "solid/validate.h"

namespace cover::cli {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

void print_warnings(const LoadedInput& in) {
  for (const std::string& w : in.warnings) std::fprintf(stderr, "cover: warning: %s\n", w.c_str());
}

json leaf_json(const Solid& s, uint32_t l, const MeshReport& r) {
  const Leaf& leaf = s.leaves[l];
  json j;
  j["name"] = leaf.name;
  if (!leaf.origin.empty()) j["origin"] = leaf.origin;
  j["vertices"] = leaf.vertex_count;
  j["faces"] = leaf.face_count;
  j["closed"] = r.closed;
  j["manifold"] = r.manifold;
  j["oriented"] = r.oriented;
  j["outward"] = r.outward;
  j["boundary_edges"] = r.boundary_edges;
  j["nonmanifold_edges"] = r.nonmanifold_edges;
  j["components"] = r.components;
  j["genus"] = r.genus >= 0 ? json(r.genus) : json(nullptr);
  j["degenerate_faces"] = r.degenerate_faces;
  j["self_intersecting"] = r.self_intersecting ? json(*r.self_intersecting) : json(nullptr);
  j["volume"] = r.volume;
  j["bbox"] = to_json(leaf.bbox);
  return j;
}

}  // namespace

int run_info(const InfoOptions& o, const CommonOptions& common) {
  LoadOptions lo;
  lo.require_closed = false;  // info reports open leaves instead of rejecting them
  lo.orient_outward = false;  // and reports orientation as found in the input
  const LoadedInput in = load_input(o.input, lo);
  const Solid& s = in.solid;
  json j;
  j["input"] = o.input;
  j["vertices"] = s.vertices.size();
  j["faces"] = s.face_count();
  j["leaves"] = s.leaves.size();
  j["bbox"] = to_json(s.bbox());
  j["leaves_info"] = json::array();
  ValidateOptions vo;
  vo.check_self_intersection = o.check_self_intersection;
  for (uint32_t l = 0; l < s.leaves.size(); ++l)
    j["leaves_info"].push_back(leaf_json(s, l, validate_mesh(leaf_mesh(s, l), vo)));
  if (common.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("%s: %zu vertices, %zu faces, %zu leaves\n", o.input.c_str(), s.vertices.size(),
              s.face_count(), s.leaves.size());
  const Bbox b = s.bbox();
  if (!b.empty())
    std::printf("bbox: [%.17g, %.17g, %.17g] .. [%.17g, %.17g, %.17g]\n", b.min.x, b.min.y,
                b.min.z, b.max.x, b.max.y, b.max.z);
  for (const json& leaf : j["leaves_info"]) {
    auto yes = [&](const char* k) { return leaf[k].get<bool>() ? "yes" : "no"; };
    std::printf("leaf %s%s\n", leaf["name"].get<std::string>().c_str(),
                leaf.contains("origin") ? (" at " + leaf["origin"].get<std::string>()).c_str() : "");
    std::printf("  closed %s, manifold %s, oriented %s, outward %s\n", yes("closed"),
                yes("manifold"), yes("oriented"), yes("outward"));
    std::printf("  boundary edges %lld, non-manifold edges %lld, components %lld, genus %s\n",
                leaf["boundary_edges"].get<long long>(), leaf["nonmanifold_edges"].get<long long>(),
                leaf["components"].get<long long>(),
                leaf["genus"].is_null() ? "n/a" : std::to_string(leaf["genus"].get<long long>()).c_str());
    std::printf("  degenerate faces %lld, self-intersecting %s, covering volume %.17g\n",
                leaf["degenerate_faces"].get<long long>(),
                leaf["self_intersecting"].is_null() ? "not checked"
                : leaf["self_intersecting"].get<bool>() ? "yes" : "no",
                leaf["volume"].get<double>());
  }
  return 0;
}

int run_volume(const VolumeCommandOptions& o, const CommonOptions& common) {
  const auto start = Clock::now();
  const LoadedInput in = load_input(o.input);
  print_warnings(in);
  VolumeOptions vo;
  vo.exact = o.exact;
  vo.rays = static_cast<int>(o.rays);
  const VolumeResult r = volume(in.solid, vo);
  json j;
  j["volume"] = r.volume;
  j["area"] = r.area ? json(*r.area) : json(nullptr);
  j["method"] = r.method;
  j["error_bound"] = r.error_bound;
  if (r.method == "rays") j["rays"] = r.rays;
  j["seconds"] = seconds_since(start);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("volume %.17g (%s, error bound %g)\n", r.volume, r.method.c_str(), r.error_bound);
    if (r.area) std::printf("area %.17g\n", *r.area);
  }
  return 0;
}

int run_classify(const ClassifyCommandOptions& o, const CommonOptions& common) {
  const LoadedInput in = load_input(o.input);
  print_warnings(in);
  const auto start = Clock::now();
  const std::vector<Vec3> points = read_points(o.points);
  // Batches keep the progress bar moving; results do not depend on the batch size.
  constexpr size_t kBatch = 1 << 20;
  std::vector<PointClass> classes;
  classes.reserve(points.size());
  Progress progress("classify", common.quiet);
  const Bvh bvh(in.solid);
  for (size_t begin = 0; begin < points.size(); begin += kBatch) {
    const size_t n = std::min(kBatch, points.size() - begin);
    const auto part = classify(in.solid, bvh, std::span<const Vec3>(points.data() + begin, n));
    classes.insert(classes.end(), part.begin(), part.end());
    progress.update(begin + n, points.size());
  }
  const double seconds = seconds_since(start);
  std::array<size_t, 5> counts{};
  for (PointClass c : classes) ++counts[static_cast<size_t>(c)];
  std::string out;
  if (common.json) {
    json j;
    j["classes"] = json::array();
    for (PointClass c : classes) j["classes"].push_back(std::string(to_string(c)));
    json& cj = j["counts"];
    for (size_t k = 0; k < counts.size(); ++k)
      cj[std::string(to_string(static_cast<PointClass>(k)))] = counts[k];
    j["seconds"] = seconds;
    out = j.dump() + "\n";
  } else {
    out.reserve(classes.size() * 8);
    for (PointClass c : classes) {
      out += to_string(c);
      out += '\n';
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

}  // namespace cover::cli
