// `cover clip` end to end (docs/cli.md): outputs, JSON keys, scenes, exit status 2 on bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cover/io/mesh_io.h"
#include "cover/solid/measure.h"
#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

TEST(ClipCli, WritesBothHalvesAndReportsJson) {
  const auto dir = test::temp_dir("clip");
  const auto torus = test::source_dir() / "models/torus.off";
  const auto r = run_cover("clip " + q(torus) + " --plane 0,0,1,0.1 -o " + q(dir / "a.obj") +
                           " --below " + q(dir / "b.ply") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  for (const char* side : {"above", "below"}) {
    ASSERT_TRUE(j.contains(side));
    for (const char* key : {"volume", "faces", "rings", "closed"})
      EXPECT_TRUE(j[side].contains(key));
    EXPECT_TRUE(j[side]["closed"].get<bool>());
    EXPECT_EQ(j[side]["rings"].get<int>(), 2);
  }
  EXPECT_TRUE(j.contains("seconds"));
  const PolygonMesh above = read_mesh(dir / "a.obj"), below = read_mesh(dir / "b.ply");
  EXPECT_NEAR(signed_volume(above), j["above"]["volume"].get<double>(), 1e-12);
  EXPECT_NEAR(signed_volume(above) + signed_volume(below), signed_volume(read_mesh(torus)), 1e-9);
  // Triangulated caps: same volumes, more faces.
  const auto t = run_cover("clip " + q(torus) + " --plane 0,0,1,0.1 -o " + q(dir / "t.off") +
                           " --triangulate --json");
  ASSERT_EQ(t.status, 0) << t.err;
  const json jt = json::parse(t.out);
  EXPECT_GT(jt["above"]["faces"].get<int>(), j["above"]["faces"].get<int>());
  EXPECT_NEAR(jt["above"]["volume"].get<double>(), j["above"]["volume"].get<double>(), 1e-12);
  std::filesystem::remove_all(dir);
}

TEST(ClipCli, BadInputExitsTwoWithOneLine) {
  const auto dir = test::temp_dir("clip");
  const auto torus = test::source_dir() / "models/torus.off";
  for (const std::string& args :
       {"clip " + q(torus) + " --plane 0,0,0,1 -o " + q(dir / "a.off"),
        "clip " + q(torus) + " --plane 0,0,1 -o " + q(dir / "a.off"),
        "clip " + q(torus) + " --plane 0,0,x,1 -o " + q(dir / "a.off"),
        "clip " + q(dir / "missing.off") + " --plane 0,0,1,0 -o " + q(dir / "a.off"),
        "clip " + q(torus) + " --plane 0,0,1,0 -o " + q(dir / "a.xyz"),
        "clip " + q(torus) + " --plane 0,0,1,0 -o " + q(dir / "a.off") + " --below " +
            q(dir / "b.json")}) {
    const auto r = run_cover(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("cover: error: ", 0), 0u) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "a.off"));
  std::filesystem::remove_all(dir);
}

TEST(ClipCli, SceneWritesClippedLeavesOrTheEvaluatedMesh) {
  const auto dir = test::temp_dir("clip");
  test::write_file(dir / "scene.json", R"({"difference": [
      {"box": {"min": [0, 0, 0], "max": [4, 4, 4]}},
      {"sphere": {"center": [2, 2, 2], "radius": 1.5, "segments": 16}}]})");
  // A mesh output for an expression of several leaves: the evaluated result is clipped; its
  // halves add up to the evaluated volume and are closed.
  const auto meshes = run_cover("clip " + q(dir / "scene.json") + " --plane 0,0,1,2.25 -o " +
                                q(dir / "a.off") + " --below " + q(dir / "b.off") + " --json");
  ASSERT_EQ(meshes.status, 0) << meshes.err;
  const json jm = json::parse(meshes.out);
  const auto evaluated =
      run_cover("evaluate " + q(dir / "scene.json") + " -o " + q(dir / "e.off") + " --json");
  ASSERT_EQ(evaluated.status, 0) << evaluated.err;
  const double ve = json::parse(evaluated.out)["volume"].get<double>();
  EXPECT_TRUE(jm["above"]["closed"].get<bool>());
  EXPECT_TRUE(jm["below"]["closed"].get<bool>());
  EXPECT_NEAR(jm["above"]["volume"].get<double>() + jm["below"]["volume"].get<double>(), ve,
              1e-9 * ve);
  EXPECT_GT(jm["above"]["rings"].get<int>(), 1);  // the box's outline and the sphere's hole
  // .json outputs: the expression is kept over clipped leaves.
  const auto r = run_cover("clip " + q(dir / "scene.json") + " --plane 0,0,1,2 -o " +
                           q(dir / "above.json") + " --below " + q(dir / "below.json") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json scene = json::parse(test::read_file(dir / "above.json"));
  ASSERT_TRUE(scene.contains("difference"));
  EXPECT_EQ(scene["difference"].size(), 2u);
  // The clipped scenes' volumes add up to the original's (covering volume is exact here).
  double bound = 1e-9;  // plus each volume's own error bound (ray integration where not exact)
  auto volume = [&](const std::filesystem::path& p) {
    const auto v = run_cover("volume " + q(p) + " --json");
    EXPECT_EQ(v.status, 0) << v.err;
    const json j = json::parse(v.out);
    bound += j["error_bound"].get<double>();
    return j["volume"].get<double>();
  };
  const double sum = volume(dir / "above.json") + volume(dir / "below.json");
  EXPECT_NEAR(sum, volume(dir / "scene.json"), bound);
  // A single-leaf scene clips to a mesh.
  test::write_file(dir / "one.json", R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}})");
  const auto one = run_cover("clip " + q(dir / "one.json") + " --plane 1,1,1,1.5 -o " +
                             q(dir / "one.off") + " --json");
  ASSERT_EQ(one.status, 0) << one.err;
  EXPECT_NEAR(json::parse(one.out)["above"]["volume"].get<double>(), 0.5, 1e-15);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
