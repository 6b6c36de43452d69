// catmull_clark_by_operators (modeler/operators.h) against the direct refinement of
// subdivision/subdivide.h: the same quads and the same doubles.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <tuple>

#include "cover/io/mesh_io.h"
#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"
#include "cover/subdivision/subdivide.h"
#include "dlfl_checks.h"

namespace cover::modeler {
namespace {

using test::totals;
using test::Totals;

/// Faces of `mesh` as vertex cycles over the vertex numbering of `reference`, matching vertices
/// by bitwise-equal positions (each vertex of `mesh` must match exactly one of `reference`).
std::vector<std::vector<uint32_t>> faces_in(const PolygonMesh& mesh, const PolygonMesh& reference) {
  std::map<std::tuple<double, double, double>, uint32_t> index;
  for (uint32_t v = 0; v < reference.vertices.size(); ++v) {
    const Vec3& p = reference.vertices[v];
    EXPECT_TRUE(index.emplace(std::tuple{p.x, p.y, p.z}, v).second) << "duplicate position";
  }
  std::vector<uint32_t> to_reference(mesh.vertices.size());
  for (uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    const auto it = index.find(std::tuple{p.x, p.y, p.z});
    if (it == index.end()) {
      ADD_FAILURE() << "vertex " << v << " at (" << p.x << ", " << p.y << ", " << p.z
                    << ") has no bitwise equal vertex in the direct refinement";
      return {};
    }
    to_reference[v] = it->second;
  }
  std::vector<std::vector<uint32_t>> faces;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    std::vector<uint32_t> cycle;
    for (uint32_t v : mesh.face(f)) cycle.push_back(to_reference[v]);
    std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
    faces.push_back(cycle);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// Refines `input` both ways and compares counts, validity, positions and faces.
void expect_equal_refinements(const PolygonMesh& input) {
  DlflMesh mesh = from_polygon_mesh(input);
  const Totals before = totals(mesh);
  const size_t corners = input.face_vertices.size();
  catmull_clark_by_operators(mesh);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh),
            (Totals{before.vertices + before.edges + before.faces, 2 * before.edges + corners,
                    corners, before.components, before.genus}));
  const PolygonMesh by_operators = to_polygon_mesh(mesh);
  const PolygonMesh direct = subdivide(input, {Scheme::kCatmullClark, 1});
  ASSERT_EQ(by_operators.vertices.size(), direct.vertices.size());
  ASSERT_EQ(by_operators.face_count(), direct.face_count());
  EXPECT_EQ(faces_in(by_operators, direct), faces_in(direct, direct));
}

TEST(CatmullClarkByOperators, EqualsTheDirectRefinementOnACube) {
  expect_equal_refinements(make_box({0, 0, 0}, {1, 1, 1}));
}

TEST(CatmullClarkByOperators, EqualsTheDirectRefinementOnATorus) {
  const PolygonMesh torus = read_mesh(std::filesystem::path(COVER_SOURCE_DIR) / "models/torus.off");
  expect_equal_refinements(torus);
  // A second level from the first level's DLFL (ids reused by the operators, so the corner
  // order is that of to_polygon_mesh, not of the first level's direct output).
  DlflMesh mesh = from_polygon_mesh(torus);
  catmull_clark_by_operators(mesh);
  const PolygonMesh level1 = to_polygon_mesh(mesh);
  expect_equal_refinements(level1);
}

TEST(CatmullClarkByOperators, EqualsTheDirectRefinementOnCgalMeshes) {
  for (const char* name : {"3torus.off", "cross.off"}) {
    SCOPED_TRACE(name);
    expect_equal_refinements(read_mesh(cover::test::cgal_mesh(name)));
  }
}

TEST(CatmullClarkByOperators, RefusesPointSpheresAndLoops) {
  DlflMesh mesh;
  mesh.create_vertex({0, 0, 0});
  EXPECT_THROW(catmull_clark_by_operators(mesh), InputError);
  DlflMesh loop;
  const VertexId v = loop.create_vertex({0, 0, 0});
  loop.insert_edge(Corner::point_sphere_of(v), Corner::point_sphere_of(v));
  EXPECT_THROW(catmull_clark_by_operators(loop), InputError);
}

}  // namespace
}  // namespace cover::modeler
