// Point-set leaves (points/point_set.h, io/point_set_io.h): clouds sampled from closed surfaces
// classify as the surface off a band (a sphere against |p| < 1; a mesh against its exact
// classification where the sound box test settles the band around the point), with given and
// with estimated normals; estimated normals point outward; tangent-plane Voronoi areas sum to
// the surface's area; the scene node reads .xyz and .npy and names bad lines; mixed evaluation
// meshes a cloud into a valid closed mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cover/covering/box_states.h"
#include "cover/io/npy.h"
#include "cover/io/scene.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "helpers.h"

namespace cover {
namespace {

/// n points on the unit sphere (Fibonacci lattice) and their normals.
std::vector<Vec3> fibonacci(size_t n) {
  std::vector<Vec3> p(n);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (size_t i = 0; i < n; ++i) {
    const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), a = golden * i;
    p[i] = {r * std::cos(a), r * std::sin(a), z};
  }
  return p;
}

std::vector<Vec3> random_points(size_t n, double half, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<Vec3> q(n);
  for (Vec3& p : q) p = {u(rng), u(rng), u(rng)};
  return q;
}

TEST(PointSet, SphereSamplesClassifyAsTheSphere) {
  const std::vector<Vec3> p = fibonacci(3000);
  const std::vector<Vec3> q = random_points(20000, 1.5, 1);
  for (bool given : {true, false}) {
    const Model m = point_set(p, given ? std::span<const Vec3>(p) : std::span<const Vec3>());
    ASSERT_TRUE(m.solid().has_open_leaf());
    const std::vector<PointClass> c = m.classify(q);
    size_t tested = 0, wrong = 0;
    for (size_t i = 0; i < q.size(); ++i) {
      const double r = std::sqrt(dot(q[i], q[i]));
      if (std::abs(r - 1) < 0.08) continue;
      ++tested;
      wrong += (c[i] != PointClass::kOutside) != (r < 1);
    }
    EXPECT_GT(tested, 15000u);
    EXPECT_EQ(wrong, 0u) << (given ? "given normals" : "estimated normals");
  }
}

TEST(PointSet, EstimatedNormalsPointOutwardAndAreasSumToTheArea) {
  const std::vector<Vec3> p = fibonacci(5000);
  const std::vector<Vec3> n = estimate_normals(p, {});
  size_t outward = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(dot(n[i], n[i]), 1, 1e-12);
    outward += dot(n[i], p[i]) > 0.99;
  }
  EXPECT_EQ(outward, p.size());
  const std::vector<double> a = voronoi_areas(p, p, {});
  double total = 0;
  for (double x : a) total += x;
  EXPECT_NEAR(total, 4 * M_PI, 0.02 * 4 * M_PI);
}

TEST(PointSet, MeshSamplesClassifyAsTheMeshOffTheBand) {
  const Model mesh_model = load(std::filesystem::path(COVER_SOURCE_DIR) / "models/torus.off");
  const Solid& s = mesh_model.solid();
  // Area-weighted samples of the faces (fans), with the face normals.
  std::vector<std::array<Vec3, 3>> tris;
  std::vector<double> cumulative;
  double total = 0;
  for (size_t f = 0; f < s.face_count(); ++f) {
    const auto face = s.face(f);
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      const std::array<Vec3, 3> t = {s.vertices[face[0]], s.vertices[face[k]],
                                     s.vertices[face[k + 1]]};
      const Vec3 c = cross(t[1] - t[0], t[2] - t[0]);
      total += 0.5 * std::sqrt(dot(c, c));
      tris.push_back(t);
      cumulative.push_back(total);
    }
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> p, n;
  for (int i = 0; i < 20000; ++i) {
    const size_t t =
        std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) - cumulative.begin();
    const auto& tr = tris[std::min(t, tris.size() - 1)];
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    p.push_back(tr[0] + a * (tr[1] - tr[0]) + b * (tr[2] - tr[0]));
    const Vec3 c = cross(tr[1] - tr[0], tr[2] - tr[0]);
    n.push_back((1 / std::sqrt(dot(c, c))) * c);
  }
  const Bbox b = *mesh_model.bounds();
  const Vec3 d = b.max - b.min;
  const double band = 0.04 * std::sqrt(dot(d, d));
  for (bool given : {true, false}) {
    const Model cloud = point_set(p, given ? std::span<const Vec3>(n) : std::span<const Vec3>());
    std::vector<Vec3> q;
    std::vector<uint8_t> expected;
    std::mt19937_64 r2(4);
    for (int i = 0; i < 20000; ++i) {
      const Vec3 x{b.min.x + d.x * u(r2), b.min.y + d.y * u(r2), b.min.z + d.z * u(r2)};
      Bbox around;
      around.add(x - Vec3{band, band, band});
      around.add(x + Vec3{band, band, band});
      const uint8_t st = box_state(mesh_model.prepared(), around);
      if (st == kBoxUndecided) continue;
      q.push_back(x);
      expected.push_back(st);
    }
    ASSERT_GT(q.size(), 3000u);
    const std::vector<PointClass> c = cloud.classify(q);
    size_t wrong = 0;
    for (size_t i = 0; i < q.size(); ++i)
      wrong += (c[i] != PointClass::kOutside) != (expected[i] == kBoxInside);
    EXPECT_EQ(wrong, 0u) << (given ? "given normals" : "estimated normals");
  }
}

