// Nested CSG scenes of real meshes (libcgal-demo) against CGAL corefinement (independent mesh
// booleans): `volume` (ray method) within 1e-4 relative of the corefined result's volume, and
// classification equal to per-leaf CGAL Side_of_triangle_mesh combined through the expression.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <random>

#include "cover/covering/classify.h"
#include "cover/covering/volume.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// A libcgal-demo mesh scaled into the cube [−1, 1]³ around `centre`, plus the same triangles as
/// a CGAL mesh (identical doubles: the transform is applied once, by Cover).
struct Operand {
  Solid solid;
  Mesh mesh;
};

Operand operand(const std::string& name, Vec3 centre, double size, double degrees) {
  PolygonMesh m = read_mesh(test::cgal_mesh(name));
  apply_transform(Transform::fit(face_bbox(m), centre, size, {0.3, 1, 0.2}, degrees), m);
  Operand o{make_leaf(m, name), {}};
  std::vector<Mesh::Vertex_index> vs;
  for (const Vec3& p : m.vertices) vs.push_back(o.mesh.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (size_t f = 0; f < m.face_count(); ++f) {
    auto face = m.face(f);
    o.mesh.add_face(vs[face[0]], vs[face[1]], vs[face[2]]);
  }
  return o;
}

enum class Op { kUnion, kIntersection, kDifference };

Mesh corefine(Mesh a, Mesh b, Op op) {
  Mesh out;
  bool ok = false;
  if (op == Op::kUnion) ok = PMP::corefine_and_compute_union(a, b, out);
  if (op == Op::kIntersection) ok = PMP::corefine_and_compute_intersection(a, b, out);
  if (op == Op::kDifference) ok = PMP::corefine_and_compute_difference(a, b, out);
  EXPECT_TRUE(ok);
  return out;
}

/// Compares Cover and CGAL on one scene: `solid` (Cover's non-evaluated expression), `mesh`
/// (CGAL's corefined result) and `truth(inside per leaf)` (the expression on leaf memberships).
void check(const Solid& solid, const Mesh& result, const std::vector<const Mesh*>& leaves,
           const std::function<bool(const std::vector<bool>&)>& truth) {
  const double expected = CGAL::to_double(PMP::volume(result));
  const VolumeResult v = volume(solid);
  EXPECT_EQ(v.method, "rays");
  if (v.target_met) {
    EXPECT_NEAR(v.volume, expected, 1e-4 * expected);
  }
  // The proven bound holds (it is loose on dense meshes, where `cover volume` then evaluates).
  EXPECT_LE(std::abs(v.volume - expected), v.error_bound + 1e-9 * expected);

  std::vector<CGAL::Side_of_triangle_mesh<Mesh, K>> sides;
  for (const Mesh* m : leaves) sides.emplace_back(*m);
  const Bbox box = solid.bbox();
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y),
      uz(box.min.z, box.max.z);
  std::vector<Vec3> pts(100000);
  for (Vec3& p : pts) p = {ux(rng), uy(rng), uz(rng)};
  const auto classes = classify(solid, pts);
  long disagreements = 0, boundary = 0, inside = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    std::vector<bool> in;
    bool on = false;
    for (const auto& side : sides) {
      const auto s = side(K::Point_3(pts[i].x, pts[i].y, pts[i].z));
      on = on || s == CGAL::ON_BOUNDARY;
      in.push_back(s == CGAL::ON_BOUNDED_SIDE);
    }
    if (on) {
      ++boundary;
      continue;
    }
    const bool t = truth(in);
    inside += t;
    disagreements += (classes[i] == PointClass::kInside) != t;
  }
  std::printf(
      "cover volume %.9g (rays %zu, error bound %.3g), CGAL corefinement %.9g, relative "
      "difference %.2g; %zu points, %ld inside, %ld disagreements\n",
      v.volume, v.rays, v.error_bound, expected, std::abs(v.volume - expected) / expected,
      pts.size(), inside, disagreements);
  EXPECT_EQ(disagreements, 0);
  EXPECT_GT(inside, 1000);
  EXPECT_EQ(boundary, 0);
}

TEST(CorefineOracle, Difference) {
  const Operand a = operand("bunny00.off", {0, 0, 0}, 1.0, 0);
  const Operand b = operand("elephant.off", {0.35, 0.2, 0.1}, 0.8, 25);
  check(subtract({a.solid, b.solid}), corefine(a.mesh, b.mesh, Op::kDifference), {&a.mesh, &b.mesh},
        [](const std::vector<bool>& in) { return in[0] && !in[1]; });
}

TEST(CorefineOracle, Intersection) {
  const Operand a = operand("armadillo.off", {0, 0, 0}, 1.0, 10);
  const Operand b = operand("knot1.off", {0.1, -0.2, 0.05}, 1.0, 40);
  check(intersect({a.solid, b.solid}), corefine(a.mesh, b.mesh, Op::kIntersection),
        {&a.mesh, &b.mesh}, [](const std::vector<bool>& in) { return in[0] && in[1]; });
}

TEST(CorefineOracle, ThreeLevelMix) {
  // (bunny − knot) ∪ (elephant ∩ fandisk)
  const Operand a = operand("bunny00.off", {0, 0, 0}, 1.0, 0);
  const Operand b = operand("knot1.off", {0.2, 0.3, 0}, 0.7, 60);
  const Operand c = operand("elephant.off", {0.9, -0.3, 0.2}, 0.9, 15);
  const Operand d = operand("fandisk.off", {0.8, -0.2, 0.3}, 0.9, 75);
  const Solid s = unite({subtract({a.solid, b.solid}), intersect({c.solid, d.solid})});
  const Mesh left = corefine(a.mesh, b.mesh, Op::kDifference);
  const Mesh right = corefine(c.mesh, d.mesh, Op::kIntersection);
  check(s, corefine(left, right, Op::kUnion), {&a.mesh, &b.mesh, &c.mesh, &d.mesh},
        [](const std::vector<bool>& in) { return (in[0] && !in[1]) || (in[2] && in[3]); });
}

}  // namespace
}  // namespace cover
