// Field leaves through the `cover` program (docs/cli.md "Field leaves and blends", `cover field`):
// the field query, classify's `uncertain`, the bracket volume, info, and one-line refusals naming
// the file and the leaf's JSON path for the commands that do not take field leaves.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

class FieldsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("fields_cli");
    scene_ = dir_ / "two.json";
    test::write_file(scene_, R"({"union": [{"blend": [
      {"field": {"skeleton": {"point": [-0.35, 0, 0]}, "radius": 0.5, "influence": 1}},
      {"field": {"skeleton": {"point": [0.35, 0, 0]}, "radius": 0.5, "influence": 1}}]},
      {"box": {"min": [2, 2, 2], "max": [3, 3, 3]}}]})");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_, scene_;
};

TEST_F(FieldsCli, FieldPrintsValueAndGradientPerPoint) {
  const auto r = run_cover("field " + q(scene_) + " --points -", "0.85 0 0\n0 0 0\n");
  ASSERT_EQ(r.status, 0) << r.err;
  // f(0.85, 0, 0) = (1 − 0.5²)² = 0.5625 exactly, ∇f = −4·0.75·(0.5, 0, 0)... = (−1.5, 0, 0).
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "0.5625 -1.5 0 0");
  const auto j = run_cover("field " + q(scene_) + " --points - --json", "0.85 0 0\n");
  ASSERT_EQ(j.status, 0) << j.err;
  const json out = json::parse(j.out);
  EXPECT_EQ(out["field"][0], 0.5625);
  EXPECT_EQ(out["leaves"][0], "/union/0/blend");
}

TEST_F(FieldsCli, ClassifyReportsFaceAndUncertain) {
  const auto r = run_cover("classify " + q(scene_) + " --points - --json", "0.85 0 0\n0 0 0\n");
  ASSERT_EQ(r.status, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["classes"][0], "face");
  EXPECT_EQ(out["classes"][1], "inside");
  EXPECT_EQ(out["uncertain"], 0);
}

TEST_F(FieldsCli, VolumeIsACertifiedBracket) {
  const auto r = run_cover("volume " + q(scene_) + " --json --tolerance 0.02");
  ASSERT_EQ(r.status, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["method"], "bracket");
  EXPECT_TRUE(out["target_met"].get<bool>());
  EXPECT_LE(out["error_bound"].get<double>(), 0.02 * out["volume"].get<double>());
  // --exact: no exact volume of a curved solid; the bracket, said on stderr, the same numbers.
  const auto e = run_cover("volume " + q(scene_) + " --exact --json --tolerance 0.02");
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_NE(e.err.find("note"), std::string::npos) << e.err;
  EXPECT_NE(e.err.find("bracket"), std::string::npos) << e.err;
  const json ex = json::parse(e.out);
  EXPECT_EQ(ex["method"], "bracket");
  EXPECT_EQ(ex["volume"], out["volume"]);
  EXPECT_EQ(ex["error_bound"], out["error_bound"]);
}

