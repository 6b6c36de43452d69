#include "cover/io/scene.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "cover/field/field.h"
#include "cover/field/warp.h"
#include "cover/io/mesh_io.h"
#include "cover/io/parse.h"
#include "cover/io/point_set_io.h"
#include "cover/mesh/orient.h"
#include "cover/mesh/repair.h"
#include "cover/mesh/triangulate.h"
#include "cover/mesh/validate.h"
#include "cover/modeler/ffd.h"
#include "cover/points/point_set.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "cover/subdivision/subdivide.h"

namespace cover {
namespace {

using nlohmann::json;

constexpr int kMaxDepth = 256;           // nesting of operations
constexpr int kMaxSubdivideLevels = 30;  // a subdivide node's "levels" (as `cover subdivide`)

/// Reads a scene in three steps. plan() walks the JSON in document order, checking its structure
/// and every primitive and transform, and lists the leaves (their meshes not yet read); the
/// leaves are then read, transformed and prepared in parallel, one task each (the load of a scene
/// of many large meshes is mostly reading and validating them); assemble() concatenates them
/// along the plan. Errors: the first structural error in document order, else the first leaf's
/// error in document order; warnings in document order. The result does not depend on threads.
class SceneReader {
 public:
  SceneReader(std::filesystem::path scene, LoadOptions options, std::vector<std::string>& warnings)
      : scene_(std::move(scene)), options_(options), warnings_(warnings) {}

  /// The solid of the scene rooted at `j`.
  Solid read(const json& j) {
    const Plan plan = this->plan(j, "", Transform{}, 0);
    read_files();
    std::vector<Solid> solids(tasks_.size());
    std::vector<std::vector<std::string>> warnings(tasks_.size());
    std::vector<std::exception_ptr> errors(tasks_.size());
    parallel_for(tasks_.size(), 1, [&](size_t begin, size_t end) {
      for (size_t t = begin; t < end; ++t) {
        try {
          solids[t] = run(tasks_[t], warnings[t]);
        } catch (...) {
          errors[t] = std::current_exception();
        }
      }
    });
    for (size_t t = 0; t < tasks_.size(); ++t) {
      if (errors[t]) std::rethrow_exception(errors[t]);
      warnings_.insert(warnings_.end(), warnings[t].begin(), warnings[t].end());
    }
    Solid out = assemble(plan, solids);
    // Colours: each leaf takes the "color" of the deepest node on its JSON path that has one.
    for (Leaf& leaf : out.leaves) {
      const json* node = &j;
      const json::json_pointer pointer(leaf.origin);
      std::vector<std::string> steps;
      for (json::json_pointer p = pointer; !p.empty(); p = p.parent_pointer())
        steps.push_back(p.back());
      for (auto s = steps.rbegin(); node; ++s) {
        if (node->is_object() && node->contains("color"))
          leaf.colour = colour(node->at("color"), "");
        if (s == steps.rend()) break;
        if (node->is_object() && node->contains(*s))
          node = &node->at(*s);
        else if (node->is_array() && !s->empty() &&
                 s->find_first_not_of("0123456789") == std::string::npos &&
                 std::stoul(*s) < node->size())
          node = &node->at(std::stoul(*s));
        else
          node = nullptr;
      }
    }
    return out;
  }

 private:
  /// One round of subdivide nodes over a leaf's mesh: subdivide() with `options`, then `world`
  /// (the node's transform) applied; `path` the node's JSON path, for messages.
  struct Subdivision {
    SubdivideOptions options;
    Transform world;
    std::string path;
    std::optional<FfdLattice> ffd = {};  ///< an ffd node instead (modeler/ffd.h)
    double ffd_tolerance = 0;
  };
  /// One leaf to make: a mesh file (read by read_files()) or a primitive's mesh (built by plan()),
  /// then refined by the subdivide nodes above it, innermost first.
  struct LeafTask {
    std::string path;            ///< its JSON path
    std::filesystem::path file;  ///< mesh leaves: the file; empty for primitives
    std::string kind;            ///< primitives: box, sphere or cylinder
    PolygonMesh mesh;            ///< primitives: the mesh (transformed)
    Transform world;             ///< mesh leaves: the transform to apply
    size_t read = 0;             ///< mesh leaves: its file's entry in reads_
    std::optional<Solid> made;   ///< field leaves: made (validated, placed) by plan()
    std::vector<Subdivision> subdivisions = {};  ///< subdivide nodes: the leaf's mesh refined
  };
  /// One distinct mesh file, read once however many leaves place it (instances: the 10-leaf
  /// preview scene reads 6 files for 10 leaves).
  struct FileRead {
    std::filesystem::path file;
    PolygonMesh mesh;                   ///< as read; each leaf transforms a copy
    std::vector<std::string> warnings;  ///< the reader's own, repeated for every leaf
    std::exception_ptr error;           ///< InputError of the reader
    /// validate_mesh of the mesh as read (full_report off): its edge counts and orientation hold
    /// for every leaf placing it whose loops need no repair (a transform moves vertices only;
    /// a mirror reverses every face, which keeps them), so the edge table is built once per
    /// file; each leaf still computes its own volume.
    MeshReport topology;
  };

  /// Reads every distinct file of the mesh leaves, in parallel (a file per task; a large OFF
  /// body is itself parsed in parallel chunks).
  void read_files() {
    parallel_for(reads_.size(), 1, [&](size_t begin, size_t end) {
      for (size_t r = begin; r < end; ++r) {
        try {
          reads_[r].mesh = read_mesh(reads_[r].file, options_.max_file_bytes, &reads_[r].warnings);
          reads_[r].topology = validate_mesh(reads_[r].mesh, leaf_validation());
        } catch (const InputError&) {
          reads_[r].error = std::current_exception();
        }
      }
    });
  }
  /// The expression: a leaf task, or an operation over plans.
  struct Plan {
    Plan(CsgOp o = CsgOp::kLeaf, size_t t = 0, std::vector<Plan> c = {})
        : op(o), task(t), children(std::move(c)) {}
    CsgOp op = CsgOp::kLeaf;
    size_t task = 0;
    std::vector<Plan> children;
    /// A warp node: its warp (parameters as written, in the node's frame), children[0] its
    /// child planned in that frame, `world` the node's transform, `path` its JSON path.
    std::optional<WarpLeaf> warp;
    Transform world;
    std::string path;
  };

