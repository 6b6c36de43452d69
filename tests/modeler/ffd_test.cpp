// Free-form deformation (modeler/ffd.h) against independent paths: the identity lattice returns
// the input exactly; a degree-1 lattice of an affine map is that map (no refinement: M = 0); a
// curved lattice's mesh is within its certified chord bound of the exact image of the input
// (points mapped one by one, distance to the mesh by brute force); the scene node names its
// errors by JSON path; the deformed box stays a closed 2-manifold.
#include "cover/modeler/ffd.h"

#include <gtest/gtest.h>

#include <random>

#include "cover/io/scene.h"
#include "cover/mesh/validate.h"
#include "cover/solid/errors.h"
#include "cover/solid/primitives.h"

namespace cover {
namespace {

/// Distance from p to triangle abc (Ericson §5.1.5, doubles).
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto len = [](const Vec3& v) { return std::sqrt(dot(v, v)); };
  if (d1 <= 0 && d2 <= 0) return len(ap);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return len(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return len(p - (a + (d1 / (d1 - d3)) * ab));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return len(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return len(p - (a + (d2 / (d2 - d6)) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return len(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
  const double denom = 1 / (va + vb + vc);
  return len(p - (a + (vb * denom) * ab + (vc * denom) * ac));
}

TEST(Ffd, IdentityLatticeReturnsTheInput) {
  const PolygonMesh box = make_box({-0.5, -0.25, 0}, {0.5, 0.25, 1});
  for (std::array<int, 3> degree : {std::array<int, 3>{1, 1, 1}, {2, 3, 2}, {4, 1, 5}}) {
    const FfdLattice f = identity_lattice({-1, -1, -1}, {1, 1, 2}, degree);
    const FfdResult r = ffd(box, f);
    EXPECT_EQ(r.levels, 0);
    EXPECT_EQ(r.chord_bound, 0);
    EXPECT_EQ(r.mesh.vertices, box.vertices);  // exactly
    EXPECT_EQ(r.mesh.face_count(), 12u);
  }
}

TEST(Ffd, AffineLatticeIsItsMap) {
  const PolygonMesh box = make_box({0, 0, 0}, {1, 1, 1});
  FfdLattice f = identity_lattice({0, 0, 0}, {1, 1, 1}, {1, 1, 1});
  auto affine = [](const Vec3& p) {
    return Vec3{2 * p.x + 0.5 * p.y + 1, p.y - 0.25 * p.z, 0.5 * p.z + 0.125 * p.x};
  };
  for (Vec3& p : f.points) p = affine(p);
  EXPECT_EQ(ffd_curvature_bound(f), 0);
  const FfdResult r = ffd(box, f);
  EXPECT_EQ(r.levels, 0);
  for (size_t v = 0; v < box.vertices.size(); ++v) {
    const Vec3 d = r.mesh.vertices[v] - affine(box.vertices[v]);
    EXPECT_LE(std::sqrt(dot(d, d)), 1e-15);
  }
}

TEST(Ffd, CurvedLatticeMeshIsWithinItsChordBound) {
  const PolygonMesh box = make_box({-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6});
  FfdLattice f = identity_lattice({-1, -1, -1}, {1, 1, 1}, {2, 2, 3});
  std::mt19937_64 rng(44);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (Vec3& p : f.points) p = p + Vec3{u(rng), u(rng), u(rng)};
  for (double tolerance : {1e-2, 2e-3}) {
    const FfdResult r = ffd(box, f, {.tolerance = tolerance});
    EXPECT_GT(r.levels, 0);
    EXPECT_LE(r.chord_bound, tolerance);
    const MeshReport rep = validate_mesh(r.mesh, {.check_self_intersection = false});
    EXPECT_TRUE(rep.closed && rep.manifold && rep.oriented);
    EXPECT_EQ(rep.genus, 0);
    // The exact image of random points on the box's faces is within the bound of the mesh.
    std::uniform_real_distribution<double> w(-0.6, 0.6);
    double worst = 0;
    for (int s = 0; s < 150; ++s) {
      Vec3 p{w(rng), w(rng), w(rng)};
      (s % 3 == 0 ? p.x : s % 3 == 1 ? p.y : p.z) = s % 2 ? 0.6 : -0.6;
      const Vec3 image = ffd_map(f, p);
      double best = INFINITY;
      for (size_t t = 0; t < r.mesh.face_count(); ++t) {
        const auto tri = r.mesh.face(t);
        best =
            std::min(best, distance_to_triangle(image, r.mesh.vertices[tri[0]],
                                                r.mesh.vertices[tri[1]], r.mesh.vertices[tri[2]]));
      }
      worst = std::max(worst, best);
    }
    EXPECT_LE(worst, r.chord_bound * (1 + 1e-9)) << tolerance;
    EXPECT_GT(worst, 0);
  }
}

TEST(Ffd, RefusesBadLatticesAndOutsideVertices) {
  const PolygonMesh box = make_box({0, 0, 0}, {1, 1, 1});
  FfdLattice f = identity_lattice({0, 0, 0}, {2, 2, 2}, {2, 2, 2});
  f.points.pop_back();
  EXPECT_THROW(ffd(box, f), InputError);
  EXPECT_THROW(ffd(box, identity_lattice({0.5, 0, 0}, {2, 2, 2}, {1, 1, 1})), InputError);
  EXPECT_THROW(ffd(box, identity_lattice({0, 0, 0}, {2, 2, 2}, {0, 1, 1})), InputError);
  EXPECT_THROW(ffd(box, identity_lattice({0, 0, 0}, {2, 2, 2}, {1, 1, 1}), {.tolerance = -1}),
               InputError);
}

TEST(Ffd, SceneNodeMakesAMeshLeafAndNamesItsErrors) {
  const std::string good = R"({"ffd": {"lattice": {"min": [-1, -1, -1], "max": [1, 1, 1],
    "degree": [1, 1, 2], "points": [[-1,-1,-1],[-1,-1,0],[-1,-1,1],[-1,1,-1],[-1,1,0],[-1,1,1],
      [1,-1,-1],[1,-1,0],[1,-1,1],[1,1,-1],[1.5,1.5,0.25],[1,1,1]]}, "tolerance": 0.01,
    "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}})";
  const LoadedInput in = parse_scene(good, "ffd.json");
  ASSERT_EQ(in.solid.leaves.size(), 1u);
  EXPECT_NE(in.solid.leaves[0].name.find("free-form deformation"), std::string::npos);
  EXPECT_GT(in.solid.face_count(), 12u);
  auto message = [](const std::string& text) {
    try {
      parse_scene(text, "ffd.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(R"({"ffd": {"lattice": {"min": [0,0,0], "max": [1,1,1], "points": [[0,0,0]]},
    "child": {"box": {"min": [0,0,0], "max": [1,1,1]}}}})")
                .find("ffd.json: /ffd/lattice: points: expected 8 control points"),
            std::string::npos);
  EXPECT_NE(message(R"({"ffd": {"lattice": {"min": [0,0,0], "max": [1,1,1], "degree": [1,1,1],
    "points": [[0,0,0],[0,0,1],[0,1,0],[0,1,1],[1,0,0],[1,0,1],[1,1,0],[1,1,1]]},
    "child": {"union": [{"box": {"min": [0,0,0], "max": [1,1,1]}}]}}})")
                .find("ffd.json: /ffd/child/union: an ffd node's child is a mesh"),
            std::string::npos);
  EXPECT_NE(message(R"({"ffd": {"lattice": {"min": [0,0,0], "max": [1,1,1], "degree": [1,1,1],
    "points": [[0,0,0],[0,0,1],[0,1,0],[0,1,1],[1,0,0],[1,0,1],[1,1,0],[1,1,1]]},
    "child": {"box": {"min": [0,0,0], "max": [2,1,1]}}}})")
                .find("ffd.json: /ffd: ffd: vertex"),
            std::string::npos);
}

}  // namespace
}  // namespace cover
