#include "cover/cli/commands.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/brep/halfedge.h"
#include "cover/cli/output.h"
#include "cover/cli/points.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/png.h"
#include "cover/io/scene.h"
#include "cover/model/info.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"

namespace cover::cli {
namespace {

using nlohmann::json;

/// One leaf of `cover info --json` (docs/cli.md "info").
/// A field leaf's entry: kind "field", threshold, support box and primitives.
json field_json(const LeafInfo& leaf) {
  json j;
  j["name"] = leaf.name;
  if (!leaf.origin.empty()) j["origin"] = leaf.origin;
  j["kind"] = "field";
  j["threshold"] = leaf.threshold;
  j["bbox"] = to_json(leaf.bbox);  // the support box
  json& prims = j["primitives"] = json::array();
  for (const FieldPrimitive& p : leaf.field->primitives) {
    json pj;
    pj["skeleton"] = std::string(to_string(p.kind));
    if (p.kind == SkeletonKind::kMesh) {
      pj["triangles"] = p.points.size() / 3;
      pj["bbox"] = {to_json(p.mesh->nodes[0].box.min), to_json(p.mesh->nodes[0].box.max)};
    } else if (p.kind == SkeletonKind::kCircle) {
      pj["center"] = to_json(p.points[0]);
      pj["normal"] = to_json(p.points[1]);
      pj["circle_radius"] = p.circle_radius;
    } else {
      pj["points"] = json::array();
      for (const Vec3& v : p.points) pj["points"].push_back(to_json(v));
    }
    pj["radius"] = p.radius;
    pj["influence"] = p.influence;
    pj["exponent"] = p.exponent;
    pj["weight"] = p.weight;
    prims.push_back(std::move(pj));
  }
  return j;
}

/// A warp leaf's entry: kind "warp", the warp, its axis and parameters, its box and the child's
/// leaf count.
json warp_json(const LeafInfo& leaf) {
  const WarpLeaf& w = *leaf.warp;
  json j;
  j["name"] = leaf.name;
  if (!leaf.origin.empty()) j["origin"] = leaf.origin;
  j["kind"] = "warp";
  j["warp"] = std::string(to_string(w.kind));
  j["axis"] = {{"point", to_json(w.point)}, {"direction", to_json(w.direction)}};
  if (w.kind == WarpKind::kTwist) j["degrees_per_unit"] = w.degrees_per_unit;
  if (w.kind != WarpKind::kTwist) j["range"] = {w.range[0], w.range[1]};
  if (w.kind == WarpKind::kTaper) j["scale"] = {w.scale[0], w.scale[1]};
  if (w.kind == WarpKind::kBend) {
    j["toward"] = to_json(w.toward);
    j["center"] = w.center;
    j["radius"] = w.radius;
  }
  j["bbox"] = to_json(leaf.bbox);
  j["child_leaves"] = leaf.child_leaves;
  return j;
}

json leaf_json(const LeafInfo& leaf) {
  if (leaf.field) return field_json(leaf);
  if (leaf.warp) return warp_json(leaf);
  const MeshReport& r = leaf.report;
  json j;
  j["name"] = leaf.name;
  if (!leaf.origin.empty()) j["origin"] = leaf.origin;
  j["kind"] = "mesh";
  j["vertices"] = leaf.vertices;
  j["faces"] = leaf.faces;
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
  j["self_touching"] = r.self_touching ? json(*r.self_touching) : json(nullptr);
  j["volume"] = r.volume;
  j["bbox"] = to_json(leaf.bbox);
  if (leaf.brep) {
    const brep::BrepReport& b = *leaf.brep;
    j["brep"] = {
        {"closed", b.closed},         {"manifold", b.manifold},
        {"euler", b.euler},           {"genus", b.genus >= 0 ? json(b.genus) : json(nullptr)},
        {"components", b.components}, {"boundary_loops", b.boundary_loops}};
  } else {
    j["brep"] = nullptr;
  }
  const RepairReport& rr = leaf.repair;
  j["repair"] = {{"welded_vertices", rr.welded_vertices},
                 {"zero_area_faces", rr.zero_area_faces},
                 {"boundary_edges", rr.boundary_edges},
                 {"edges", rr.edges}};
  j["rule"] = rr.rule();
  j["boundary_edge_fraction"] = rr.boundary_edge_fraction();
  return j;
}

json camera_json(const Camera& c) {
  json j;
  j["type"] = c.perspective ? "perspective" : "orthographic";
  j["width"] = c.width;
  j["height"] = c.height;
  j["eye"] = to_json(c.eye);
  j["forward"] = to_json(c.forward);
  j["right"] = to_json(c.right);
  j["up"] = to_json(c.up);
  if (c.perspective)
    j["tan_half_fov"] = c.tan_half_fov;
  else
    j["pixel_size"] = c.pixel_size;
  j["depth_near"] = c.near;
  j["depth_far"] = c.far;
  j["pixel_ray"] = c.perspective
                       ? "origin = eye; dir = normalize(forward + s*(px+0.5-width/2)*right + "
                         "s*(height/2-py-0.5)*up), s = 2*tan_half_fov/min(width,height)"
                       : "origin = eye + pixel_size*((px+0.5-width/2)*right + "
                         "(height/2-py-0.5)*up); dir = forward";
  j["depth_png"] = "t = depth_near + value/65534*(depth_far-depth_near); 65535 = no surface";
  return j;
}

}  // namespace

std::string flag_of(std::string_view name) {
  if (name == "resolution") return "--res";
  if (name == "width, height") return "--size";
  if (name == "require_closed") return "--closed-only";
  if (name == "crease_degrees") return "--crease";
  std::string out = "--" + std::string(name);
  std::replace(out.begin(), out.end(), '_', '-');
  return out;
}

Model load_model(const std::string& input, const LoadOptions& options,
                 const std::string& closed_needed, const std::string& field_reason,
                 bool curved_ok) {
  Model model = load(input, options);
  // curved_ok with field or warp leaves: accepted, open leaves beside them included.
  const bool check = !closed_needed.empty() && !(curved_ok && model.solid().has_implicit_leaf());
  if (check)
    for (const Leaf& l : model.solid().leaves)
      if (l.open())
        throw InputError(l.name + ": open mesh (" + std::to_string(l.boundary_edges) +
                         " boundary edges): " + closed_needed);
  if (check)
    for (const Leaf& l : model.solid().leaves)
      if (l.is_implicit()) {
        std::string reason = field_reason.empty() ? closed_needed : field_reason;
        if (const size_t at = reason.find("closed leaves"); at != std::string::npos)
          reason.replace(at, 13, "closed mesh leaves");
        throw InputError(input + ": " + l.origin +
                         (l.is_field() ? ": field leaf: " : ": warp leaf: ") + reason);
      }
  for (const std::string& w : model.warnings(flag_of))
    std::fprintf(stderr, "cover: warning: %s\n", w.c_str());
  return model;
}

int run_info(const InfoOptions& o, const CommonOptions& common) {
  Timing timing;
  LoadOptions lo = common.load_options();
  lo.require_closed = false;  // info reports open leaves instead of rejecting them
  lo.orient_outward = false;  // and reports orientation as found in the input
  lo.repair = false;          // and the faces as found (no loop collapse, no re-orientation)
  const Model model = load_model(o.input, lo);
  const Solid& s = model.solid();
  timing.lap(Timing::kLoad);
  const ModelInfo facts = info(model, {.check_self_intersection = o.check_self_intersection});
  json j;
  j["input"] = o.input;
  j["vertices"] = facts.vertices;
  j["faces"] = facts.faces;
  j["leaves"] = facts.leaves.size();
  j["bbox"] = to_json(facts.bbox);
  j["leaves_info"] = json::array();
  for (const LeafInfo& leaf : facts.leaves) j["leaves_info"].push_back(leaf_json(leaf));
  timing.lap(Timing::kKernel);
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::printf("%s: %zu vertices, %zu faces, %zu leaves\n", o.input.c_str(), s.vertices.size(),
              s.face_count(), s.leaves.size());
  const Bbox b = s.bbox();
  if (!b.empty())
    std::printf("bbox: [%.17g, %.17g, %.17g] .. [%.17g, %.17g, %.17g]\n", b.min.x, b.min.y, b.min.z,
                b.max.x, b.max.y, b.max.z);
  for (const json& leaf : j["leaves_info"]) {
    auto yes = [&](const char* k) { return leaf[k].get<bool>() ? "yes" : "no"; };
    std::printf(
        "leaf %s%s\n", leaf["name"].get<std::string>().c_str(),
        leaf.contains("origin") ? (" at " + leaf["origin"].get<std::string>()).c_str() : "");
    if (leaf["kind"] == "warp") {
      std::printf("  warp: %s of %zu leaf(s), box %s\n", leaf["warp"].get<std::string>().c_str(),
                  leaf["child_leaves"].get<size_t>(), leaf["bbox"].dump().c_str());
      continue;
    }
    if (leaf["kind"] == "field") {
      const json& sb = leaf["bbox"];
      std::printf("  field: %zu primitive(s), threshold %.17g, support box %s\n",
                  leaf["primitives"].size(), leaf["threshold"].get<double>(), sb.dump().c_str());
      for (const json& p : leaf["primitives"])
        std::printf("    %s weight %+d: radius %.17g, influence %.17g, exponent %d\n",
                    p["skeleton"].get<std::string>().c_str(), p["weight"].get<int>(),
                    p["radius"].get<double>(), p["influence"].get<double>(),
                    p["exponent"].get<int>());
      continue;
    }
    std::printf("  closed %s, manifold %s, oriented %s, outward %s\n", yes("closed"),
                yes("manifold"), yes("oriented"), yes("outward"));
    std::printf(
        "  boundary edges %lld, non-manifold edges %lld, components %lld, genus %s\n",
        leaf["boundary_edges"].get<long long>(), leaf["nonmanifold_edges"].get<long long>(),
        leaf["components"].get<long long>(),
        leaf["genus"].is_null() ? "n/a" : std::to_string(leaf["genus"].get<long long>()).c_str());
    std::printf("  degenerate faces %lld, self-intersecting %s, covering volume %.17g\n",
                leaf["degenerate_faces"].get<long long>(),
                leaf["self_intersecting"].is_null()     ? "not checked"
                : leaf["self_intersecting"].get<bool>() ? "yes"
                : leaf["self_touching"].get<bool>()
                    ? "no (touches itself at vertices of equal coordinates)"
                    : "no",
                leaf["volume"].get<double>());
    const json& rp = leaf["repair"];
    std::printf(
        "  rule %s; on load: %lld duplicate vertices welded, %lld zero-area faces dropped, "
        "%lld boundary edges left (%.4g of %lld edges)\n",
        leaf["rule"].get<std::string>().c_str(), rp["welded_vertices"].get<long long>(),
        rp["zero_area_faces"].get<long long>(), rp["boundary_edges"].get<long long>(),
        leaf["boundary_edge_fraction"].get<double>(), rp["edges"].get<long long>());
    const json& b = leaf["brep"];
    if (b.is_null())
      std::printf("  half-edge kernel: not an oriented surface\n");
    else
      std::printf(
          "  half-edge kernel: euler %lld, boundary loops %lld, genus %s\n",
          b["euler"].get<long long>(), b["boundary_loops"].get<long long>(),
          b["genus"].is_null() ? "n/a" : std::to_string(b["genus"].get<long long>()).c_str());
  }
  return 0;
}

int run_volume(const VolumeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  // --exact on a tree with field or warp leaves: the mesh leaves stay exact inside the bracket
  // method's certified bound (curved solids have no exact volume in doubles); an open leaf
  // without them has only the winding method's estimate, which --exact refuses.
  const Model model = load_model(
      o.input, common.load_options(),
      o.exact ? "no exact volume; the winding method estimates it (without --exact)" : "", "",
      true);
  const bool curved = model.solid().has_implicit_leaf();
  if (o.exact && curved)
    std::fprintf(stderr,
                 "cover: note: %s: --exact: field and warp leaves have no exact volume; the "
                 "bracket method bounds it (mesh leaves are settled exactly inside it)\n",
                 o.input.c_str());
  if (!model.bounded()) throw InputError(unbounded_message(o.input));
  timing.lap(Timing::kLoad);
  VolumeOptions vo;
  vo.rays = static_cast<int>(o.rays);
  vo.exact = o.exact;
  if (o.tolerance) vo.target_relative_error = vo.bracket_relative_error = *o.tolerance;
  Progress progress("volume", common.quiet);
  vo.progress = [&](double fraction) {
    progress.update(static_cast<size_t>(1000 * fraction), 1000);
  };
  // The covering where exact, else rays with their proven bound, else (--exact, or a bound that
  // misses the target) the evaluated B-rep's exact volume and area (Model::volume).
  VolumeResult r;
  try {
    r = model.volume(vo);
  } catch (const InputError& e) {
    throw e.prefixed(o.input + ": --exact: ");  // a leaf evaluate() refuses
  }
  progress.finish();
  timing.lap(Timing::kKernel);
  if (!r.target_met && r.method == "rays")
    std::fprintf(stderr,
                 "cover: warning: %s: the ray volume's proven error bound %g is above the target "
                 "(relative %g) after %zu rays, and B-rep evaluation is not available for it\n",
                 o.input.c_str(), r.error_bound, vo.target_relative_error, r.rays);
  if (!r.target_met && r.method == "bracket")
    std::fprintf(stderr,
                 "cover: warning: %s: the bracket's certified half-width %g is above the target "
                 "(relative %g) after %zu cells (the cell budget)\n",
                 o.input.c_str(), r.error_bound, vo.bracket_relative_error, r.rays);
  json j;
  j["volume"] = r.volume;
  j["area"] = r.area ? json(*r.area) : json(nullptr);
  j["method"] = r.method;
  j["error_bound"] = r.error_bound;
  if (r.method == "rays") j["rays"] = r.rays;
  if (r.method == "bracket") {
    j["cells"] = r.rays;
    j["tolerance"] = vo.bracket_relative_error;
    j["target_met"] = r.target_met;
  }
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("volume %.17g (%s, error bound %g)\n", r.volume, r.method.c_str(), r.error_bound);
    if (r.area) std::printf("area %.17g\n", *r.area);
  }
  return 0;
}