  Plan plan(const json& j, const std::string& path, const Transform& parent, int depth) {
    if (depth > kMaxDepth) fail(path, "scene nested deeper than " + std::to_string(kMaxDepth));
    if (!j.is_object()) fail(path, "expected an object (a leaf or an operation)");
    Transform world = parent;
    std::string kind;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "transform") {
        world = parent * transform(it.value(), path + "/transform");
      } else if (it.key() == "color") {
        colour(it.value(), path + "/color");  // checked here, given to the leaves by read()
      } else if (kind.empty()) {
        kind = it.key();
      } else {
        fail(path, "more than one of leaf/operation keys ('" + kind + "', '" + it.key() + "')");
      }
    }
    if (kind.empty())
      fail(path,
           "expected one of mesh, box, sphere, cylinder, field, blend, twist, taper, bend, "
           "points, subdivide, ffd, union, intersection, difference, complement");
    const json& v = j.at(kind);
    const std::string sub = path + "/" + kind;
    if (kind == "mesh") {
      if (!v.is_string()) fail(sub, "expected a file path string");
      if (v.get_ref<const std::string&>().empty()) fail(sub, "expected a non-empty file path");
      std::filesystem::path file = v.get<std::string>();
      if (file.is_relative()) file = scene_.parent_path() / file;
      if (file.extension() == ".json") fail(sub, "a mesh leaf must be a mesh file, not a scene");
      const std::string key = file.lexically_normal().string();
      auto [it, fresh] = read_index_.try_emplace(key, reads_.size());
      if (fresh) reads_.emplace_back().file = file;
      tasks_.push_back({sub, std::move(file), {}, {}, world, it->second, {}});
      return {CsgOp::kLeaf, tasks_.size() - 1, {}};
    }
    if (kind == "box" || kind == "sphere" || kind == "cylinder") {
      PolygonMesh m = primitive(kind, v, sub);
      apply_transform(world, m);
      tasks_.push_back({sub, {}, kind, std::move(m), Transform{}, 0, {}});
      return {CsgOp::kLeaf, tasks_.size() - 1, {}};
    }
    if (kind == "points") {
      Solid made = point_set_leaf(v, sub, world);
      tasks_.push_back({sub, {}, kind, {}, Transform{}, 0, std::move(made)});
      return {CsgOp::kLeaf, tasks_.size() - 1, {}};
    }
    if (kind == "field" || kind == "blend") {
      // Made first: a throw inside the braced initializer would unwind a half-built task (GCC 12
      // destroys some of its members twice).
      Solid made = field_leaf(j, path, parent, depth);
      tasks_.push_back({sub, {}, kind, {}, Transform{}, 0, std::move(made)});
      return {CsgOp::kLeaf, tasks_.size() - 1, {}};
    }
    if (kind == "twist" || kind == "taper" || kind == "bend") {
      Plan out;
      out.warp = warp_params(kind, v, sub);
      out.world = world;
      out.path = sub;
      out.children.push_back(
          plan(required(v, sub, "child"), sub + "/child", Transform{}, depth + 1));
      return out;
    }
    if (kind == "subdivide") return subdivide_node(v, sub, world, depth);
    if (kind == "ffd") return ffd_node(v, sub, world, depth);
    if (kind == "complement") return {CsgOp::kComplement, 0, {plan(v, sub, world, depth + 1)}};
    if (kind == "union" || kind == "intersection" || kind == "difference") {
      if (!v.is_array() || v.empty()) fail(sub, "expected an array of one or more nodes");
      if (kind == "difference" && v.size() < 2) fail(sub, "expected two or more nodes");
      Plan out{kind == "union"          ? CsgOp::kUnion
               : kind == "intersection" ? CsgOp::kIntersection
                                        : CsgOp::kDifference,
               0,
               {}};
      for (size_t i = 0; i < v.size(); ++i)
        out.children.push_back(plan(v[i], sub + "/" + std::to_string(i), world, depth + 1));
      return out;
    }
    fail(path, "unknown key '" + kind + "'");
  }

  /// A subdivide node `v` at `path` (its transform included in `world`): one leaf, the mesh of
  /// its child (a mesh leaf, a primitive or another subdivide node, placed in the node's frame
  /// by its own transform) refined by subdivide() when the leaf is made, then placed by `world`.
  /// io does not depend on boolean (docs/design.md "Modules"), so an operation is not evaluated
  /// here: other children are refused.
  Plan subdivide_node(const json& v, const std::string& path, const Transform& world, int depth) {
    keys(v, path, {"scheme", "levels", "exact_rounding", "child"});
    Subdivision step{{}, world, path};
    if (v.contains("scheme")) {
      const json& s = v.at("scheme");
      const std::optional<Scheme> scheme =
          s.is_string() ? scheme_from_string(s.get_ref<const std::string&>()) : std::nullopt;
      if (!scheme)
        fail(path + "/scheme", "expected \"catmull-clark\", \"doo-sabin\", \"loop\" or \"sqrt3\"");
      step.options.scheme = *scheme;
    }
    if (v.contains("levels")) {
      const json& l = v.at("levels");
      if (!l.is_number_integer() || l.get<int64_t>() < 0 || l.get<int64_t>() > kMaxSubdivideLevels)
        fail(path + "/levels",
             "expected an integer from 0 to " + std::to_string(kMaxSubdivideLevels));
      step.options.levels = static_cast<int>(l.get<int64_t>());
    }
    if (v.contains("exact_rounding")) {
      if (!v.at("exact_rounding").is_boolean())
        fail(path + "/exact_rounding", "expected true or false");
      step.options.exact_rounding = v.at("exact_rounding").get<bool>();
    }
    return mesh_step(required(v, path, "child"), path + "/child", "subdivide", std::move(step),
                     depth);
  }

