// Mesh skeletons (solid/field_leaf.h kMesh): a closed mesh as a field primitive with the
// pseudo-distance. Checked against independent paths: the mesh leaf's own classification (the
// simplicial covering) for the primitive alone, a brute-force distance over every triangle in
// long double for blends and box bounds, a mirrored mesh leaf for mirrored skeletons; meshes of
// blends pass the exact validity check; what is not a closed outward mesh is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cover/field/field.h"
#include "cover/io/scene.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "helpers.h"

namespace cover {
namespace {

using namespace test;

std::string torus() { return (source_dir() / "models" / "torus.off").string(); }

Model scene(const std::string& text) {
  LoadedInput in = parse_scene(text, "mesh_skeleton.json");
  return Model(std::move(in.solid), std::move(in.warnings));
}

std::string skeleton(const std::string& file, double r, double R, const std::string& extra = "") {
  return R"({"field": {"skeleton": {"mesh": ")" + file + R"("}, "radius": )" + std::to_string(r) +
         R"(, "influence": )" + std::to_string(R) + extra + "}}";
}

std::vector<Vec3> random_points(size_t n, const Bbox& box, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> out(n);
  for (Vec3& p : out)
    p = {box.min.x + u(rng) * (box.max.x - box.min.x), box.min.y + u(rng) * (box.max.y - box.min.y),
         box.min.z + u(rng) * (box.max.z - box.min.z)};
  return out;
}

/// Squared distance from p to the triangle abc in long double: the least of the plane distance
/// (where the projection falls inside) and the three edge distances.
long double triangle_d2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  using L = long double;
  auto sub = [](const Vec3& u, const Vec3& v) {
    return std::array<L, 3>{L(u.x) - v.x, L(u.y) - v.y, L(u.z) - v.z};
  };
  auto dot = [](const std::array<L, 3>& u, const std::array<L, 3>& v) {
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
  };
  auto cross = [](const std::array<L, 3>& u, const std::array<L, 3>& v) {
    return std::array<L, 3>{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                            u[0] * v[1] - u[1] * v[0]};
  };
  auto segment = [&](const Vec3& s, const Vec3& e) {
    const auto u = sub(e, s), v = sub(p, s);
    const L t = std::clamp(dot(v, u) / dot(u, u), L(0), L(1));
    const std::array<L, 3> w{v[0] - t * u[0], v[1] - t * u[1], v[2] - t * u[2]};
    return dot(w, w);
  };
  const auto n = cross(sub(b, a), sub(c, a));
  if (dot(cross(sub(b, a), sub(p, a)), n) >= 0 && dot(cross(sub(c, b), sub(p, b)), n) >= 0 &&
      dot(cross(sub(a, c), sub(p, c)), n) >= 0) {
    const L h = dot(sub(p, a), n);
    return h * h / dot(n, n);
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

/// f(p) − T by brute force: the skeleton's pseudo-distance from every triangle and the mesh
/// leaf's exact side; point primitives directly.
struct Reference {
  const FieldLeaf& leaf;
  const Model& mesh;  ///< the skeleton's mesh as a mesh leaf (its exact classification)

  long double operator()(const Vec3& p) const {
    long double f = 0;
    for (const FieldPrimitive& prim : leaf.primitives) {
      long double d;
      if (prim.kind == SkeletonKind::kMesh) {
        long double best = INFINITY;
        for (size_t t = 0; t < prim.points.size(); t += 3)
          best = std::min(best,
                          triangle_d2(p, prim.points[t], prim.points[t + 1], prim.points[t + 2]));
        const long double dist = std::sqrt(best);
        const PointClass c = mesh.classify(std::span<const Vec3>(&p, 1))[0];
        d = c == PointClass::kInside ? std::max(0.0L, prim.radius - dist) : prim.radius + dist;
      } else {
        const Vec3 q = prim.points[0];
        d = std::sqrt((long double)(p.x - q.x) * (p.x - q.x) +
                      (long double)(p.y - q.y) * (p.y - q.y) +
                      (long double)(p.z - q.z) * (p.z - q.z));
      }
      const long double R = prim.influence;
      const long double g = d < R ? std::pow(1 - d * d / (R * R), prim.exponent) : 0;
      f += prim.weight * g;
    }
    const FieldPrimitive& p0 = leaf.primitives[0];
    const long double r = p0.radius, R = p0.influence;
    return f - std::pow(1 - r * r / (R * R), p0.exponent);
  }
};

TEST(MeshSkeleton, AloneItIsTheMeshExactly) {
  const Model field = scene(skeleton(torus(), 0.1, 0.3));
  const Model mesh = scene(R"({"mesh": ")" + torus() + R"("})");
  const FieldLeaf& leaf = field.solid().fields.at(0);
  EXPECT_TRUE(field::exact(leaf));
  std::vector<Vec3> points = random_points(20000 / kCheckedStride, field.solid().bbox(), 1);
  // Every triangle's corners (on ∂M) and a point just off each corner.
  const std::vector<Vec3>& soup = leaf.primitives[0].points;
  for (size_t i = 0; i < soup.size(); i += 12 * kCheckedStride) {
    points.push_back(soup[i]);
    points.push_back({std::nextafter(soup[i].x, 9.0), soup[i].y, soup[i].z});
  }
  const std::vector<PointClass> f = field.classify(points), m = mesh.classify(points);
  size_t on = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const bool mesh_on = m[i] != PointClass::kInside && m[i] != PointClass::kOutside;
    on += mesh_on;
    ASSERT_EQ(f[i], mesh_on ? PointClass::kFace : m[i]) << i;
  }
  EXPECT_GT(on, soup.size() / 12 / kCheckedStride / 2);
}

TEST(MeshSkeleton, BlendAgreesWithBruteForceOffAThinBand) {
  const std::string text = R"({"blend": [)" + skeleton(torus(), 0.1, 0.3) + "," +
                           R"({"field": {"skeleton": {"point": [1.25, 0, 0.3]}, "radius": 0.1,
                               "influence": 0.3}}]})";
  const Model blend = scene(text);
  const Model mesh = scene(R"({"mesh": ")" + torus() + R"("})");
  const FieldLeaf& leaf = blend.solid().fields.at(0);
  EXPECT_FALSE(field::exact(leaf));
  const Reference f{leaf, mesh};
  // Points around the point primitive, where both terms are positive, and everywhere.
  std::vector<Vec3> points =
      random_points(1500 / kCheckedStride, {{0.9, -0.4, -0.1}, {1.6, 0.4, 0.7}}, 2);
  for (const Vec3& p : random_points(1500 / kCheckedStride, blend.solid().bbox(), 3))
    points.push_back(p);
  size_t checked = 0, inside = 0;
  for (const Vec3& p : points) {
    const long double ref = f(p);
    if (std::abs(ref) < 1e-9L) continue;
    const field::Sign s = field::sign(leaf, p);
    ASSERT_EQ(s, ref > 0 ? field::Sign::kInside : field::Sign::kOutside)
        << p.x << " " << p.y << " " << p.z << " ref " << (double)ref;
    ++checked;
    inside += ref > 0;
  }
  EXPECT_GT(checked, points.size() * 9 / 10);
  EXPECT_GT(inside, 50u / kCheckedStride);
}

