// JSON scenes (io/scene.h): every node kind, transforms, and errors naming the JSON path.
#include "cover/io/scene.h"

#include <gtest/gtest.h>

#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

LoadedInput parse(const std::string& text) { return parse_scene(text, "scene.json"); }

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

double leaf_volume(const Solid& s, uint32_t l) { return signed_volume(leaf_mesh(s, l)); }

TEST(Scene, AllNodeKinds) {
  const LoadedInput in = parse(R"({"difference": [
      {"union": [{"box": {"min": [0,0,0], "max": [2,2,2]}},
                 {"sphere": {"center": [3,3,3], "radius": 1, "segments": 8}}]},
      {"intersection": [{"cylinder": {"base": [1,1,-1], "top": [1,1,3], "radius": 0.5}},
                        {"complement": {"box": {"min": [0,0,5], "max": [1,1,6]}}}]}]})");
  const Solid& s = in.solid;
  EXPECT_EQ(s.leaves.size(), 4u);
  EXPECT_EQ(s.tree.nodes[s.tree.root].op, CsgOp::kDifference);
  EXPECT_EQ(s.leaves[0].origin, "/difference/0/union/0/box");
  EXPECT_EQ(s.leaves[2].origin, "/difference/1/intersection/0/cylinder");
  EXPECT_DOUBLE_EQ(leaf_volume(s, 0), 8.0);
  EXPECT_TRUE(in.warnings.empty());
}

TEST(Scene, ColoursAreInheritedFromTheNearestNodeThatHasOne) {
  const LoadedInput in = parse(R"({"difference": [
      {"union": [{"box": {"min": [0,0,0], "max": [2,2,2]}, "color": "#FF8000"},
                 {"sphere": {"center": [3,3,3], "radius": 1, "segments": 8}}],
       "color": [0, 0.5, 1]},
      {"cylinder": {"base": [1,1,-1], "top": [1,1,3], "radius": 0.5}}], "color": [1, 1, 1]})");
  const Solid& s = in.solid;
  ASSERT_EQ(s.leaves.size(), 3u);
  EXPECT_EQ(s.leaves[0].colour, (std::array<uint8_t, 3>{255, 128, 0}));
  EXPECT_EQ(s.leaves[1].colour, (std::array<uint8_t, 3>{0, 128, 255}));
  EXPECT_EQ(s.leaves[2].colour, (std::array<uint8_t, 3>{255, 255, 255}));
  EXPECT_FALSE(parse(R"({"box": {"min": [0,0,0], "max": [1,1,1]}})").solid.leaves[0].colour);
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "color": [1, 0]})"),
            "scene.json: /color: expected [r, g, b] from 0 to 1 or \"#rrggbb\"");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "color": [1, 0, -0.5]})"),
            "scene.json: /color/2: expected a number from 0 to 1");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "color": "#12345g"})"),
            "scene.json: /color: expected [r, g, b] from 0 to 1 or \"#rrggbb\", got \"#12345g\"");
}

TEST(Scene, TransformsComposeParentAfterChild) {
  // Child: scale 2 then translate x by 1 → [1,3]; parent: translate y by 10.
  const Solid s = parse(R"({"union": [{"box": {"min": [0,0,0], "max": [1,1,1]},
      "transform": {"scale": 2, "translate": [1,0,0]}}],
      "transform": {"translate": [0,10,0]}})")
                      .solid;
  EXPECT_EQ(s.leaves[0].bbox.min, (Vec3{1, 10, 0}));
  EXPECT_EQ(s.leaves[0].bbox.max, (Vec3{3, 12, 2}));
  // T·R·S: rotate 90° about z then translate.
  const Solid r = parse(R"({"box": {"min": [0,0,0], "max": [2,1,1]},
      "transform": {"rotate": {"axis": [0,0,1], "degrees": 90}, "translate": [5,0,0]}})")
                      .solid;
  EXPECT_NEAR(r.leaves[0].bbox.min.x, 4, 1e-15);
  EXPECT_NEAR(r.leaves[0].bbox.max.y, 2, 1e-15);
  // Row-major matrix.
  const Solid m = parse(R"({"box": {"min": [0,0,0], "max": [1,1,1]},
      "transform": {"matrix": [1,0,0,7, 0,1,0,0, 0,0,1,0, 0,0,0,1]}})")
                      .solid;
  EXPECT_EQ(m.leaves[0].bbox.min, (Vec3{7, 0, 0}));
}

