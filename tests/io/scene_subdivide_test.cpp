// The scene's "subdivide" node (io/scene.h, docs/cli.md "Scenes"): its leaf is cover::subdivide
// of the child's mesh placed as the JSON says; the leaf takes part in non-evaluated CSG exactly
// as the same mesh read from a file; bad nodes are errors naming the JSON path.
#include <gtest/gtest.h>

#include <random>

#include "cover/covering/classify.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "cover/subdivision/subdivide.h"
#include "helpers.h"

namespace cover {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_scene(text, "scene.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

void expect_same_mesh(const PolygonMesh& a, const PolygonMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (size_t v = 0; v < a.vertices.size(); ++v) ASSERT_EQ(a.vertices[v], b.vertices[v]) << v;
  EXPECT_EQ(a.face_start, b.face_start);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
}

TEST(SceneSubdivide, LeafIsTheSubdividedChildAndClassifiesAsThatMesh) {
  const auto dir = test::temp_dir("scene-subdivide");
  const std::string torus = (test::source_dir() / "models/torus.off").string();
  test::write_file(dir / "s.json", R"({"union": [
      {"subdivide": {"scheme": "catmull-clark", "levels": 2, "exact_rounding": true,
                     "child": {"mesh": ")" +
                                       torus + R"(",
                               "transform": {"translate": [1, 0, 0]}}},
       "transform": {"scale": 2}},
      {"box": {"min": [2, -1, -1], "max": [4, 1, 1]}}]})");
  const LoadedInput in = load_input(dir / "s.json");
  ASSERT_EQ(in.solid.leaves.size(), 2u);
  EXPECT_EQ(in.solid.leaves[0].origin, "/union/0/subdivide");
  EXPECT_NE(in.solid.leaves[0].name.find("catmull-clark"), std::string::npos);
  EXPECT_NE(in.solid.leaves[0].name.find("torus.off"), std::string::npos);
  EXPECT_TRUE(in.warnings.empty());

  // The same mesh built independently: read, placed, subdivided, scaled.
  PolygonMesh expected = read_mesh(torus);
  apply_transform(Transform::translation({1, 0, 0}), expected);
  expected =
      subdivide(expected, {.scheme = Scheme::kCatmullClark, .levels = 2, .exact_rounding = true});
  apply_transform(Transform::scaling({2, 2, 2}), expected);
  expect_same_mesh(leaf_mesh(in.solid, 0), expected);

  // Classification of the scene equals that of the same union with the mesh as a file leaf: on
  // the subdivided surface's vertices and face centres, and at random points around it.
  write_mesh(dir / "sub.off", expected);
  test::write_file(dir / "m.json", R"({"union": [{"mesh": "sub.off"},
      {"box": {"min": [2, -1, -1], "max": [4, 1, 1]}}]})");
  const LoadedInput direct = load_input(dir / "m.json");
  // (A sample: each point on a curved surface is decided exactly, at a cost per point.)
  std::vector<Vec3> points;
  for (size_t v = 0; v < expected.vertices.size(); v += 409) points.push_back(expected.vertices[v]);
  const size_t surface = points.size();  // then face centres: off the surface (curved quads)
  for (size_t f = 0; f < expected.face_count(); f += 389) {
    Vec3 c{0, 0, 0};
    for (uint32_t v : expected.face(f)) c = c + expected.vertices[v];
    points.push_back((1.0 / static_cast<double>(expected.face(f).size())) * c);
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-6, 8);
  for (int i = 0; i < 300; ++i) points.push_back({u(rng), u(rng) / 2, u(rng) / 4});
  const std::vector<PointClass> a = classify(in.solid, points);
  const std::vector<PointClass> b = classify(direct.solid, points);
  EXPECT_EQ(a, b);
  size_t inside = 0, boundary = 0;
  for (PointClass c : a) {
    inside += c == PointClass::kInside;
    boundary += c != PointClass::kInside && c != PointClass::kOutside;
  }
  EXPECT_GT(inside, 0u);
  EXPECT_GE(boundary, surface);
  std::filesystem::remove_all(dir);
}