TEST(MeshSkeleton, BoxBoundsHoldTheBruteForceValues) {
  const std::string text = R"({"blend": [)" + skeleton(torus(), 0.1, 0.3) + "," +
                           R"({"field": {"skeleton": {"point": [1.25, 0, 0.3]}, "radius": 0.1,
                               "influence": 0.3, "weight": -1}}]})";
  const Model blend = scene(text);
  const Model mesh = scene(R"({"mesh": ")" + torus() + R"("})");
  const FieldLeaf& leaf = blend.solid().fields.at(0);
  const Reference f{leaf, mesh};
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> size(0.001, 0.5);
  size_t settled = 0;
  for (const Vec3& c : random_points(400 / kCheckedStride, blend.solid().bbox(), 5)) {
    const double h = size(rng);
    const Bbox box{c - Vec3{h, h, h}, c + Vec3{h, h, h}};
    const field::Range r = field::bound(leaf, box);
    settled += r.lo > 0 || r.hi < 0;
    for (const Vec3& p : random_points(9, box, rng())) {
      const long double v = f(p);
      ASSERT_GE(v, r.lo - 1e-12L) << c.x << " " << c.y << " " << c.z << " h " << h;
      ASSERT_LE(v, r.hi + 1e-12L) << c.x << " " << c.y << " " << c.z << " h " << h;
    }
  }
  EXPECT_GT(settled, 100u / kCheckedStride);
}