TEST(Scene, NegativeDeterminantKeepsSolidsSolid) {
  const LoadedInput in = parse(R"({"box": {"min": [0,0,0], "max": [1,2,3]},
      "transform": {"scale": [-1, 1, 1]}})");
  EXPECT_DOUBLE_EQ(leaf_volume(in.solid, 0), 6.0);
  EXPECT_TRUE(in.warnings.empty());
}

TEST(Scene, ErrorsNameTheJsonPath) {
  EXPECT_EQ(error_of(R"({"union": [{"box": {"min": [0,0,0], "max": [1,1,1]}},
      {"box": {"min": [0,0,0], "max": [1,1,1]}, "transform": {"scale": "big"}}]})"),
            "scene.json: /union/1/transform/scale: expected a number or 3 numbers");
  EXPECT_EQ(error_of(R"({"union": []})"),
            "scene.json: /union: expected an array of one or more nodes");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1]}})"),
            "scene.json: /box/max: expected 3 numbers");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1], "colour": 1}})"),
            "scene.json: /box/colour: unknown key");
  EXPECT_EQ(error_of(R"({"sphere": {"center": [0,0,0], "radius": -1}})"),
            "scene.json: /sphere/radius: expected a positive number");
  EXPECT_EQ(error_of(R"({"sphere": {"center": [0,0,0], "radius": 1, "segments": 1000000000}})"),
            "scene.json: /sphere/segments: expected an integer from 3 to 4096");
  EXPECT_EQ(error_of(R"({"frobnicate": {}})"), "scene.json: /: unknown key 'frobnicate'");
  EXPECT_EQ(error_of(R"({"difference": [{"box": {"min": [0,0,0], "max": [1,1,1]}}]})"),
            "scene.json: /difference: expected two or more nodes");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "transform": {"scale": 0}})"),
            "scene.json: /transform: transform is singular");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]},
      "transform": {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1,0,0,1]}})"),
            "scene.json: /transform/matrix: last row must be 0 0 0 1");
  EXPECT_EQ(error_of("{\"box\": \n {\"min\": [0,0,0],, }"),
            "scene.json:2: invalid JSON: parse error at line 2, column 18: syntax error while "
            "parsing object key - unexpected ','; expected string literal");
  EXPECT_EQ(error_of(R"({"mesh": "does-not-exist.off"})")
                .rfind("scene.json: /mesh: does-not-exist.off: cannot open: ", 0),
            0u);
  EXPECT_EQ(error_of(R"({"mesh": ""})"), "scene.json: /mesh: expected a non-empty file path");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1]}, "box": {}})"),
            "scene.json: /: duplicate key 'box'");
  EXPECT_EQ(error_of(R"({"union": [{"sphere": {"center": [0,0,0], "radius": 1}},
      {"box": {"min": [0,0,0], "max": [1,1,1], "min": [0,0,0]}}]})"),
            "scene.json: /union/1/box: duplicate key 'min'");
  EXPECT_EQ(error_of(R"({"union": [{"box": {"min": [0,0,0], "max": [1,1,1]}}, {"box": {}}],
      "transform": {"scale": 2, "scale": 3}})"),
            "scene.json: /transform: duplicate key 'scale'");
  std::string deep;
  for (int i = 0; i < 300; ++i) deep += R"({"complement": )";
  deep += R"({"box": {"min": [0,0,0], "max": [1,1,1]}})";
  for (int i = 0; i < 300; ++i) deep += "}";
  EXPECT_NE(error_of(deep).find("nested deeper than"), std::string::npos);
}

// Found by fuzz_scene: a number too large for a double made nlohmann throw out_of_range, which
// escaped as an internal error instead of an InputError.
TEST(Scene, FuzzRegressionNumberOverflow) {
  const auto file = test::source_dir() / "tests" / "data" / "fuzz" / "scene-number-overflow.json";
  EXPECT_THROW(load_input(file), InputError);
  // The number rule (io/parse.h): overflow names the value's JSON path.
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,0], "max": [1,1,1e400]}})"),
            "scene.json: /box/max/2: out-of-range number '1e400'");
  EXPECT_EQ(error_of(R"({"box": {"min": [0,0,1e-400], "max": [1,1,1]}})"), "no error");
}