  /// The child of a subdivide or ffd node: a mesh-node (mesh, primitive, subdivide or ffd), whose
  /// leaf gets `step` after its own.
  Plan mesh_step(const json& c, const std::string& child, const std::string& node, Subdivision step,
                 int depth) {
    std::string kind;
    if (c.is_object())
      for (auto it = c.begin(); it != c.end(); ++it)
        if (it.key() != "transform") kind = it.key();
    if (kind != "mesh" && kind != "box" && kind != "sphere" && kind != "cylinder" &&
        kind != "subdivide" && kind != "ffd")
      fail(kind.empty() ? child : child + "/" + kind,
           "a" + std::string(node == "ffd" ? "n " : " ") + node +
               " node's child is a mesh, box, sphere, cylinder, subdivide or ffd node" +
               (kind.empty() ? std::string() : ", not '" + kind + "'") +
               " (operations, fields and warps are not refined here; evaluate them to a "
               "mesh first: cover evaluate)");
    const std::string path = step.path;
    const Plan p = plan(c, child, Transform{}, depth + 1);
    LeafTask& task = tasks_[p.task];
    task.subdivisions.push_back(std::move(step));
    task.path = path;
    return p;
  }

  /// An ffd node `v` at `path`: one leaf, its child's mesh deformed by the lattice
  /// (modeler/ffd.h), refined until the chord bound meets `tolerance`, then placed by `world`.
  Plan ffd_node(const json& v, const std::string& path, const Transform& world, int depth) {
    keys(v, path, {"lattice", "tolerance", "child"});
    const json& l = required(v, path, "lattice");
    const std::string lp = path + "/lattice";
    keys(l, lp, {"min", "max", "degree", "points"});
    FfdLattice f;
    f.min = vec3(required(l, lp, "min"), lp + "/min");
    f.max = vec3(required(l, lp, "max"), lp + "/max");
    if (l.contains("degree")) {
      const json& d = l.at("degree");
      if (!d.is_array() || d.size() != 3 || !std::all_of(d.begin(), d.end(), [](const json& x) {
            return x.is_number_integer() && x.get<int64_t>() >= 1 && x.get<int64_t>() <= 16;
          }))
        fail(lp + "/degree", "expected 3 integers from 1 to 16");
      for (int a = 0; a < 3; ++a) f.degree[a] = static_cast<int>(d[a].get<int64_t>());
    }
    const json& pts = required(l, lp, "points");
    if (!pts.is_array()) fail(lp + "/points", "expected an array of [x, y, z] points");
    for (size_t i = 0; i < pts.size(); ++i)
      f.points.push_back(vec3(pts[i], lp + "/points/" + std::to_string(i)));
    if (const std::string problem = validate(f); !problem.empty()) fail(lp, problem);
    Subdivision step{{}, world, path, std::move(f), 0};
    if (v.contains("tolerance")) {
      const double t = number(v.at("tolerance"), path + "/tolerance");
      if (!(t > 0)) fail(path + "/tolerance", "expected a number > 0");
      step.ffd_tolerance = t;
    }
    return mesh_step(required(v, path, "child"), path + "/child", "ffd", std::move(step), depth);
  }

  /// Makes the leaf of one task (in parallel with the others; `warnings` are the task's own).
  /// A mesh file's own errors ("m.off:5: ...", "m.off: cannot open: ...") follow the JSON path.
  Solid run(LeafTask& task, std::vector<std::string>& warnings) const {
    if (task.made) return std::move(*task.made);
    if (task.file.empty() && task.subdivisions.empty())
      return leaf(std::move(task.mesh), task.kind, task.path, false, warnings);
    PolygonMesh m;
    std::string name = task.kind;
    const FileRead* r = nullptr;
    if (task.file.empty()) {
      m = std::move(task.mesh);
    } else {
      r = &reads_[task.read];
      if (r->error) {
        try {
          std::rethrow_exception(r->error);
        } catch (const InputError& e) {
          fail(task.subdivisions.empty() ? task.path : task.subdivisions[0].path + "/child/mesh",
               e.what());
        }
      }
      warnings.insert(warnings.end(), r->warnings.begin(), r->warnings.end());
      m = r->mesh;
      apply_transform(task.world, m);
      name = task.file.string();
    }
    if (task.subdivisions.empty())
      return leaf(std::move(m), std::move(name), task.path, true, warnings, &r->topology);
    for (const Subdivision& s : task.subdivisions) {
      try {
        if (s.ffd) {
          FfdResult r = ffd(m, *s.ffd, {.tolerance = s.ffd_tolerance});
          m = std::move(r.mesh);
          name = "free-form deformation (" + std::to_string(r.levels) + " refinement" +
                 (r.levels == 1 ? "" : "s") + ", chord bound " + std::to_string(r.chord_bound) +
                 ") of " + name;
        } else {
          m = subdivide(m, s.options);
          name = std::string(to_string(s.options.scheme)) + " subdivision (" +
                 std::to_string(s.options.levels) + " level" + (s.options.levels == 1 ? "" : "s") +
                 ") of " + name;
        }
      } catch (const InputError& e) {
        fail(s.path, (task.file.empty() ? "" : task.file.string() + ": ") + e.what());
      }
      apply_transform(s.world, m);
    }
    return leaf(std::move(m), std::move(name), task.path, false, warnings);
  }