TEST(SceneSubdivide, NestedNodesAndPrimitivesRefineInOrder) {
  const LoadedInput in = parse_scene(R"({"subdivide": {"scheme": "doo-sabin",
      "child": {"subdivide": {"levels": 1, "child": {"box": {"min": [0,0,0], "max": [1,2,3]}}},
                "transform": {"rotate": {"axis": [0,0,1], "degrees": 30}}}}})",
                                     "scene.json");
  ASSERT_EQ(in.solid.leaves.size(), 1u);
  PolygonMesh expected = subdivide(make_box({0, 0, 0}, {1, 2, 3}), {});
  apply_transform(Transform::rotation({0, 0, 1}, 30), expected);
  expected = subdivide(expected, {.scheme = Scheme::kDooSabin});
  expect_same_mesh(leaf_mesh(in.solid, 0), expected);
  EXPECT_EQ(in.solid.leaves[0].origin, "/subdivide");
  // levels 0: the child itself.
  const LoadedInput zero = parse_scene(
      R"({"subdivide": {"levels": 0, "child": {"box": {"min": [0,0,0], "max": [1,1,1]}}}})",
      "scene.json");
  expect_same_mesh(leaf_mesh(zero.solid, 0), make_box({0, 0, 0}, {1, 1, 1}));
}

TEST(SceneSubdivide, BadNodesNameTheJsonPath) {
  const std::string box = R"({"box": {"min": [0,0,0], "max": [1,1,1]}})";
  const auto node = [&](const std::string& fields) {
    return R"({"union": [)" + box + R"(, {"subdivide": {)" + fields + "}}]}";
  };
  const auto starts = [](const std::string& e, const std::string& prefix) {
    return e.rfind(prefix, 0) == 0;
  };
  EXPECT_PRED2(starts, error_of(node(R"("scheme": "butterfly", "child": )" + box)),
               "scene.json: /union/1/subdivide/scheme: expected");
  EXPECT_PRED2(starts, error_of(node(R"("scheme": 3, "child": )" + box)),
               "scene.json: /union/1/subdivide/scheme: expected");
  for (const char* levels : {"-1", "31", "1.5", "\"2\""})
    EXPECT_PRED2(starts,
                 error_of(node(std::string(R"("levels": )") + levels + ", \"child\": " + box)),
                 "scene.json: /union/1/subdivide/levels: expected an integer from 0 to 30");
  EXPECT_PRED2(starts, error_of(node(R"("exact_rounding": 1, "child": )" + box)),
               "scene.json: /union/1/subdivide/exact_rounding: expected true or false");
  EXPECT_PRED2(starts, error_of(node(R"("level": 1, "child": )" + box)),
               "scene.json: /union/1/subdivide/level: unknown key");
  EXPECT_PRED2(starts, error_of(node(R"("levels": 1)")),
               "scene.json: /union/1/subdivide: missing key 'child'");
  // Operations, fields and warps are not meshes: refused at the child's path.
  for (const std::string& child :
       {R"({"union": [)" + box + "]}",
        std::string(R"({"field": {"skeleton": {"point": [0,0,0]}, "radius": 1, "influence": 2}})"),
        R"({"twist": {"axis": {"direction": [0,0,1]}, "degrees_per_unit": 10, "child": )" + box +
            "}}",
        std::string("[]")}) {
    const std::string e = error_of(node(R"("child": )" + child));
    EXPECT_PRED2(starts, e, "scene.json: /union/1/subdivide/child") << child;
    EXPECT_NE(
        e.find("a subdivide node's child is a mesh, box, sphere, cylinder, subdivide or ffd node"),
        std::string::npos)
        << e;
    EXPECT_EQ(e.find('\n'), std::string::npos);
  }
  // What subdivide() refuses: named at the node.
  EXPECT_PRED2(starts, error_of(node(R"("scheme": "loop", "child": )" + box)),
               "scene.json: /union/1/subdivide: ");
  EXPECT_PRED2(starts, error_of(node(R"("levels": 30, "child": )" + box)),
               "scene.json: /union/1/subdivide: ");
}

TEST(SceneSubdivide, MeshFileErrorsNameTheChildPathAndTheFile) {
  const auto dir = test::temp_dir("scene-subdivide");
  // Three triangles on one edge: subdivide() refuses the non-manifold edge.
  test::write_file(dir / "fin.off",
                   "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  test::write_file(dir / "a.json", R"({"subdivide": {"child": {"mesh": "fin.off"}}})");
  test::write_file(dir / "b.json", R"({"subdivide": {"child": {"mesh": "missing.off"}}})");
  for (const char* scene : {"a.json", "b.json"}) {
    try {
      load_input(dir / scene);
      ADD_FAILURE() << scene << " accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind((dir / scene).string() + ": /subdivide", 0), 0u) << what;
      EXPECT_NE(what.find(scene[0] == 'a' ? "fin.off: edge" : "missing.off"), std::string::npos)
          << what;
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
