// User-level operators built from the minimal DLFL operators (notation in dlfl.h).
//
// Corner names stay valid across insertions elsewhere: Corner::at(h) is the corner after h, and
// an insertion at another corner never changes next(h). An insertion at Corner::at(h) itself
// leaves Corner::at(h) between h and the new half-edge.

#include "cover/modeler/operators.h"

#include <cmath>
#include <limits>
#include <string>

#include "cover/modeler/detail/pipe_path.h"
#include "cover/solid/errors.h"

namespace cover::modeler {

namespace {

void require_face(const DlflMesh& mesh, FaceId f, const char* op) {
  if (!mesh.face_alive(f))
    throw PreconditionError(std::string(op) + ": face " + std::to_string(f) + " is not live");
  if (mesh.face_halfedge(f) == kNone)
    throw InputError(std::string(op) + ": face " + std::to_string(f) +
                     " is a point-sphere's face (no corners to build on)");
}

Vec3 lerp(const Vec3& p, const Vec3& q, double t) { return p + t * (q - p); }

/// The unit Newell normal of f, or InputError naming `op` when it is zero.
Vec3 unit_normal(const DlflMesh& mesh, FaceId f, const char* op) {
  const std::vector<HalfedgeId> loop = mesh.face_loop(f);
  Vec3 normal{0, 0, 0};
  for (size_t i = 0; i < loop.size(); ++i)
    normal = normal + cross(mesh.position(mesh.head(loop[i])),
                            mesh.position(mesh.head(loop[(i + 1) % loop.size()])));
  const double length = std::sqrt(dot(normal, normal));
  if (!(length > 0))
    throw InputError(std::string(op) + ": face " + std::to_string(f) +
                     " has no normal (degenerate)");
  return (1 / length) * normal;
}

/// The mean of the loop's vertex positions.
Vec3 centroid(const DlflMesh& mesh, const std::vector<HalfedgeId>& loop) {
  Vec3 c{0, 0, 0};
  for (HalfedgeId h : loop) c = c + mesh.position(mesh.head(h));
  return (1.0 / static_cast<double>(loop.size())) * c;
}

/// The corner of v that lies in face f (the first in rotation order).
Corner corner_in_face(const DlflMesh& mesh, VertexId v, FaceId f) {
  for (Corner c : mesh.vertex_corners(v))
    if (mesh.corner_face(c) == f) return c;
  throw InternalError("modeler: vertex " + std::to_string(v) + " has no corner in face " +
                      std::to_string(f));
}

}  // namespace

void remove_edge(DlflMesh& mesh, EdgeId e) {
  if (!mesh.edge_alive(e))
    throw PreconditionError("remove_edge: edge " + std::to_string(e) + " is not live");
  const VertexId v1 = mesh.tail(2 * e), v2 = mesh.head(2 * e);
  mesh.delete_edge(e);
  if (mesh.is_point_sphere(v1)) mesh.delete_vertex(v1);
  if (v2 != v1 && mesh.is_point_sphere(v2)) mesh.delete_vertex(v2);
}

std::vector<VertexId> subdivide_edge(DlflMesh& mesh, HalfedgeId h, int k) {
  if (!mesh.halfedge_alive(h))
    throw PreconditionError("subdivide_edge: half-edge " + std::to_string(h) + " is not live");
  if (k < 0) throw InputError(parameter("k") + ": negative vertex count " + std::to_string(k));
  std::vector<VertexId> added(static_cast<size_t>(k));
  if (k == 0) return added;
  // The chain runs from head(h) to tail(h) through face(b): it leaves at the corner before b
  // and ends at the corner after b, so its loop takes b's place in face(b) and its twins form,
  // with b, a new face that the final delete_edge merges into face(h).
  const HalfedgeId b = DlflMesh::twin(h);
  const Vec3 from = mesh.position(mesh.head(h)), to = mesh.position(mesh.tail(h));
  Corner corner = Corner::at(mesh.prev(b));
  for (int i = 1; i <= k; ++i) {
    const VertexId w = mesh.create_vertex(lerp(from, to, double(i) / double(k + 1)));
    added[static_cast<size_t>(k - i)] = w;
    corner = Corner::at(mesh.insert_edge(corner, Corner::point_sphere_of(w)));
  }
  mesh.insert_edge(corner, Corner::at(b));
  mesh.delete_edge(DlflMesh::edge(h));
  return added;
}

void create_pipe(DlflMesh& mesh, FaceId f1, FaceId f2, const PipeOptions& options) {
  require_face(mesh, f1, "create_pipe");
  require_face(mesh, f2, "create_pipe");
  if (f1 == f2) throw InputError("create_pipe: f1 and f2 are the same face");
  const std::vector<HalfedgeId> loop1 = mesh.face_loop(f1), loop2 = mesh.face_loop(f2);
  const size_t n = loop1.size();
  if (loop2.size() != n)
    throw InputError("create_pipe: faces of " + std::to_string(n) + " and " +
                     std::to_string(loop2.size()) + " sides");
  if (options.segments < 1)
    throw InputError(parameter("segments") + ": " + std::to_string(options.segments) +
                     " is not positive");
  if (options.segments > 1 && n < 3)
    throw InputError(parameter("segments") + ": inner rings need faces of at least 3 sides");
  const bool curved = options.curved || !options.path.empty();
  detail::PipePath path;
  std::vector<detail::Frame> frames;
  std::vector<Vec3> p1(n), p2(n);
  for (size_t i = 0; i < n; ++i) p1[i] = mesh.position(mesh.head(loop1[i]));
  if (curved) {
    for (double w : {options.weight1, options.weight2})
      if (!(w > 0) || !std::isfinite(w))
        throw InputError(parameter("weights") + ": " + std::to_string(w) +
                         " is not a positive number");
    path = {centroid(mesh, loop1),
            centroid(mesh, loop2),
            unit_normal(mesh, f1, "create_pipe"),
            unit_normal(mesh, f2, "create_pipe"),
            options.path,
            options.weight1,
            options.weight2};
    frames = detail::pipe_frames(path, options.segments);
  }
  // The closest correspondence i ↔ s − i, then the twist.
  auto partner = [n](size_t s, size_t i) { return (s + n - i) % n; };
  size_t best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (size_t s = 0; s < n; ++s) {
    for (size_t i = 0; i < n; ++i) p2[i] = mesh.position(mesh.head(loop2[partner(s, i)]));
    double cost = 0;
    if (curved) {
      cost = detail::pipe_correspondence_cost(path, p1, p2, frames.back());
    } else {
      for (size_t i = 0; i < n; ++i) cost += dot(p1[i] - p2[i], p1[i] - p2[i]);
    }
    if (cost < best_cost) {
      best_cost = cost;
      best = s;
    }
  }
  const auto count = static_cast<long long>(n);
  const size_t s =
      static_cast<size_t>(((static_cast<long long>(best) + options.twist) % count + count) % count);
  for (size_t i = 0; i < n; ++i) p2[i] = mesh.position(mesh.head(loop2[partner(s, i)]));
  const std::vector<Vec3> rings =
      curved ? detail::pipe_rings(path, p1, p2, options.segments) : std::vector<Vec3>{};
  std::vector<HalfedgeId> rails(n);
  for (size_t i = 0; i < n; ++i)
    rails[i] = mesh.insert_edge(Corner::at(loop1[i]), Corner::at(loop2[partner(s, i)]));
  if (options.segments == 1) return;
  // Quad i lies between rails i and i+1 and holds loop2[partner(s, i)] at its far end; ring
  // edges cut it from the near end up, so that half-edge stays in the part still to cut.
  std::vector<std::vector<VertexId>> chains(n);
  for (size_t i = 0; i < n; ++i) chains[i] = subdivide_edge(mesh, rails[i], options.segments - 1);
  // chains[i][j] is ring j + 1 (counted from f1) on rail i.
  if (curved)
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < chains[i].size(); ++j)
        mesh.set_position(chains[i][j], rings[j * n + i]);
  for (size_t j = 0; j + 1 < static_cast<size_t>(options.segments); ++j) {
    for (size_t i = 0; i < n; ++i) {
      const FaceId quad = mesh.face(loop2[partner(s, i)]);
      mesh.insert_edge(corner_in_face(mesh, chains[i][j], quad),
                       corner_in_face(mesh, chains[(i + 1) % n][j], quad));
    }
  }
}