  Solid assemble(const Plan& p, std::vector<Solid>& solids) const {
    if (p.warp) return warp_leaf(p, assemble(p.children[0], solids));
    if (p.op == CsgOp::kLeaf) return std::move(solids[p.task]);
    if (p.op == CsgOp::kComplement) return complement(assemble(p.children[0], solids));
    std::vector<Solid> parts;
    for (const Plan& c : p.children) parts.push_back(assemble(c, solids));
    if (p.op == CsgOp::kUnion) return unite(std::move(parts));
    if (p.op == CsgOp::kIntersection) return intersect(std::move(parts));
    return subtract(std::move(parts));
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw InputError(scene_.string() + ": " + (path.empty() ? "/" : path) + ": " + what);
  }

  double number(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number");
    const double d = j.get<double>();
    if (!std::isfinite(d)) fail(path, "expected a finite number");
    return d;
  }

  Vec3 vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) fail(path, "expected 3 numbers");
    return {number(j[0], path + "/0"), number(j[1], path + "/1"), number(j[2], path + "/2")};
  }

  /// Checks that `j` is an object whose keys are all in `allowed`.
  /// A node's "color": [r, g, b] with each number from 0 to 1 (as glTF's and OpenSCAD's), or a
  /// "#rrggbb" string; to 8-bit RGB (rounded).
  std::array<uint8_t, 3> colour(const json& c, const std::string& path) const {
    std::array<uint8_t, 3> rgb{};
    if (c.is_string()) {
      const std::string& t = c.get_ref<const std::string&>();
      if (t.size() != 7 || t[0] != '#' ||
          t.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
        fail(path,
             "expected [r, g, b] from 0 to 1 or \"#rrggbb\", got \"" + t.substr(0, 20) + "\"");
      for (int k = 0; k < 3; ++k)
        rgb[k] = static_cast<uint8_t>(std::stoul(t.substr(1 + 2 * k, 2), nullptr, 16));
      return rgb;
    }
    if (!c.is_array() || c.size() != 3) fail(path, "expected [r, g, b] from 0 to 1 or \"#rrggbb\"");
    for (int k = 0; k < 3; ++k) {
      if (!c[k].is_number() || !(c[k].get<double>() >= 0 && c[k].get<double>() <= 1))
        fail(path + "/" + std::to_string(k), "expected a number from 0 to 1");
      rgb[k] = static_cast<uint8_t>(std::lround(c[k].get<double>() * 255));
    }
    return rgb;
  }

  void keys(const json& j, const std::string& path,
            std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) fail(path, "expected an object");
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || it.key() == a;
      if (!ok) fail(path + "/" + it.key(), "unknown key");
    }
  }

  const json& required(const json& j, const std::string& path, const char* key) const {
    if (!j.contains(key)) fail(path, std::string("missing key '") + key + "'");
    return j.at(key);
  }

  int segments(const json& j, const std::string& path, int max) const {
    if (!j.contains("segments")) return 32;
    const json& s = j.at("segments");
    if (!s.is_number_integer() || s.get<int64_t>() < 3 || s.get<int64_t>() > max)
      fail(path + "/segments", "expected an integer from 3 to " + std::to_string(max));
    return static_cast<int>(s.get<int64_t>());
  }

  double positive(const json& j, const std::string& path) const {
    const double d = number(j, path);
    if (!(d > 0)) fail(path, "expected a positive number");
    return d;
  }

  PolygonMesh primitive(const std::string& kind, const json& v, const std::string& path) const {
    if (kind == "box") {
      keys(v, path, {"min", "max"});
      const Vec3 lo = vec3(required(v, path, "min"), path + "/min");
      const Vec3 hi = vec3(required(v, path, "max"), path + "/max");
      if (!(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z))
        fail(path, "expected min < max on every axis");
      return make_box(lo, hi);
    }
    if (kind == "sphere") {
      keys(v, path, {"center", "radius", "segments"});
      const Vec3 c = vec3(required(v, path, "center"), path + "/center");
      const double r = positive(required(v, path, "radius"), path + "/radius");
      return make_sphere(c, r, segments(v, path, kMaxSphereSegments));
    }
    keys(v, path, {"base", "top", "radius", "segments"});
    const Vec3 b = vec3(required(v, path, "base"), path + "/base");
    const Vec3 t = vec3(required(v, path, "top"), path + "/top");
    const double r = positive(required(v, path, "radius"), path + "/radius");
    if (b == t) fail(path, "base and top coincide");
    return make_cylinder(b, t, r, segments(v, path, kMaxCylinderSegments));
  }

  /// The warp leaf of warp node `p` over its assembled child (in the node's frame), validated
  /// against the child's box, then placed by the node's transform (a similarity).
  Solid warp_leaf(const Plan& p, Solid child) const {
    WarpLeaf w = *p.warp;
    const Bbox box = child.bbox();
    if (box.empty()) fail(p.path + "/child", "the warped child is empty");
    if (std::string problem = field::validate(w, box); !problem.empty()) fail(p.path, problem);
    w.child = std::make_shared<const Solid>(std::move(child));
    const Bbox image = field::forward_box(w, box);
    Solid s = make_warp_leaf(std::move(w), image, std::string(to_string(p.warp->kind)), p.path);
    if (p.world == Transform{}) return s;
    try {
      return transform_solid(p.world, std::move(s));
    } catch (const InputError& e) {
      fail(p.path, e.what());
    }
  }

  /// A twist, taper or bend node's object (solid/warp_leaf.h): "axis": {"point", "direction"}
  /// (point default the origin), then per kind: twist "degrees_per_unit"; taper "range",
  /// "scale"; bend "toward", "range", "center" (default range[0]), "radius"; and "child".
  WarpLeaf warp_params(const std::string& kind, const json& v, const std::string& path) const {
    WarpLeaf w;
    if (kind == "twist") {
      w.kind = WarpKind::kTwist;
      keys(v, path, {"axis", "degrees_per_unit", "child"});
      w.degrees_per_unit =
          number(required(v, path, "degrees_per_unit"), path + "/degrees_per_unit");
    } else if (kind == "taper") {
      w.kind = WarpKind::kTaper;
      keys(v, path, {"axis", "range", "scale", "child"});
    } else {
      w.kind = WarpKind::kBend;
      keys(v, path, {"axis", "toward", "range", "center", "radius", "child"});
      w.toward = vec3(required(v, path, "toward"), path + "/toward");
      w.radius = number(required(v, path, "radius"), path + "/radius");
    }
    const json& axis = required(v, path, "axis");
    keys(axis, path + "/axis", {"point", "direction"});
    if (axis.contains("point")) w.point = vec3(axis.at("point"), path + "/axis/point");
    w.direction = vec3(required(axis, path + "/axis", "direction"), path + "/axis/direction");
    auto pair = [&](const char* key, double(&out)[2]) {
      const json& a = required(v, path, key);
      const std::string at = path + "/" + key;
      if (!a.is_array() || a.size() != 2) fail(at, "expected 2 numbers");
      out[0] = number(a[0], at + "/0");
      out[1] = number(a[1], at + "/1");
    };
    if (w.kind != WarpKind::kTwist) pair("range", w.range);
    if (w.kind == WarpKind::kTaper) pair("scale", w.scale);
    if (w.kind == WarpKind::kBend)
      w.center = v.contains("center") ? number(v.at("center"), path + "/center") : w.range[0];
    if (std::string problem = field::make_frame(w); !problem.empty()) fail(path, problem);
    return w;
  }

  /// One primitive as written, with its JSON path and the transform to the scene's frame.
  struct PlacedPrimitive {
    FieldPrimitive primitive;
    std::string path;
    Transform world;
  };

  /// The field leaf of the field or blend node `j` at `path` under `parent`: its primitives are
  /// validated as written (one threshold for all, compared exactly), then each is mapped by its
  /// own transform (a similarity; solid/transform.h), and the blend keeps its first primitive's
  /// threshold (solid/field_leaf.h).
  /// A point-set leaf (points/point_set.h): the cloud of `file` (io/point_set_io.h), its normals
  /// from the file or estimated, as an open-mesh leaf of dipole triangles placed by `world`.
  Solid point_set_leaf(const json& v, const std::string& path, const Transform& world) const {
    keys(v, path, {"file", "neighbours", "estimate_normals"});
    const json& f = required(v, path, "file");
    if (!f.is_string() || f.get_ref<const std::string&>().empty())
      fail(path + "/file", "expected a non-empty file path string");
    std::filesystem::path file = f.get<std::string>();
    if (file.is_relative()) file = scene_.parent_path() / file;
    PointSetOptions o;
    if (v.contains("neighbours")) {
      const json& k = v.at("neighbours");
      if (!k.is_number_integer() || k.get<int64_t>() < 3 || k.get<int64_t>() > 64)
        fail(path + "/neighbours", "expected an integer from 3 to 64");
      o.neighbours = static_cast<int>(k.get<int64_t>());
    }
    bool estimate = false;
    if (v.contains("estimate_normals")) {
      if (!v.at("estimate_normals").is_boolean())
        fail(path + "/estimate_normals", "expected true or false");
      estimate = v.at("estimate_normals").get<bool>();
    }
    PolygonMesh m;
    size_t count = 0;
    try {
      PointCloud cloud = read_point_cloud(file, options_.max_file_bytes);
      count = cloud.points.size();
      if (estimate) cloud.normals.clear();
      m = point_set_mesh(cloud.points, cloud.normals, o);
    } catch (const InputError& e) {
      fail(path, e.what());
    }
    apply_transform(world, m);
    for (const Vec3& p : m.vertices)
      if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
            std::abs(p.z) <= kMaxCoordinate))
        fail(path, "a point lies outside ±" + std::to_string(kMaxCoordinate));
    const size_t triangles = m.face_count();
    Solid s = make_leaf(
        std::move(m), "point set (" + std::to_string(count) + " points) of " + file.string(), path);
    s.leaves[0].boundary_edges = static_cast<int64_t>(3 * triangles);
    return s;
  }

  Solid field_leaf(const json& j, const std::string& path, const Transform& parent,
                   int depth) const {
    std::vector<PlacedPrimitive> placed;
    collect_field(j, path, parent, placed, depth);
    FieldLeaf as_written;
    for (const PlacedPrimitive& p : placed) as_written.primitives.push_back(p.primitive);
    if (std::string problem = field::validate(as_written); !problem.empty()) {
      // "primitive i: ..." → the i-th primitive's JSON path
      const size_t i = std::strtoull(problem.c_str() + problem.find(' ') + 1, nullptr, 10);
      fail(i < placed.size() ? placed[i].path : path, problem.substr(problem.find(": ") + 2));
    }
    FieldLeaf leaf;
    for (PlacedPrimitive& p : placed) {
      if (p.world == Transform{}) {
        leaf.primitives.push_back(std::move(p.primitive));
        continue;
      }
      FieldLeaf one{{std::move(p.primitive)}};
      try {
        Solid mapped = transform_solid(p.world, make_field_leaf(std::move(one), "field", p.path));
        leaf.primitives.push_back(std::move(mapped.fields[0].primitives[0]));
      } catch (const InputError& e) {
        fail(p.path, e.what());
      }
    }
    const std::string kind = j.contains("blend") ? "blend" : "field";
    return make_field_leaf(std::move(leaf), kind, path + "/" + kind);
  }

  /// Appends the primitives of the field or blend node `j` at `path` with their transforms (the
  /// node's own after `parent`); a blend's children are field or blend nodes (a nested blend is
  /// flattened: Σ is associative).
  void collect_field(const json& j, const std::string& path, const Transform& parent,
                     std::vector<PlacedPrimitive>& out, int depth) const {
    if (depth > kMaxDepth) fail(path, "scene nested deeper than " + std::to_string(kMaxDepth));
    if (!j.is_object()) fail(path, "expected a field or blend node");
    Transform world = parent;
    std::string kind;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "transform")
        world = parent * transform(it.value(), path + "/transform");
      else if (kind.empty())
        kind = it.key();
      else
        fail(path, "more than one of leaf/operation keys ('" + kind + "', '" + it.key() + "')");
    }
    const std::string sub = path + "/" + kind;
    if (kind == "field") {
      out.push_back({field_primitive(j.at(kind), sub), sub, world});
      return;
    }
    if (kind == "blend") {
      const json& v = j.at(kind);
      if (!v.is_array() || v.empty()) fail(sub, "expected an array of one or more field nodes");
      for (size_t i = 0; i < v.size(); ++i)
        collect_field(v[i], sub + "/" + std::to_string(i), world, out, depth + 1);
      return;
    }
    fail(path, kind.empty() ? "expected a field or blend node"
                            : "a blend's children are field or blend nodes, not '" + kind + "'");
  }

  /// A mesh skeleton `{"mesh": "part.off"}`: the file's faces triangulated (mesh/triangulate.h)
  /// into the primitive's triangle soup and indexed. The closedness and degenerate-triangle
  /// checks are field::validate's; an inside-out mesh (negative volume) is refused here.
  void mesh_skeleton(const json& a, const std::string& path, FieldPrimitive& p) const {
    if (!a.is_string() || a.get_ref<const std::string&>().empty())
      fail(path, "expected a non-empty mesh file path string");
    std::filesystem::path file = a.get<std::string>();
    if (file.is_relative()) file = scene_.parent_path() / file;
    PolygonMesh m;
    try {
      m = read_mesh(file, options_.max_file_bytes, nullptr);
    } catch (const InputError& e) {
      fail(path, e.what());
    }
    std::vector<std::array<uint32_t, 3>> triangles;
    for (size_t f = 0; f < m.face_count(); ++f)
      if (triangulate_face(m.vertices, m.face(f), triangles) == FaceTiling::kCrossing)
        fail(path, file.string() + ": face " + std::to_string(f) + " crosses itself");
    if (triangles.size() * 3 > kMaxPolylinePoints)
      fail(path, file.string() + ": more than " + std::to_string(kMaxPolylinePoints / 3) +
                     " triangles in a mesh skeleton");
    double volume = 0;
    for (const auto& t : triangles) {
      for (uint32_t v : t) p.points.push_back(m.vertices[v]);
      volume += dot(m.vertices[t[0]], cross(m.vertices[t[1]], m.vertices[t[2]]));
    }
    if (volume < 0)
      fail(path, file.string() + ": the mesh is inside out (negative volume); reverse its faces");
    p.mesh = index_skeleton_mesh(p.points);
  }

  /// A `field` node's object: skeleton, radius (r_T), influence (R), exponent (n, default 2),
  /// weight (±1, default 1). Ranges are field::validate's.
  FieldPrimitive field_primitive(const json& v, const std::string& path) const {
    keys(v, path, {"skeleton", "radius", "influence", "exponent", "weight"});
    FieldPrimitive p;
    const std::string sp = path + "/skeleton";
    const json& sk = required(v, path, "skeleton");
    if (!sk.is_object() || sk.size() != 1)
      fail(sp, "expected one of point, segment, triangle, polyline, circle, mesh");
    const std::string kind = sk.begin().key();
    const json& a = sk.begin().value();
    const std::string ap = sp + "/" + kind;
    auto points = [&](size_t lo, size_t hi) {
      if (!a.is_array() || a.size() < lo || a.size() > hi)
        fail(ap, lo == hi ? "expected " + std::to_string(lo) + " points"
                          : "expected " + std::to_string(lo) + " or more points");
      for (size_t i = 0; i < a.size(); ++i)
        p.points.push_back(vec3(a[i], ap + "/" + std::to_string(i)));
    };
    if (kind == "point") {
      p.kind = SkeletonKind::kPoint;
      p.points.push_back(vec3(a, ap));
    } else if (kind == "segment") {
      p.kind = SkeletonKind::kSegment;
      points(2, 2);
    } else if (kind == "triangle") {
      p.kind = SkeletonKind::kTriangle;
      points(3, 3);
    } else if (kind == "polyline") {
      p.kind = SkeletonKind::kPolyline;
      points(2, kMaxPolylinePoints);
    } else if (kind == "mesh") {
      p.kind = SkeletonKind::kMesh;
      mesh_skeleton(a, ap, p);
    } else if (kind == "circle") {
      p.kind = SkeletonKind::kCircle;
      keys(a, ap, {"center", "normal", "radius"});
      p.points.push_back(vec3(required(a, ap, "center"), ap + "/center"));
      p.points.push_back(vec3(required(a, ap, "normal"), ap + "/normal"));
      p.circle_radius = number(required(a, ap, "radius"), ap + "/radius");
    } else {
      fail(sp + "/" + kind,
           "unknown skeleton (expected point, segment, triangle, polyline, circle, mesh)");
    }
    p.radius = number(required(v, path, "radius"), path + "/radius");
    p.influence = number(required(v, path, "influence"), path + "/influence");
    auto integer = [&](const char* key, int fallback) {
      if (!v.contains(key)) return fallback;
      const json& n = v.at(key);
      if (!n.is_number_integer()) fail(path + "/" + key, "expected an integer");
      const int64_t k = n.get<int64_t>();
      if (k < -1000000 || k > 1000000) fail(path + "/" + key, "out of range");
      return static_cast<int>(k);
    };
    p.exponent = integer("exponent", 2);
    p.weight = integer("weight", 1);
    return p;
  }

  Transform transform(const json& t, const std::string& path) const {
    if (!t.is_object()) fail(path, "expected an object");
    Transform m;
    if (t.contains("matrix")) {
      keys(t, path, {"matrix"});
      const json& a = t.at("matrix");
      if (!a.is_array() || a.size() != 16)
        fail(path + "/matrix", "expected 16 numbers (row-major)");
      std::array<double, 16> rows{};
      for (int i = 0; i < 16; ++i) rows[i] = number(a[i], path + "/matrix/" + std::to_string(i));
      if (rows[12] != 0 || rows[13] != 0 || rows[14] != 0 || rows[15] != 1)
        fail(path + "/matrix", "last row must be 0 0 0 1");
      m = Transform::from_matrix(rows);
    } else {
      keys(t, path, {"scale", "rotate", "translate"});
      Vec3 scale{1, 1, 1}, axis{0, 0, 1}, translate{0, 0, 0};
      double degrees = 0;
      if (t.contains("scale")) {
        const json& s = t.at("scale");
        if (s.is_number()) {
          const double f = number(s, path + "/scale");
          scale = {f, f, f};
        } else if (s.is_array() && s.size() == 3) {
          scale = vec3(s, path + "/scale");
        } else {
          fail(path + "/scale", "expected a number or 3 numbers");
        }
      }
      if (t.contains("rotate")) {
        const std::string rp = path + "/rotate";
        const json& r = t.at("rotate");
        keys(r, rp, {"axis", "degrees"});
        const Vec3 a = vec3(required(r, rp, "axis"), rp + "/axis");
        if (a == Vec3{}) fail(rp + "/axis", "axis must be non-zero");
        axis = a;
        degrees = number(required(r, rp, "degrees"), rp + "/degrees");
      }
      if (t.contains("translate")) {
        translate = vec3(t.at("translate"), path + "/translate");
      }
      m = Transform::trs(scale, axis, degrees, translate);
    }
    const double det = m.determinant();
    if (!(std::abs(det) > 0) || !std::isfinite(det)) fail(path, "transform is singular");
    return m;
  }

  /// Messages name the scene file and the leaf's JSON path, and a mesh leaf's file before them.
  Solid leaf(PolygonMesh m, std::string name, const std::string& path, bool from_file,
             std::vector<std::string>& warnings, const MeshReport* topology = nullptr) const {
    const std::string at = scene_.string() + ": " + path;
    const std::string where = from_file ? name + " (" + at + ")" : at;
    return prepare_leaf(std::move(m), std::move(name), path, where, options_, warnings, topology);
  }

  /// What loading validates: boundary, orientation and volume only.
  static ValidateOptions leaf_validation() {
    ValidateOptions vo;
    vo.check_self_intersection = false;
    vo.full_report = false;
    return vo;
  }

 public:
  /// Makes one mesh a leaf (orient.h, docs/cli.md#semantics): coordinates within
  /// ±kMaxCoordinate; repeated loops read once; a closed leaf re-oriented consistently; an
  /// inside-out leaf reversed. `where` names the leaf in messages.
  /// `topology`: validate_mesh of the same index lists before any transform (FileRead), or
  /// nullptr.
  static Solid prepare_leaf(PolygonMesh m, std::string name, const std::string& origin,
                            const std::string& where, const LoadOptions& options,
                            std::vector<std::string>& warnings,
                            const MeshReport* topology = nullptr) {
    check_coordinate_range(m, where);
    if (options.repair) {
      size_t first = 0;
      if (const size_t n = collapse_repeated_loops(m, &first)) {
        warnings.push_back(where + ": " + std::to_string(n) + " face(s) (first: face " +
                           std::to_string(first) +
                           ", counting from 0) repeat one loop several times; read once");
        topology = nullptr;  // the loops changed
      }
    }
    const ValidateOptions vo = leaf_validation();
    MeshReport r;
    if (topology != nullptr) {
      r = *topology;
      r.volume = signed_volume(m);
      r.outward = r.closed && r.oriented && r.volume > 0;
    } else {
      r = validate_mesh(m, vo);
    }
    if (options.repair && r.boundary_edges > 0) {  // only open leaves are repaired (repair.h)
      const int64_t before = r.boundary_edges;
      const size_t welded = weld_duplicate_vertices(m);
      const size_t dropped = drop_zero_area_faces(m);
      if (welded > 0)
        warnings.push_back(where + ": " + std::to_string(welded) +
                           " duplicate vertices welded (exact coordinates)");
      if (dropped > 0)
        warnings.push_back(where + ": " + std::to_string(dropped) + " zero-area face(s) dropped");
      if (welded > 0 || dropped > 0) {
        r = validate_mesh(m, vo);
        if (r.boundary_edges == 0)
          warnings.push_back(where + ": closed after repair (" + std::to_string(before) +
                             " boundary edges before)");
      }
    }
    if (options.require_closed && r.boundary_edges > 0)
      throw InputError(where + ": open mesh: " + std::to_string(r.boundary_edges) +
                       " boundary edges (a leaf must be a closed solid)");
    if (r.boundary_edges > 0)
      warnings.push_back(where + ": open mesh: " + std::to_string(r.boundary_edges) +
                         " boundary edges; inside where the generalized winding number has "
                         "|w| > 1/2 (" +
                         parameter("require_closed") + " refuses)");
    // A closed leaf whose every edge has two sides of opposite directions (r.oriented, none
    // non-manifold) is balanced: orient_consistently() would change nothing, so its edge sorts
    // are skipped (the common case; ~15% of a scene's load).
    const bool balanced = r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.oriented;
    bool reoriented = false;
    if (options.repair && r.boundary_edges == 0 && !balanced) {
      const OrientResult o = orient_consistently(m, where);
      reoriented = o.flipped_faces > 0 || o.dropped_faces > 0;
      if (o.flipped_faces > 0)
        warnings.push_back(where + ": faces not consistently oriented; " +
                           std::to_string(o.flipped_faces) + " face(s) reversed in " +
                           std::to_string(o.components) + " component(s)");
      if (o.dropped_faces > 0)
        warnings.push_back(where + ": " + std::to_string(o.dropped_faces) +
                           " face(s) spanning edges of three or more faces dropped (an inner "
                           "membrane) to make the surface closed");
    }
    bool flipped = false;
    // validate_mesh's volume holds unless faces were flipped or dropped since.
    if (options.orient_outward && (reoriented ? signed_volume(m) : r.volume) < 0) {
      for (size_t f = 0; f < m.face_count(); ++f)
        std::reverse(m.face_vertices.begin() + m.face_start[f],
                     m.face_vertices.begin() + m.face_start[f + 1]);
      flipped = true;
      warnings.push_back(where + ": inside-out leaf (negative volume), faces reversed");
    }
    Solid s = make_leaf(std::move(m), std::move(name), origin);
    s.leaves[0].flipped = flipped;
    s.leaves[0].boundary_edges = r.boundary_edges;
    return s;
  }

 private:
  /// Refuses a vertex outside ±kMaxCoordinate (solid/types.h says why the range).
  static void check_coordinate_range(const PolygonMesh& m, const std::string& where) {
    for (size_t v = 0; v < m.vertices.size(); ++v) {
      const Vec3 p = m.vertices[v];
      for (int a = 0; a < 3; ++a)
        if (!(std::abs(p[a]) <= kMaxCoordinate)) {
          char value[32];
          std::snprintf(value, sizeof value, "%.17g", p[a]);
          throw InputError(where + ": vertex " + std::to_string(v) +
                           " (counting from 0): " + "xyz"[a] + " coordinate " + value +
                           " is outside the supported range [-2^64, 2^64] (about ±1.8e19)");
        }
    }
  }

 private:
  std::filesystem::path scene_;
  LoadOptions options_;
  std::vector<std::string>& warnings_;
  std::vector<LeafTask> tasks_;               ///< the leaves, in document order
  std::vector<FileRead> reads_;               ///< the distinct mesh files, in order of first use
  std::map<std::string, size_t> read_index_;  ///< a file's (normalized) path → its entry
};

