// Recorded modeling operations (modeler/script.h): parse, resolve ids and points, apply.
#include "cover/modeler/script.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"
#include "cover/subdivision/subdivide.h"

namespace cover::modeler {
namespace {

using Json = nlohmann::json;

double distance2(const Vec3& a, const Vec3& b) {
  const Vec3 d = a - b;
  return dot(d, d);
}

/// One operation's arguments, read with errors naming the key.
class Args {
 public:
  Args(const Json& object, std::string path, std::set<std::string> keys)
      : object_(object), path_(std::move(path)) {
    if (!object.is_object()) throw InputError(path_ + ": expected an object of arguments");
    for (const auto& [key, value] : object.items())
      if (!keys.count(key)) throw InputError(path_ + ": unknown key '" + key + "'");
  }

  double number(const std::string& key, std::optional<double> fallback = std::nullopt) const {
    if (!object_.contains(key)) {
      if (fallback) return *fallback;
      throw InputError(path_ + ": missing '" + key + "'");
    }
    const Json& v = object_.at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw InputError(path_ + "/" + key + ": expected a finite number");
    return v.get<double>();
  }

  int integer(const std::string& key, std::optional<int> fallback = std::nullopt) const {
    if (!object_.contains(key)) {
      if (fallback) return *fallback;
      throw InputError(path_ + ": missing '" + key + "'");
    }
    const Json& v = object_.at(key);
    if (!v.is_number_integer() || v.get<int64_t>() < std::numeric_limits<int>::min() ||
        v.get<int64_t>() > std::numeric_limits<int>::max())
      throw InputError(path_ + "/" + key + ": expected an integer");
    return static_cast<int>(v.get<int64_t>());
  }

  bool boolean(const std::string& key, bool fallback) const {
    if (!object_.contains(key)) return fallback;
    const Json& v = object_.at(key);
    if (!v.is_boolean()) throw InputError(path_ + "/" + key + ": expected true or false");
    return v.get<bool>();
  }

  bool has(const std::string& key) const { return object_.contains(key); }

  const Json& at(const std::string& key) const {
    if (!object_.contains(key)) throw InputError(path_ + ": missing '" + key + "'");
    return object_.at(key);
  }

  const std::string& path() const { return path_; }