TEST(Scene, MeshLeavesRelativeToSceneFolderOpenAndInsideOut) {
  const auto dir = test::temp_dir("scene");
  PolygonMesh box = make_box({0, 0, 0}, {1, 1, 1});
  write_mesh(dir / "box.off", box);
  PolygonMesh inverted = box;
  for (size_t f = 0; f < inverted.face_count(); ++f)
    std::reverse(inverted.face_vertices.begin() + inverted.face_start[f],
                 inverted.face_vertices.begin() + inverted.face_start[f + 1]);
  write_mesh(dir / "inverted.off", inverted);
  PolygonMesh open = box;
  open.face_start.pop_back();
  open.face_vertices.resize(open.face_start.back());
  write_mesh(dir / "open.off", open);

  test::write_file(dir / "s.json", R"({"union": [{"mesh": "box.off"}, {"mesh": "inverted.off",
      "transform": {"translate": [3,0,0]}}]})");
  const LoadedInput in = load_input(dir / "s.json");
  ASSERT_EQ(in.warnings.size(), 1u);
  EXPECT_NE(in.warnings[0].find("inside-out"), std::string::npos);
  EXPECT_DOUBLE_EQ(leaf_volume(in.solid, 1), 1.0);
  EXPECT_TRUE(in.solid.leaves[1].flipped);

  test::write_file(dir / "o.json", R"({"union": [{"mesh": "open.off"}]})");
  LoadOptions closed_only;
  closed_only.require_closed = true;
  try {
    load_input(dir / "o.json", closed_only);
    ADD_FAILURE() << "open mesh accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("open mesh: 4 boundary edges"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("/union/0/mesh"), std::string::npos);
  }
  LoadOptions lenient;
  lenient.require_closed = false;
  EXPECT_EQ(load_input(dir / "o.json", lenient).solid.leaves.size(), 1u);
  std::filesystem::remove_all(dir);
}

// A file placed by several leaves is read once (scene.cpp's FileRead): every leaf still gets
// its own transformed copy, its own inside-out repair and its own messages, and a bad file fails
// at the first leaf (in document order) that names it.
TEST(Scene, InstancesOfOneFileAreIndependentLeaves) {
  const auto dir = test::temp_dir("scene");
  write_mesh(dir / "box.off", make_box({0, 0, 0}, {1, 1, 1}));
  test::write_file(dir / "s.json", R"({"union": [
      {"mesh": "box.off"},
      {"mesh": "./box.off", "transform": {"scale": 2, "translate": [5,0,0]}},
      {"mesh": "box.off", "transform": {"matrix": [-1,0,0,-3, 0,1,0,0, 0,0,1,0, 0,0,0,1]}}]})");
  const LoadedInput in = load_input(dir / "s.json");
  ASSERT_EQ(in.solid.leaves.size(), 3u);
  EXPECT_DOUBLE_EQ(leaf_volume(in.solid, 0), 1.0);
  EXPECT_DOUBLE_EQ(leaf_volume(in.solid, 1), 8.0);
  EXPECT_DOUBLE_EQ(leaf_volume(in.solid, 2), 1.0);  // the mirror image, still outward
  EXPECT_TRUE(in.warnings.empty());
  EXPECT_EQ(leaf_mesh(in.solid, 0).vertices[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(leaf_mesh(in.solid, 1).vertices[0], (Vec3{5, 0, 0}));
  // An open file placed twice: each leaf its own warning, naming its JSON path.
  PolygonMesh open = make_box({0, 0, 0}, {1, 1, 1});
  open.face_start.pop_back();
  open.face_vertices.resize(open.face_start.back());
  write_mesh(dir / "open.off", open);
  test::write_file(dir / "o.json", R"({"union": [{"mesh": "open.off"},
      {"mesh": "open.off", "transform": {"translate": [2,0,0]}}]})");
  LoadOptions lenient;
  lenient.require_closed = false;
  const LoadedInput o = load_input(dir / "o.json", lenient);
  ASSERT_EQ(o.warnings.size(), 2u);
  EXPECT_NE(o.warnings[0].find("/union/0/mesh"), std::string::npos) << o.warnings[0];
  EXPECT_NE(o.warnings[1].find("/union/1/mesh"), std::string::npos) << o.warnings[1];
  test::write_file(dir / "bad.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n");
  test::write_file(dir / "b.json", R"({"union": [{"mesh": "box.off"}, {"mesh": "bad.off"},
      {"mesh": "bad.off"}]})");
  try {
    load_input(dir / "b.json");
    ADD_FAILURE() << "bad file accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/union/1/mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.off"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