/// json::parse callback that keeps the JSON pointer of the value being parsed (for errors in the
/// text itself) and refuses duplicate keys, which nlohmann would silently resolve to the last.
class JsonPath {
 public:
  explicit JsonPath(std::string scene) : scene_(std::move(scene)) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        frames_.push_back({event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::key: {
        Frame& top = frames_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second)
          throw InputError(scene_ + ": " + pointer(frames_.size() - 1) + ": duplicate key " +
                           detail::quote(top.key));
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        frames_.pop_back();
        completed();
        break;
      case json::parse_event_t::value:
        completed();
        break;
    }
    return true;
  }

  /// The pointer of the value being parsed ("/" at the root).
  std::string current() const { return pointer(frames_.size()); }

 private:
  struct Frame {
    bool array = false;
    size_t index = 0;            ///< arrays: elements completed so far
    std::string key;             ///< objects: the last key
    std::set<std::string> keys;  ///< objects: every key so far
  };

  /// The pointer through the first `n` open containers ("/" when n = 0).
  std::string pointer(size_t n) const {
    std::string out;
    for (size_t i = 0; i < n; ++i)
      out += "/" + (frames_[i].array ? std::to_string(frames_[i].index) : frames_[i].key);
    return out.empty() ? "/" : out;
  }

  void completed() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }

  std::string scene_;
  std::vector<Frame> frames_;
};