TEST(PointSet, SceneNodeReadsXyzAndNpyAndNamesBadLines) {
  const auto dir = test::temp_dir("points");
  const std::vector<Vec3> p = fibonacci(500);
  std::string xyz, xyz3;
  for (const Vec3& v : p) {
    xyz += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + " " +
           std::to_string(v.x) + "," + std::to_string(v.y) + "\t" + std::to_string(v.z) + "\n";
    xyz3 += std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
  }
  test::write_file(dir / "s.xyz", "# a sphere\n" + xyz);
  test::write_file(dir / "s3.pts", xyz3);
  {
    const uint64_t shape[2] = {p.size(), 6};
    std::string npy = npy_header("<f8", shape);
    for (const Vec3& v : p)
      for (double x : {v.x, v.y, v.z, v.x, v.y, v.z})
        npy.append(reinterpret_cast<const char*>(&x), 8);
    test::write_file(dir / "s.npy", npy);
  }
  const std::vector<Vec3> q = random_points(4000, 1.5, 9);
  std::vector<std::vector<PointClass>> classes;
  for (const char* file : {"s.xyz", "s.npy", "s3.pts"}) {
    LoadedInput in =
        parse_scene(std::string(R"({"points": {"file": ")") + file + "\"}}", dir / "scene.json");
    ASSERT_EQ(in.solid.leaves.size(), 1u) << file;
    EXPECT_NE(in.solid.leaves[0].name.find("point set (500 points)"), std::string::npos);
    classes.push_back(Model(std::move(in.solid)).classify(q));
  }
  size_t differ = 0;  // .xyz (6 decimals) and .npy (exact) give nearly the same cloud
  for (size_t i = 0; i < q.size(); ++i) differ += classes[0][i] != classes[1][i];
  EXPECT_LT(differ, 40u);
  test::write_file(dir / "bad.xyz", "0 0 0\n1 0 0\n1 1 0 5\n");
  try {
    parse_scene(R"({"points": {"file": "bad.xyz"}})", dir / "scene.json");
    ADD_FAILURE() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.xyz:3: expected 3 or 6 numbers"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_scene(R"({"points": {"file": "s.xyz", "neighbours": 2}})", dir / "scene.json"),
               InputError);
  std::filesystem::remove_all(dir);
}

TEST(PointSet, EvaluatesToAValidMesh) {
  const std::vector<Vec3> p = fibonacci(1500);
  const Model m = point_set(p, p);
  const EvaluateResult e = m.evaluate({.mesh_resolution = 16});
  ASSERT_EQ(e.meshed.size(), 1u);
  const MeshReport r = validate_mesh(e.mesh);
  EXPECT_TRUE(r.closed && r.manifold && r.oriented && r.outward);
  EXPECT_FALSE(r.self_intersecting.value_or(true));
  EXPECT_NEAR(e.volume, 4 * M_PI / 3, 0.1 * 4 * M_PI / 3);
  EXPECT_THROW(point_set(std::span<const Vec3>(p.data(), 10)), InputError);
}

}  // namespace
}  // namespace cover