FaceId extrude_face(DlflMesh& mesh, FaceId f, double distance) {
  require_face(mesh, f, "extrude_face");
  const std::vector<HalfedgeId> loop = mesh.face_loop(f);
  const size_t n = loop.size();
  const Vec3 offset = distance * unit_normal(mesh, f, "extrude_face");
  std::vector<HalfedgeId> posts(n);
  for (size_t i = 0; i < n; ++i) {
    const VertexId w = mesh.create_vertex(mesh.position(mesh.head(loop[i])) + offset);
    posts[i] = mesh.insert_edge(Corner::at(loop[i]), Corner::point_sphere_of(w));
  }
  // Each cross edge splits off one side quad; the remaining loop (which keeps f's id) reaches
  // the top vertex i through the corner after the previous cross edge.
  Corner corner = Corner::at(posts[0]);
  for (size_t i = 0; i < n; ++i) {
    const Corner target = Corner::at(posts[(i + 1) % n]);
    corner = Corner::at(mesh.insert_edge(corner, target));
  }
  return f;
}

VertexId stellate_face(DlflMesh& mesh, FaceId f, double height) {
  require_face(mesh, f, "stellate_face");
  const std::vector<HalfedgeId> loop = mesh.face_loop(f);
  const Vec3 normal = unit_normal(mesh, f, "stellate_face");
  const VertexId apex = mesh.create_vertex(centroid(mesh, loop) + height * normal);
  // The apex's corner in the part of f still to cut stays the one after the first spoke.
  const Corner at_apex =
      Corner::at(mesh.insert_edge(Corner::at(loop[0]), Corner::point_sphere_of(apex)));
  for (size_t i = 1; i < loop.size(); ++i) mesh.insert_edge(Corner::at(loop[i]), at_apex);
  return apex;
}