TEST_F(FieldsCli, InfoDescribesFieldLeaves) {
  const auto r = run_cover("info " + q(scene_) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json leaf = json::parse(r.out)["leaves_info"][0];
  EXPECT_EQ(leaf["kind"], "field");
  EXPECT_EQ(leaf["threshold"], 0.5625);
  EXPECT_EQ(leaf["primitives"].size(), 2u);
  EXPECT_EQ(leaf["primitives"][1]["skeleton"], "point");
}

TEST_F(FieldsCli, EvaluateAndClipMeshTheBlendFirst) {
  const auto r = run_cover("evaluate " + q(scene_) + " -o " + q(dir_ / "e.off") +
                           " --mesh-resolution 32 --mesh-tolerance 1e-7 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["meshed"].size(), 1u);
  EXPECT_EQ(j["meshed"][0]["name"], "/union/0/blend");
  EXPECT_LE(j["tolerance"].get<double>(), 1e-7);
  EXPECT_EQ(j["components"], 2);  // the blend and the box apart
  const auto info = run_cover("info " + q(dir_ / "e.off") + " --json");
  ASSERT_EQ(info.status, 0) << info.err;
  const json leaf = json::parse(info.out)["leaves_info"][0];
  EXPECT_TRUE(leaf["closed"].get<bool>());
  EXPECT_FALSE(leaf["self_intersecting"].get<bool>());
  const auto c = run_cover("clip " + q(scene_) + " --plane 0,0,1,0 -o " + q(dir_ / "c.off"));
  EXPECT_EQ(c.status, 0) << c.err;
  // The polygonizer itself, on the whole tree.
  const auto p =
      run_cover("polygonize " + q(scene_) + " -o " + q(dir_ / "p.ply") + " --resolution 20 --json");
  ASSERT_EQ(p.status, 0) << p.err;
  const json pj = json::parse(p.out);
  EXPECT_EQ(pj["cell_size"], 0.125);  // the largest power of two ≤ 2.7 / 20
  EXPECT_GT(pj["faces"].get<int>(), 100);
  const auto bad =
      run_cover("polygonize " + q(scene_) + " -o " + q(dir_ / "p.ply") + " --resolution 1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
}

TEST_F(FieldsCli, BadFieldNodeNamesTheFileAndPath) {
  const auto bad = dir_ / "bad.json";
  test::write_file(bad, R"({"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 1,
                            "influence": 1, "exponent": 1}})");
  const auto r = run_cover("classify " + q(bad) + " --points -", "0 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("cover: error: " + bad.string() + ": /field: ", 0), 0u) << r.err;
}

TEST_F(FieldsCli, OctreeOfTheBlend) {
  const auto r =
      run_cover("octree " + q(scene_) + " --depth 4 -o " + q(dir_ / "o.json") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "o.json"));
}

TEST_F(FieldsCli, RenderDrawsTheBlend) {
  const auto r = run_cover("render " + q(scene_) + " -o " + q(dir_ / "f.png") + " --size 48x32");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "f.png"));
}

TEST_F(FieldsCli, WarpsClassifyInfoAndEvaluate) {
  const std::filesystem::path taper = dir_ / "taper.json";
  test::write_file(taper, R"({"taper": {"axis": {"direction": [0, 1, 0]}, "range": [-0.5, 0.5],
    "scale": [1, 0.5], "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}})");
  // y = 0.25: s = 5/8, so (0.3125, 0.25, 0.3125) maps exactly onto the box's edge.
  const auto r = run_cover("classify " + q(taper) + " --points - --json",
                           "0.3125 0.25 0.3125\n0.3 0.25 0\n0.32 0.25 0\n");
  ASSERT_EQ(r.status, 0) << r.err;
  const json out = json::parse(r.out);
  EXPECT_EQ(out["classes"], json({"face", "inside", "outside"}));
  EXPECT_EQ(out["uncertain"], 0);
  const auto i = run_cover("info " + q(taper) + " --json");
  ASSERT_EQ(i.status, 0) << i.err;
  const json leaf = json::parse(i.out)["leaves_info"][0];
  EXPECT_EQ(leaf["kind"], "warp");
  EXPECT_EQ(leaf["warp"], "taper");
  EXPECT_EQ(leaf["child_leaves"], 1);
  const auto e = run_cover("evaluate " + q(taper) + " -o " + q(dir_ / "out.off") +
                           " --mesh-resolution 16 --json");
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_EQ(json::parse(e.out)["meshed"][0]["name"], "/taper");
  test::write_file(taper, R"({"taper": {"axis": {"direction": [0, 1, 0]}, "range": [1, 0],
    "scale": [1, 0.5], "child": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}}})");
  const auto bad = run_cover("classify " + q(taper) + " --points -", "0 0 0\n");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("taper.json: /taper: taper: range must be increasing"), std::string::npos)
      << bad.err;
}

}  // namespace
}  // namespace cover