 private:
  const Json& object_;
  std::string path_;
};

/// A point [x, y, z], or nullopt when `v` is an id.
std::optional<Vec3> point_of(const Json& v, const std::string& path) {
  if (v.is_number_integer()) return std::nullopt;
  if (!v.is_array() || v.size() != 3)
    throw InputError(path + ": expected an id or a point [x, y, z]");
  Vec3 p;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      throw InputError(path + ": expected an id or a point [x, y, z]");
    (i == 0 ? p.x : i == 1 ? p.y : p.z) = v[i].get<double>();
  }
  return p;
}

uint32_t id_of(const Json& v, const std::string& path) {
  const int64_t id = v.get<int64_t>();
  if (id < 0 || id >= kNone) throw InputError(path + ": id " + std::to_string(id) + " is not live");
  return static_cast<uint32_t>(id);
}

FaceId face_of(const DlflMesh& m, const Json& v, const std::string& path) {
  if (const std::optional<Vec3> p = point_of(v, path)) {
    FaceId best = kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (FaceId f = 0; f < m.face_capacity(); ++f) {
      if (!m.face_alive(f) || m.face_halfedge(f) == kNone) continue;
      const std::vector<VertexId> vs = m.face_vertices(f);
      Vec3 c{0, 0, 0};
      for (VertexId u : vs) c = c + m.position(u);
      const double d = distance2((1.0 / static_cast<double>(vs.size())) * c, *p);
      if (d < best_d) best = f, best_d = d;
    }
    if (best == kNone) throw InputError(path + ": the mesh has no face");
    return best;
  }
  const FaceId f = id_of(v, path);
  if (!m.face_alive(f)) throw InputError(path + ": face " + std::to_string(f) + " is not live");
  return f;
}

VertexId vertex_of(const DlflMesh& m, const Json& v, const std::string& path) {
  if (const std::optional<Vec3> p = point_of(v, path)) {
    VertexId best = kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (VertexId u = 0; u < m.vertex_capacity(); ++u) {
      if (!m.vertex_alive(u)) continue;
      const double d = distance2(m.position(u), *p);
      if (d < best_d) best = u, best_d = d;
    }
    if (best == kNone) throw InputError(path + ": the mesh has no vertex");
    return best;
  }
  const VertexId u = id_of(v, path);
  if (!m.vertex_alive(u)) throw InputError(path + ": vertex " + std::to_string(u) + " is not live");
  return u;
}

EdgeId edge_of(const DlflMesh& m, const Json& v, const std::string& path) {
  if (const std::optional<Vec3> p = point_of(v, path)) {
    EdgeId best = kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (EdgeId e = 0; e < m.edge_capacity(); ++e) {
      if (!m.edge_alive(e)) continue;
      const Vec3 mid = 0.5 * (m.position(m.head(2 * e)) + m.position(m.tail(2 * e)));
      const double d = distance2(mid, *p);
      if (d < best_d) best = e, best_d = d;
    }
    if (best == kNone) throw InputError(path + ": the mesh has no edge");
    return best;
  }
  const EdgeId e = id_of(v, path);
  if (!m.edge_alive(e)) throw InputError(path + ": edge " + std::to_string(e) + " is not live");
  return e;
}

/// A corner: {"face": F, "vertex": V} (face F's corner at V, its first in loop order when F
/// passes V more than once) or {"vertex": V} for a point-sphere's corner.
Corner corner_of(const DlflMesh& m, const Json& v, const std::string& path) {
  const Args a(v, path, {"face", "vertex"});
  const VertexId u = vertex_of(m, a.at("vertex"), path + "/vertex");
  if (!v.contains("face")) {
    if (!m.is_point_sphere(u))
      throw InputError(path + ": vertex " + std::to_string(u) +
                       " is not a point-sphere: name its corner's face");
    return Corner::point_sphere_of(u);
  }
  const FaceId f = face_of(m, a.at("face"), path + "/face");
  for (const Corner& c : m.face_corners(f))
    if (m.corner_vertex(c) == u) return c;
  throw InputError(path + ": face " + std::to_string(f) + " has no corner at vertex " +
                   std::to_string(u));
}

void apply_one(DlflMesh& mesh, const std::string& name, const Json& body, const std::string& path) {
  if (name == "pipe") {
    const Args a(body, path, {"faces", "segments", "twist", "curved", "weights", "path"});
    const Json& faces = a.at("faces");
    if (!faces.is_array() || faces.size() != 2)
      throw InputError(path + "/faces: expected two faces (ids or points)");
    const FaceId f1 = face_of(mesh, faces[0], path + "/faces/0");
    const FaceId f2 = face_of(mesh, faces[1], path + "/faces/1");
    // twist in degrees, turned into whole corners of f1 (360/n degrees each).
    const double n = static_cast<double>(mesh.face_degree(f1));
    const double corners = std::round(a.number("twist", 0) * n / 360);
    if (std::abs(corners) > 1e6) throw InputError(path + "/twist: out of range");
    PipeOptions o{a.integer("segments", 1), static_cast<int>(corners)};
    o.curved = a.boolean("curved", false);
    if (a.has("weights")) {
      const Json& w = a.at("weights");
      if (!w.is_array() || w.size() != 2 || !w[0].is_number() || !w[1].is_number())
        throw InputError(path + "/weights: expected two numbers [w1, w2]");
      o.weight1 = w[0].get<double>();
      o.weight2 = w[1].get<double>();
    }
    if (a.has("path")) {
      const Json& points = a.at("path");
      if (!points.is_array()) throw InputError(path + "/path: expected a list of points [x, y, z]");
      for (size_t i = 0; i < points.size(); ++i) {
        const std::string where = path + "/path/" + std::to_string(i);
        const std::optional<Vec3> p =
            points[i].is_array() ? point_of(points[i], where) : std::nullopt;
        if (!p) throw InputError(where + ": expected a point [x, y, z]");
        o.path.push_back(*p);
      }
    }
    create_pipe(mesh, f1, f2, o);
  } else if (name == "extrude") {
    const Args a(body, path, {"face", "distance", "kind", "scale", "twist"});
    const FaceId f = face_of(mesh, a.at("face"), path + "/face");
    const double d = a.number("distance");
    const Json& kind = body.contains("kind") ? body.at("kind") : Json("straight");
    const std::string k = kind.is_string() ? kind.get<std::string>() : "";
    if (k == "straight") {
      extrude_face(mesh, f, d);
    } else if (k == "stellate") {
      stellate_face(mesh, f, d);
    } else if (k == "cubical") {
      extrude_face_doo_sabin(mesh, f, d, {a.number("twist", 0), a.number("scale", 1)});
    } else if (k == "dome") {
      extrude_face_dome(mesh, f, d, a.number("scale", 1));
    } else if (k == "dodecahedral") {
      extrude_face_dodecahedral(mesh, f, d, a.number("scale", 1));
    } else {
      throw InputError(path + "/kind: expected straight, cubical, dodecahedral, stellate or dome");
    }
  } else if (name == "create_vertex") {
    const Args a(body, path, {"point"});
    const std::optional<Vec3> p = point_of(a.at("point"), path + "/point");
    if (!p) throw InputError(path + "/point: expected a point [x, y, z]");
    mesh.create_vertex(*p);
  } else if (name == "delete_vertex") {
    const Args a(body, path, {"vertex"});
    const VertexId v = vertex_of(mesh, a.at("vertex"), path + "/vertex");
    if (!mesh.is_point_sphere(v))
      throw InputError(path + ": vertex " + std::to_string(v) + " has edges (not a point-sphere)");
    mesh.delete_vertex(v);
  } else if (name == "insert_edge") {
    const Args a(body, path, {"corners"});
    const Json& corners = a.at("corners");
    if (!corners.is_array() || corners.size() != 2)
      throw InputError(path + "/corners: expected two corners");
    mesh.insert_edge(corner_of(mesh, corners[0], path + "/corners/0"),
                     corner_of(mesh, corners[1], path + "/corners/1"));
  } else if (name == "delete_edge") {
    const Args a(body, path, {"edge"});
    mesh.delete_edge(edge_of(mesh, a.at("edge"), path + "/edge"));
  } else if (name == "inset") {
    const Args a(body, path, {"face", "fraction"});
    inset_face(mesh, face_of(mesh, a.at("face"), path + "/face"), a.number("fraction", 0.2));
  } else if (name == "chamfer") {
    const Args a(body, path, {"edge", "fraction"});
    chamfer_edge(mesh, edge_of(mesh, a.at("edge"), path + "/edge"), a.number("fraction", 0.25));
  } else if (name == "bevel") {
    const Args a(body, path, {"fraction"});
    bevel(mesh, a.number("fraction", 0.25));
  } else if (name == "crust" || name == "wireframe") {
    const Args a(body, path, {"faces", "thickness", "inset"});
    const CrustOptions o{a.number("thickness", 0.1), a.number("inset", 0.2)};
    if (name == "wireframe") {
      if (body.contains("faces")) throw InputError(path + ": unknown key 'faces'");
      wireframe(mesh, o);
    } else {
      const Json& faces = a.at("faces");
      if (!faces.is_array()) throw InputError(path + "/faces: expected a list of faces");
      std::vector<FaceId> punched;
      for (size_t i = 0; i < faces.size(); ++i)
        punched.push_back(face_of(mesh, faces[i], path + "/faces/" + std::to_string(i)));
      crust(mesh, punched, o);
    }
  } else if (name == "stellate") {
    const Args a(body, path, {"face", "height"});
    stellate_face(mesh, face_of(mesh, a.at("face"), path + "/face"), a.number("height"));
  } else if (name == "truncate") {
    const Args a(body, path, {"vertex", "fraction"});
    truncate_vertex(mesh, vertex_of(mesh, a.at("vertex"), path + "/vertex"),
                    a.number("fraction", 0.25));
  } else if (name == "subdivide_edge") {
    const Args a(body, path, {"edge", "points"});
    subdivide_edge(mesh, 2 * edge_of(mesh, a.at("edge"), path + "/edge"), a.integer("points", 1));
  } else if (name == "remove_edge") {
    const Args a(body, path, {"edge"});
    remove_edge(mesh, edge_of(mesh, a.at("edge"), path + "/edge"));
  } else if (name == "subdivide") {
    const Args a(body, path, {"scheme", "levels", "exact_rounding"});
    SubdivideOptions o;
    const Json& scheme = body.contains("scheme") ? body.at("scheme") : Json("catmull-clark");
    const std::optional<Scheme> s =
        scheme.is_string() ? scheme_from_string(scheme.get<std::string>()) : std::nullopt;
    if (!s) throw InputError(path + "/scheme: expected catmull-clark, doo-sabin, loop or sqrt3");
    o.scheme = *s;
    o.levels = a.integer("levels", 1);
    if (body.contains("exact_rounding")) {
      if (!body.at("exact_rounding").is_boolean())
        throw InputError(path + "/exact_rounding: expected true or false");
      o.exact_rounding = body.at("exact_rounding").get<bool>();
    }
    mesh = from_polygon_mesh(subdivide(to_polygon_mesh(mesh), o));
  } else {
    throw InputError(path +
                     ": unknown operation (pipe, extrude, stellate, truncate, "
                     "subdivide_edge, remove_edge, subdivide)");
  }
}

}  // namespace