int run_classify(const ClassifyCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!o.output.empty()) check_classes_path(o.output);
  const Model model = load_model(o.input, common.load_options());
  // Per point: the point, its class, and its output: a line of at most 8 bytes ("outside\n"), or
  // a JSON string value (16 bytes, its heap string ~48, room for the array's growth, the dump);
  // --output writes the classes themselves.
  const size_t bytes_per_point = sizeof(Vec3) + sizeof(PointClass) +
                                 (!o.output.empty() ? 0
                                  : common.json     ? 96
                                                    : 8);
  const std::vector<Vec3> points =
      read_points(o.points, common.max_memory_bytes(), bytes_per_point);
  timing.lap(Timing::kLoad);
  // Batches keep the progress bar moving; results do not depend on the batch size.
  constexpr size_t kBatch = 1 << 20;
  std::vector<PointClass> classes;
  classes.reserve(points.size());
  size_t uncertain = 0;
  Progress progress("classify", common.quiet);
  for (size_t begin = 0; begin < points.size(); begin += kBatch) {
    const size_t n = std::min(kBatch, points.size() - begin);
    const Classification part =
        model.classify_counted(std::span<const Vec3>(points.data() + begin, n));
    classes.insert(classes.end(), part.classes.begin(), part.classes.end());
    uncertain += part.uncertain;
    progress.update(begin + n, points.size());
  }
  progress.finish();
  timing.lap(Timing::kKernel);
  std::array<size_t, 5> counts{};
  for (PointClass c : classes) ++counts[static_cast<size_t>(c)];
  if (!o.output.empty()) {
    OutputBatch outputs;
    write_classes(o.output, classes);
    outputs.commit();
  }
  std::string out;
  if (common.json) {
    json j;
    if (o.output.empty()) {
      j["classes"] = json::array();
      for (PointClass c : classes) j["classes"].push_back(std::string(to_string(c)));
    }
    json& cj = j["counts"];
    for (size_t k = 0; k < counts.size(); ++k)
      cj[std::string(to_string(static_cast<PointClass>(k)))] = counts[k];
    j["uncertain"] = uncertain;
    timing.lap(Timing::kWrite);
    timing.put(j);
    out = j.dump() + "\n";
  } else if (!o.output.empty()) {
    out = o.output + ": " + std::to_string(classes.size()) + " points (";
    for (size_t k = 0; k < counts.size(); ++k)
      out += std::string(k ? ", " : "") + std::string(to_string(static_cast<PointClass>(k))) + " " +
             std::to_string(counts[k]);
    out += ")\n";
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

int run_field(const FieldCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  const Model model = load_model(o.input, common.load_options());
  const size_t leaves = std::count_if(model.solid().leaves.begin(), model.solid().leaves.end(),
                                      [](const Leaf& l) { return l.is_implicit(); });
  if (leaves == 0) throw InputError(o.input + ": no field leaf (field and blend nodes)");
  // Per point: the point, and per field leaf its value (32 bytes) and a printed line or JSON
  // numbers (~100 bytes).
  const std::vector<Vec3> points =
      read_points(o.points, common.max_memory_bytes(), sizeof(Vec3) + leaves * 132);
  timing.lap(Timing::kLoad);
  const Model::FieldValues f = model.field(points);
  timing.lap(Timing::kKernel);
  std::string out;
  if (common.json) {
    json j;
    j["leaves"] = json::array();
    for (uint32_t l : f.leaves) j["leaves"].push_back(model.solid().leaves[l].origin);
    json& values = j["field"] = json::array();
    json& gradients = j["gradient"] = json::array();
    for (size_t i = 0; i < points.size(); ++i) {
      json v = json::array(), g = json::array();
      for (size_t k = 0; k < leaves; ++k) {
        const field::FieldValue& x = f.values[i * leaves + k];
        v.push_back(x.value);
        g.push_back({x.gradient.x, x.gradient.y, x.gradient.z});
      }
      values.push_back(leaves == 1 ? v[0] : v);
      gradients.push_back(leaves == 1 ? g[0] : g);
    }
    timing.lap(Timing::kWrite);
    timing.put(j);
    out = j.dump() + "\n";
  } else {
    // One line per point: f gx gy gz for each field leaf in turn (%.17g: the doubles themselves).
    char buf[128];
    for (size_t i = 0; i < points.size(); ++i) {
      for (size_t k = 0; k < leaves; ++k) {
        const field::FieldValue& x = f.values[i * leaves + k];
        std::snprintf(buf, sizeof buf, "%s%.17g %.17g %.17g %.17g", k ? " " : "", x.value,
                      x.gradient.x, x.gradient.y, x.gradient.z);
        out += buf;
      }
      out += '\n';
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

}  // namespace cover::cli

namespace cover::cli {

namespace {

/// One frame of `cover render`: its camera options and the suffix of its files ("" for a
/// single frame, "_000" ... for --turntable, "_iso" ... for --views).
struct Frame {
  std::string suffix;
  CameraOptions camera;
};

/// PATH with `suffix` before its extension (out.png, "_iso" → out_iso.png).
std::string with_suffix(const std::string& path, const std::string& suffix) {
  if (path.empty() || suffix.empty()) return path;
  const std::filesystem::path p = path;
  return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

/// The frames of --turntable N (azimuth 360·k/N from the chosen view) or --views a,b,c (each
/// named view), else the one frame of the options.
std::vector<Frame> render_frames(const RenderCommandOptions& o, const CameraOptions& base) {
  std::vector<Frame> frames;
  if (o.turntable > 0) {
    const int digits = std::max<int>(3, std::to_string(o.turntable - 1).size());
    for (int k = 0; k < o.turntable; ++k) {
      std::string number = std::to_string(k);
      number.insert(number.begin(), static_cast<size_t>(digits) - number.size(), '0');
      Frame f{"_" + number, base};
      f.camera.azimuth_degrees = base.azimuth_degrees + 360.0 * k / o.turntable;
      f.camera.turntable = true;  // one framing for every frame
      frames.push_back(std::move(f));
    }
  } else if (!o.views.empty()) {
    std::vector<std::string> seen;
    size_t begin = 0;
    for (;;) {
      const size_t end = std::min(o.views.find(',', begin), o.views.size());
      const std::string name = o.views.substr(begin, end - begin);
      if (std::find(seen.begin(), seen.end(), name) != seen.end())
        throw InputError("--views: view '" + name + "' given twice");
      Frame f{"_" + name, base};
      f.camera.view = parse_view(name);  // "--view: unknown view ..." names the option
      seen.push_back(name);
      frames.push_back(std::move(f));
      if (end == o.views.size()) break;
      begin = end + 1;
    }
  } else {
    frames.push_back({"", base});
  }
  return frames;
}

}  // namespace

int run_render(const RenderCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  for (const std::string& image : {o.output, o.depth, o.ids})
    if (!image.empty()) check_png_path(image);
  CameraOptions co;
  co.view = parse_view(o.view);
  co.perspective = o.perspective;
  co.up = parse_up(o.up);  // "--up: expected x, y or z, got 'w'"
  co.elevation_degrees = o.elevation;
  co.azimuth_degrees = o.azimuth;
  co.zoom = o.zoom;
  if (!o.pan.empty()) {
    const std::vector<double> pan = parse_numbers(o.pan, "--pan", 2, ",");
    co.pan = {pan[0], pan[1]};
  }
  co.fit = o.fit;
  if (o.fit && o.section.empty()) throw InputError("--fit: needs a --section");
  const std::vector<double> size = parse_numbers(o.size, "--size", 2, "xX");
  if (size[0] < 1 || size[1] < 1 || size[0] > 16384 || size[1] > 16384 ||
      size[0] != std::floor(size[0]) || size[1] != std::floor(size[1]))
    throw InputError("--size: expected WxH with whole numbers from 1 to 16384, got '" + o.size +
                     "'");
  co.width = static_cast<int>(size[0]);
  co.height = static_cast<int>(size[1]);
  // Frames are rendered one after the other: one frame's buffers at a time.
  if (o.samples < 1 || o.samples > kMaxRenderSamples)
    throw InputError("--samples: expected a whole number from 1 to " +
                     std::to_string(kMaxRenderSamples) + ", got " + std::to_string(o.samples));
  check_memory(
      render_bytes(co.width, co.height, o.samples), common.max_memory_bytes(),
      "--size " + o.size +
          (o.samples > 1 ? " with --samples " + std::to_string(o.samples) : std::string()) +
          ": the image");
  RenderOptions ro;
  ro.outline = o.outline;
  ro.samples = o.samples;
  ro.crease_degrees = o.crease;
  const std::vector<double> bg = parse_numbers(o.background, "--background", 3, ",");
  for (int c = 0; c < 3; ++c) {
    if (bg[c] < 0 || bg[c] > 255)
      throw InputError("--background: expected 3 numbers from 0 to 255");
    ro.background[c] = static_cast<uint8_t>(bg[c]);
  }
  if (!o.section.empty()) {
    const std::vector<double> p = parse_numbers(o.section, "--section", 4, ",");
    if (p[0] == 0 && p[1] == 0 && p[2] == 0)
      throw InputError("--section: the normal must be non-zero");
    ro.section = Plane{{p[0], p[1], p[2]}, p[3]};
  }
  const std::vector<Frame> frames = render_frames(o, co);
  const Model model = load_model(o.input, common.load_options());
  timing.lap(Timing::kLoad);
  // Every frame through the one Model: one load (and one BVH, where a frame walks one: open
  // leaves) for all of them. Each frame's files join the batch as soon as it is
  // drawn (frames one at a time); all are committed together.
  Progress progress("render", common.quiet);
  OutputBatch outputs;
  json frames_json = json::array();
  for (size_t f = 0; f < frames.size(); ++f) {
    // Frames the result's box, or with --fit what the section keeps (Model::camera).
    const Camera camera = model.camera(frames[f].camera, ro.section);
    ro.progress = [&](size_t done, size_t total) {
      progress.update(f * total + done, frames.size() * total);
    };
    const Image image = model.render(camera, ro);
    timing.lap(Timing::kKernel);
    const std::string& sfx = frames[f].suffix;
    write_png_rgb(with_suffix(o.output, sfx), image.width, image.height, image.rgb);
    if (!o.depth.empty())
      write_png_gray16(with_suffix(o.depth, sfx), image.width, image.height, image.depth);
    if (!o.ids.empty())
      write_png_gray16(with_suffix(o.ids, sfx), image.width, image.height, image.ids);
    timing.lap(Timing::kWrite);
    json fj;
    fj["output"] = with_suffix(o.output, sfx);
    fj["camera"] = camera_json(camera);
    frames_json.push_back(std::move(fj));
  }
  progress.finish();
  outputs.commit();
  timing.lap(Timing::kWrite);
  const Solid& s = model.solid();
  json j;
  j["width"] = co.width;
  j["height"] = co.height;
  // Rays cast: the sub-pixel image's and the pixel-centre rays with samples > 1 (render.h).
  const size_t rays_per_pixel = o.samples > 1 ? size_t(o.samples) * o.samples + 1 : 1;
  j["samples"] = o.samples;
  j["rays"] = static_cast<size_t>(co.width) * co.height * rays_per_pixel * frames.size();
  timing.put(j);
  j["camera"] = frames_json[0]["camera"];
  if (frames.size() > 1) j["frames"] = std::move(frames_json);
  j["ids"] = json::object({{"0", "background"}, {"65535", "section cap"}});
  for (size_t l = 0; l < s.leaves.size(); ++l) j["ids"][std::to_string(l + 1)] = s.leaves[l].name;
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else if (frames.size() == 1) {
    std::printf("%s: %dx%d, %zu rays, %.3f s\n", o.output.c_str(), co.width, co.height,
                static_cast<size_t>(co.width) * co.height * rays_per_pixel,
                j["seconds"].get<double>());
  } else {
    std::printf("%zu frames %s ... %s: %dx%d, %zu rays, %.3f s\n", frames.size(),
                with_suffix(o.output, frames.front().suffix).c_str(),
                with_suffix(o.output, frames.back().suffix).c_str(), co.width, co.height,
                static_cast<size_t>(co.width) * co.height * frames.size(),
                j["seconds"].get<double>());
  }
  return 0;
}

}  // namespace cover::cli