TEST(MeshSkeleton, MirroredSkeletonIsTheMirroredMesh) {
  const std::string t = R"(, "transform": {"scale": [-1, 1, 1], "translate": [0.25, 0, 0]})";
  const Model field = scene(R"({"field": {"skeleton": {"mesh": ")" + torus() +
                            R"("}, "radius": 0.1, "influence": 0.3})" + t + "}");
  const Model mesh = scene(R"({"mesh": ")" + torus() + "\"" + t + "}");
  const std::vector<Vec3> points = random_points(5000 / kCheckedStride, field.solid().bbox(), 6);
  const std::vector<PointClass> f = field.classify(points), m = mesh.classify(points);
  for (size_t i = 0; i < points.size(); ++i) ASSERT_EQ(f[i], m[i]) << i;
  // Through the solid format and back.
  const Model back = Model::from_bytes(field.to_bytes());
  EXPECT_EQ(back.classify(points), f);
}

TEST(MeshSkeleton, BlendPolygonizesAndEvaluatesToValidMeshes) {
  const std::string blend = R"({"blend": [)" + skeleton(torus(), 0.1, 0.3) + "," +
                            R"({"field": {"skeleton": {"segment": [[1, 0, 0.2], [1.5, 0, 0.2]]},
                                "radius": 0.1, "influence": 0.3}}]})";
  PolygonizeOptions o;
  o.resolution = 48;
  const PolygonizeResult r = scene(blend).polygonize(o);
  ASSERT_GT(r.mesh.face_count(), 0u);
  const MeshReport rep = validate_mesh(r.mesh);
  EXPECT_TRUE(rep.closed && rep.manifold && rep.oriented && rep.outward);
  EXPECT_EQ(rep.components, 1);
  ASSERT_TRUE(rep.self_intersecting.has_value());
  EXPECT_FALSE(*rep.self_intersecting);
  // Blended with a box by the exact Booleans after meshing.
  const Model diff = scene(R"({"difference": [)" + blend +
                           R"(, {"box": {"min": [0, -2, -2], "max": [2, 2, 2]}}]})");
  EvaluateOptions eo;
  eo.mesh_resolution = 48;
  const EvaluateResult e = diff.evaluate(eo);
  ASSERT_EQ(e.meshed.size(), 1u);
  const MeshReport er = validate_mesh(e.mesh);
  EXPECT_TRUE(er.closed && er.manifold && er.oriented);
  ASSERT_TRUE(er.self_intersecting.has_value());
  EXPECT_FALSE(*er.self_intersecting);
}

TEST(MeshSkeleton, RefusesOpenInsideOutAndDegenerateMeshes) {
  const std::filesystem::path dir = temp_dir("mesh-skeleton");
  const std::string cube = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";
  const std::string faces = "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  write_file(dir / "cube.off", cube + faces);
  write_file(dir / "open.off",
             "OFF\n8 5 0\n" + cube.substr(10) + faces.substr(0, faces.rfind("4 3 0 4 7")));
  std::string inverted = "OFF\n8 6 0\n" + cube.substr(10);
  for (const char* f :
       {"4 1 2 3 0\n", "4 7 6 5 4\n", "4 4 5 1 0\n", "4 5 6 2 1\n", "4 6 7 3 2\n", "4 7 4 0 3\n"})
    inverted += f;
  write_file(dir / "inverted.off", inverted);
  EXPECT_NO_THROW(scene(skeleton((dir / "cube.off").string(), 0.1, 0.3)));
  auto message = [&](const std::string& file) {
    try {
      scene(skeleton((dir / file).string(), 0.1, 0.3));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("open.off").find("not closed"), std::string::npos) << message("open.off");
  EXPECT_NE(message("open.off").find("/field"), std::string::npos) << message("open.off");
  EXPECT_NE(message("inverted.off").find("inside out"), std::string::npos)
      << message("inverted.off");
  EXPECT_NE(message("missing.off").find("missing.off"), std::string::npos);
  // The cube alone is the cube: its corners and face centres are on it, its centre inside.
  const Model m = scene(skeleton((dir / "cube.off").string(), 0.1, 0.3));
  const std::vector<Vec3> probe = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 0.5}, {1.1, 0.5, 0.5}};
  const std::vector<PointClass> c = m.classify(probe);
  EXPECT_EQ(c[0], PointClass::kFace);
  EXPECT_EQ(c[1], PointClass::kFace);
  EXPECT_EQ(c[2], PointClass::kInside);
  EXPECT_EQ(c[3], PointClass::kOutside);
}

}  // namespace
}  // namespace cover