FaceId truncate_vertex(DlflMesh& mesh, VertexId v, double t) {
  if (!mesh.vertex_alive(v))
    throw PreconditionError("truncate_vertex: vertex " + std::to_string(v) + " is not live");
  if (mesh.is_point_sphere(v))
    throw InputError("truncate_vertex: vertex " + std::to_string(v) + " has no edges");
  if (!(t > 0 && t < 1))
    throw InputError(parameter("t") + ": " + std::to_string(t) + " is not in (0, 1)");
  const std::vector<HalfedgeId> spokes = mesh.rotation(v);
  for (HalfedgeId h : spokes)
    if (mesh.head(h) == v)
      throw InputError("truncate_vertex: vertex " + std::to_string(v) + " has a loop edge");
  const Vec3 p = mesh.position(v);
  for (HalfedgeId h : spokes) {
    const Vec3 q = mesh.position(mesh.head(h));
    const VertexId w = subdivide_edge(mesh, h, 1)[0];
    mesh.set_position(w, lerp(p, q, t));
  }
  // Each corner of v, entered by g from w_i and left by next(g) to w_j, is cut off by an edge
  // w_i → w_j; the cut-off triangles hold v and its short edges only.
  // The twin of each cut edge lies in its triangle, so in the cut face at the end.
  const std::vector<HalfedgeId> short_spokes = mesh.rotation(v);
  HalfedgeId inside = kNone;
  for (HalfedgeId s : short_spokes) {
    const HalfedgeId g = DlflMesh::twin(s);
    inside = DlflMesh::twin(mesh.insert_edge(Corner::at(mesh.prev(g)), Corner::at(mesh.next(g))));
  }
  // Removing the short edges merges the triangles into the cut face; the last leaves v alone.
  for (HalfedgeId s : short_spokes) remove_edge(mesh, DlflMesh::edge(s));
  COVER_ASSERT(!mesh.vertex_alive(v));
  return mesh.face(inside);
}

}  // namespace cover::modeler
