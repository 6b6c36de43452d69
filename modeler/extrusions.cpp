// TopMod's extrusion variants (dlflaux/DLFLExtrude: extrudeFaceDS, extrudeFaceDome,
// extrudeFaceDodeca), built from extrude_face, stellate_face and the minimal operators
// (notation in dlfl.h). Positions are set after the topology is in place.

#include <cmath>
#include <numbers>
#include <string>

#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"

namespace cover::modeler {

namespace {

Vec3 centroid_of(const std::vector<Vec3>& points) {
  Vec3 sum{0, 0, 0};
  for (const Vec3& p : points) sum = sum + p;
  return (1.0 / double(points.size())) * sum;
}

/// The points scaled by s about their centroid.
void scale_about_centroid(std::vector<Vec3>& points, double s) {
  const Vec3 c = centroid_of(points);
  for (Vec3& p : points) p = c + s * (p - c);
}

/// The unit Newell normal of f, or InputError naming `op`.
Vec3 unit_normal_of(const DlflMesh& mesh, FaceId f, const char* op) {
  const std::vector<VertexId> loop = mesh.face_vertices(f);
  Vec3 normal{0, 0, 0};
  for (size_t i = 0; i < loop.size(); ++i)
    normal = normal + cross(mesh.position(loop[i]), mesh.position(loop[(i + 1) % loop.size()]));
  const double length = std::sqrt(dot(normal, normal));
  if (!(length > 0))
    throw InputError(std::string(op) + ": face " + std::to_string(f) +
                     " has no normal (degenerate)");
  return (1 / length) * normal;
}

void require_scale(double scale) {
  if (!(scale > 0))
    throw InputError(parameter("scale") + ": " + std::to_string(scale) + " is not positive");
}

/// extrude_face(f, 0), then the new corners (f's loop, in order) moved to at(base corners).
template <class Place>
FaceId extrude_and_place(DlflMesh& mesh, FaceId f, const char* op, const Place& at) {
  if (mesh.face_alive(f) && mesh.face_halfedge(f) != kNone) unit_normal_of(mesh, f, op);
  extrude_face(mesh, f, 0.0);
  const std::vector<VertexId> top = mesh.face_vertices(f);
  std::vector<Vec3> base;
  for (VertexId w : top) {
    // The post: w's one edge that leaves the top face.
    for (HalfedgeId h : mesh.rotation(w)) {
      if (mesh.face(h) != f && mesh.face(DlflMesh::twin(h)) != f) {
        base.push_back(mesh.position(mesh.head(h)));
        break;
      }
    }
  }
  COVER_ASSERT(base.size() == top.size());
  const std::vector<Vec3> placed = at(base);
  for (size_t i = 0; i < top.size(); ++i) mesh.set_position(top[i], placed[i]);
  return f;
}

}  // namespace

FaceId extrude_face_doo_sabin(DlflMesh& mesh, FaceId f, double distance,
                              const DooSabinExtrudeOptions& options) {
  require_scale(options.scale);
  if (!(options.twist >= 0 && options.twist <= 1))
    throw InputError(parameter("twist") + ": " + std::to_string(options.twist) +
                     " is not in [0, 1]");
  const Vec3 offset = mesh.face_alive(f) && mesh.face_halfedge(f) != kNone
                          ? distance * unit_normal_of(mesh, f, "extrude_face_doo_sabin")
                          : Vec3{0, 0, 0};
  return extrude_and_place(mesh, f, "extrude_face_doo_sabin", [&](const std::vector<Vec3>& b) {
    const size_t n = b.size();
    std::vector<Vec3> moved(n), out(n, Vec3{0, 0, 0});
    for (size_t i = 0; i < n; ++i)
      moved[i] = offset + (1 - options.twist) * b[i] + options.twist * b[(i + 1) % n];
    // The Doo–Sabin corner mask: a_0 = 1/4 + 5/(4n), a_k = (3 + 2 cos(2πk/n)) / (4n).
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = 0; j < n; ++j) {
        const double k = double((j + n - i) % n);
        const double a = k == 0 ? 0.25 + 5.0 / (4.0 * double(n))
                                : (3.0 + 2.0 * std::cos(2.0 * std::numbers::pi * k / double(n))) /
                                      (4.0 * double(n));
        out[i] = out[i] + a * moved[j];
      }
    }
    scale_about_centroid(out, options.scale);
    return out;
  });
}