ScriptReport apply_script(DlflMesh& mesh, std::string_view script, const std::string& origin) {
  Json doc;
  try {
    doc = Json::parse(script);
  } catch (const Json::parse_error& e) {
    throw InputError(origin + ": invalid JSON at byte " + std::to_string(e.byte));
  }
  std::string base;
  if (doc.is_object()) {
    if (doc.size() != 1 || !doc.contains("operations"))
      throw InputError(origin + ": expected {\"operations\": [...]} or a list of operations");
    doc = Json(doc.at("operations"));
    base = "/operations";
  }
  if (!doc.is_array())
    throw InputError(origin + ": " + (base.empty() ? "" : base + ": ") +
                     "expected a list of operations");
  ScriptReport report;
  for (size_t k = 0; k < doc.size(); ++k) {
    const std::string at = base + "/" + std::to_string(k);
    const Json& op = doc[k];
    if (!op.is_object() || op.size() != 1)
      throw InputError(origin + ": " + at + ": expected an object with one operation");
    const std::string name = op.begin().key();
    const std::string path = at + "/" + name;
    try {
      apply_one(mesh, name, op.begin().value(), path);
    } catch (const InputError& e) {
      const std::string what = e.what();
      throw InputError(origin + ": " + (what.rfind(path, 0) == 0 ? what : path + ": " + what));
    } catch (const PreconditionError& e) {
      throw InputError(origin + ": " + path + ": " + e.what());
    }
    ++report.operations;
  }
  return report;
}

}  // namespace cover::modeler