std::string line_of(const std::string& text, size_t byte) {
  size_t line = 1;
  for (size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
  return std::to_string(line);
}

}  // namespace

Solid prepare_leaf(PolygonMesh mesh, std::string name, const std::string& where,
                   const LoadOptions& options, std::vector<std::string>& warnings) {
  return SceneReader::prepare_leaf(std::move(mesh), std::move(name), "", where, options, warnings);
}

LoadedInput parse_scene(const std::string& text, const std::filesystem::path& scene_path,
                        const LoadOptions& options) {
  json j;
  JsonPath where(scene_path.string());
  try {
    j = json::parse(text, [&where](int depth, json::parse_event_t event, json& parsed) {
      return where(depth, event, parsed);
    });
  } catch (const json::exception& e) {
    std::string what = e.what();
    if (e.id == 406) {  // "number overflow parsing 'TOKEN'": beyond a double (the number rule)
      const size_t open = what.find('\''), close = what.rfind('\'');
      const std::string token = open < close ? what.substr(open + 1, close - open - 1) : "";
      throw InputError(scene_path.string() + ": " + where.current() + ": out-of-range number " +
                       detail::quote(token));
    }
    // nlohmann: "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
    const auto colon = what.find("] ");
    const auto* parse = dynamic_cast<const json::parse_error*>(&e);
    const size_t byte = parse && parse->byte > 0 ? parse->byte - 1 : 0;
    throw InputError(scene_path.string() + ":" + line_of(text, byte) + ": invalid JSON: " +
                     (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
  LoadedInput out;
  SceneReader reader(scene_path, options, out.warnings);
  out.solid = reader.read(j);
  return out;
}

LoadedInput load_input(const std::filesystem::path& path, const LoadOptions& options) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".json")
    return parse_scene(std::string(read_regular_file(path, options.max_file_bytes).view()), path,
                       options);
  LoadedInput out;
  PolygonMesh mesh = read_mesh(path, options.max_file_bytes, &out.warnings);
  out.solid = SceneReader::prepare_leaf(std::move(mesh), path.string(), "", path.string(), options,
                                        out.warnings);
  return out;
}

}  // namespace cover