VertexId extrude_face_dome(DlflMesh& mesh, FaceId f, double length, double scale) {
  require_scale(scale);
  // TopMod's profile: five Doo–Sabin rings of shrinking height, then a low cone.
  constexpr double kHeights[] = {0.3, 0.18, 0.1, 0.05, 0.025};
  constexpr double kScales[] = {1.7, 1.6, 1.4, 1.2, 1.1};
  for (int i = 0; i < 5; ++i)
    f = extrude_face_doo_sabin(mesh, f, kHeights[i] * length, {0.0, kScales[i] * scale});
  return stellate_face(mesh, f, 0.01 * length);
}

FaceId extrude_face_dodecahedral(DlflMesh& mesh, FaceId f, double distance, double scale) {
  require_scale(scale);
  const char* op = "extrude_face_dodecahedral";
  if (!mesh.face_alive(f))
    throw PreconditionError(std::string(op) + ": face " + std::to_string(f) + " is not live");
  if (mesh.face_degree(f) < 3)
    throw InputError(std::string(op) + ": face " + std::to_string(f) + " has under 3 sides");
  const double step = distance / 3, s = std::cbrt(scale);
  const auto lift = [&](FaceId g) {
    const Vec3 offset = step * unit_normal_of(mesh, g, op);
    return extrude_and_place(mesh, g, op, [&](const std::vector<Vec3>& base) {
      std::vector<Vec3> out;
      for (const Vec3& p : base) out.push_back(p + offset);
      scale_about_centroid(out, s);
      return out;
    });
  };
  // 1. A straight extrusion: the top corners c_i, loop half-edges h_i: c_i → c_{i+1}.
  lift(f);
  const std::vector<HalfedgeId> rim = mesh.face_loop(f);
  const size_t n = rim.size();
  const Vec3 offset = step * unit_normal_of(mesh, f, op);
  std::vector<Vec3> mid(n);
  for (size_t i = 0; i < n; ++i)
    mid[i] = 0.5 * (mesh.position(mesh.tail(rim[i])) + mesh.position(mesh.head(rim[i]))) + offset;
  scale_about_centroid(mid, s);
  // 2. The dual ring: m_i over the middle of h_i, d_i: c_i → m_i dangling in f, g_i: m_i →
  //    c_{i+1} cutting off the triangle (c_i, c_{i+1}, m_i), then a_i: m_i → m_{i+1} cutting off
  //    (m_i, c_{i+1}, m_{i+1}); the a_i bound the new top face.
  std::vector<HalfedgeId> spoke(n), ring(n);
  for (size_t i = 0; i < n; ++i) {
    const VertexId m = mesh.create_vertex(mid[i]);
    spoke[i] = mesh.insert_edge(Corner::at(rim[(i + n - 1) % n]), Corner::point_sphere_of(m));
  }
  for (size_t i = 0; i < n; ++i) mesh.insert_edge(Corner::at(spoke[i]), Corner::at(rim[i]));
  Corner corner = Corner::at(spoke[0]);
  for (size_t i = 0; i < n; ++i) {
    ring[i] = mesh.insert_edge(corner, Corner::at(spoke[(i + 1) % n]));
    corner = Corner::at(ring[i]);
  }
  const FaceId top = mesh.face(ring[n - 1]);
  // Deleting h_i merges triangle i with side quad i: the lower pentagons.
  for (HalfedgeId h : rim) mesh.delete_edge(DlflMesh::edge(h));
  // 3. A straight extrusion of the dual face; deleting a_i gives the upper pentagons.
  lift(top);
  for (HalfedgeId h : ring) mesh.delete_edge(DlflMesh::edge(h));
  return top;
}

}  // namespace cover::modeler
