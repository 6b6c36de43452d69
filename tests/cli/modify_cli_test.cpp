// `cover modify` / `cover pipe` / `cover extrude` end to end (docs/cli.md "Modeling"): results
// checked by independent paths — the written mesh's genus, components and counts by
// mesh/validate.h, exact volumes by `cover volume --exact` (an extrusion adds area × distance, a
// stellation a third of it), the modeled genus-3 part against its script's expected topology;
// bad scripts exit 2 with one line naming the script and the operation, and write nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::filesystem::path model(const std::string& name) {
  return test::source_dir() / "models" / name;
}

json run_json(const std::string& args) {
  const auto r = run_cover(args + " --json");
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r.status == 0 ? json::parse(r.out) : json::object();
}

double exact_volume(const std::filesystem::path& mesh) {
  const json j = run_json("volume --exact " + q(mesh));
  return j.contains("volume") ? j["volume"].get<double>() : -1;
}

TEST(ModifyCli, GenusThreePartIsAValidGenusThreeSurface) {
  const auto dir = test::temp_dir("modify");
  const auto out = dir / "g3.off";
  const json j = run_json("modify " + q(model("slab.off")) + " --ops " +
                          q(model("genus3_part.json")) + " -o " + q(out));
  EXPECT_EQ(j["operations"], 4);
  EXPECT_EQ(j["genus"], 3);
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["self_intersecting"], false);
  // Independently: the written mesh as cover info's validation sees it.
  const PolygonMesh m = read_mesh(out);
  const MeshReport r = validate_mesh(m, {});
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.genus, 3);
  EXPECT_EQ(r.components, 1);
  ASSERT_TRUE(r.self_intersecting.has_value());
  EXPECT_FALSE(*r.self_intersecting);
  EXPECT_EQ(j["vertices"].get<size_t>(), m.vertices.size());
  EXPECT_EQ(j["faces"].get<size_t>(), m.face_count());
  // Three pipes of 2 segments on quads: V + 3·4, F + 3·(4·2 − 2); then Catmull–Clark keeps
  // V − E + F = 2 − 2g = −4 at every level.
  EXPECT_EQ(
      static_cast<int64_t>(m.vertices.size()) - r.edges + static_cast<int64_t>(m.face_count()), -4);
  std::filesystem::remove_all(dir);
}

TEST(ModifyCli, ExtrusionAndStellationAddTheirExactVolumes) {
  const auto dir = test::temp_dir("modify");
  const double base = exact_volume(model("slab.off"));
  EXPECT_DOUBLE_EQ(base, 7 * 0.6);
  // The top face of cell 3 (area 1) moved up by 0.5: + 0.5; a cone of height 0.75 over it:
  // + 1/3 · 0.75 = 0.25.
  const auto ext = dir / "ext.off", cone = dir / "cone.ply";
  const json e = run_json("extrude " + q(model("slab.off")) +
                          " --near 3.5,0.5,0.6 --distance 0.5 -o " + q(ext));
  EXPECT_EQ(e["vertices"], 36);
  EXPECT_EQ(e["faces"], 34);
  EXPECT_EQ(e["genus"], 0);
  EXPECT_NEAR(exact_volume(ext), base + 0.5, 1e-12);
  run_json("extrude " + q(model("slab.off")) + " --face 12 --distance 0.75 --kind stellate -o " +
           q(cone));
  EXPECT_NEAR(exact_volume(cone), base + 0.25, 1e-12);
  std::filesystem::remove_all(dir);
}

TEST(ModifyCli, PipeRaisesTheGenusAndTheFlagsAgreeWithTheScript) {
  const auto dir = test::temp_dir("modify");
  const auto a = dir / "a.off", b = dir / "b.off", ops = dir / "ops.json";
  run_json("pipe " + q(model("torus.off")) + " --near 3,0,0,-3,0,0 --segments 3 -o " + q(a));
  std::ofstream(ops) << R"({"operations": [{"pipe": {"faces": [[3, 0, 0], [-3, 0, 0]],
                                                      "segments": 3}}]})";
  run_json("modify " + q(model("torus.off")) + " --ops " + q(ops) + " -o " + q(b));
  const PolygonMesh ma = read_mesh(a), mb = read_mesh(b);
  EXPECT_EQ(ma.vertices, mb.vertices);
  EXPECT_EQ(ma.face_vertices, mb.face_vertices);
  const MeshReport before = validate_mesh(read_mesh(model("torus.off")), {});
  const MeshReport after = validate_mesh(ma, {});
  EXPECT_EQ(after.genus, before.genus + 1);
  std::filesystem::remove_all(dir);
}

TEST(ModifyCli, CurvedHandleOverTheSlabIsEmbeddedAndMatchesTheScript) {
  const auto dir = test::temp_dir("modify");
  const auto a = dir / "a.off", b = dir / "b.off", ops = dir / "ops.json";
  // Two top cells of the slab (z = 0.6) joined by an arch: the centre on a Hermite curve
  // through a point above the slab's middle.
  const json p = run_json("pipe " + q(model("slab.off")) +
                          " --near 1.5,0.5,0.6 --near 5.5,0.5,0.6 --segments 12 --curved"
                          " --weights 1,1 --through 3.5,0.5,2.5 -o " +
                          q(a));
  EXPECT_EQ(p["genus"], 1);
  EXPECT_EQ(p["self_intersecting"], false);
  EXPECT_EQ(p["vertices"], 32 + 4 * 11);
  std::ofstream(ops) << R"([{"pipe": {"faces": [[1.5, 0.5, 0.6], [5.5, 0.5, 0.6]],
      "segments": 12, "curved": true, "path": [[3.5, 0.5, 2.5]]}}])";
  run_json("modify " + q(model("slab.off")) + " --ops " + q(ops) + " -o " + q(b));
  const PolygonMesh ma = read_mesh(a), mb = read_mesh(b);
  EXPECT_EQ(ma.vertices, mb.vertices);
  EXPECT_EQ(ma.face_vertices, mb.face_vertices);
  // The arch rises above the slab: its highest ring reaches the path point's height.
  double top = 0;
  for (const Vec3& v : ma.vertices) top = std::max(top, v.z);
  EXPECT_GT(top, 2.5);
  // Bad curve arguments: one line, exit 2, nothing written.
  for (const std::string& bad : {" --curved --weights 0,1", " --through 1,2"}) {
    const auto r = run_cover("pipe " + q(model("slab.off")) +
                             " --near 1.5,0.5,0.6 --near 5.5,0.5,0.6 --segments 4 -o " +
                             q(dir / "bad.off") + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.off"));
  }
  std::filesystem::remove_all(dir);
}

TEST(ModifyCli, MinimalOperatorsUndoneGiveTheInputBack) {
  const auto dir = test::temp_dir("modify");
  const auto out = dir / "out.off", mid = dir / "mid.off", ops = dir / "ops.json";
  // A point-sphere above the slab joined to the corner of its top face 0 at vertex 1 (a join:
  // the point-sphere's face merges into face 0), then undone in reverse.
  const std::string grow = R"({"create_vertex": {"point": [0.5, 0.5, 2]}},
      {"insert_edge": {"corners": [{"vertex": 32}, {"face": 0, "vertex": 1}]}})";
  std::ofstream(ops) << "[" << grow << "]";
  const json j = run_json("modify " + q(model("slab.off")) + " --ops " + q(ops) + " -o " + q(mid) +
                          " --no-self-intersection");
  EXPECT_EQ(j["vertices"], 33);
  EXPECT_EQ(j["edges"], 61);
  EXPECT_EQ(j["faces"], 30);  // the point-sphere's face merged into face 0
  EXPECT_EQ(j["genus"], 0);
  EXPECT_EQ(j["components"], 1);
  std::ofstream(ops) << "[" << grow << R"(, {"delete_edge": {"edge": 60}},
      {"delete_vertex": {"vertex": 32}}])";
  run_json("modify " + q(model("slab.off")) + " --ops " + q(ops) + " -o " + q(out));
  const PolygonMesh a = read_mesh(model("slab.off")), b = read_mesh(out);
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_EQ(a.face_start, b.face_start);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
  // A pipe turned by 90° on quads: one corner further than the closest pairing; still genus +1.
  const json p = run_json("pipe " + q(model("slab.off")) +
                          " --near 1.5,0.5,0.6 --near 5.5,0.5,0 --segments 3 --twist 90 -o " +
                          q(out) + " --no-self-intersection");
  EXPECT_EQ(p["genus"], 1);
  EXPECT_EQ(p["vertices"], 32 + 4 * 2);
  std::filesystem::remove_all(dir);
}

TEST(ModifyCli, BadScriptsAreOneLineErrorsAndWriteNothing) {
  const auto dir = test::temp_dir("modify");
  const auto out = dir / "out.off", ops = dir / "ops.json";
  const std::pair<const char*, const char*> cases[] = {
      {R"([{"pipe": {"faces": [0, 99]}}])", "ops.json: /0/pipe/faces/1: face 99 is not live"},
      {R"([{"twirl": {}}])", "ops.json: /0/twirl: unknown operation"},
      {R"({"operations": [{"extrude": {"face": 1, "distance": "x"}}]})",
       "ops.json: /operations/0/extrude/distance: expected a finite number"},
      {R"([{"extrude": {"face": 1, "distance": 1, "colour": 2}}])",
       "ops.json: /0/extrude: unknown key 'colour'"},
      {"not json", "ops.json: invalid JSON"},
      {R"([{"truncate": {"vertex": 0, "fraction": 2}}])", "ops.json: /0/truncate: "},
  };
  for (const auto& [text, message] : cases) {
    std::ofstream(ops) << text;
    const auto r =
        run_cover("modify " + q(model("slab.off")) + " --ops " + q(ops) + " -o " + q(out));
    EXPECT_EQ(r.status, 2) << text;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << text;
  }
  // An open input names the input file.
  const auto open = dir / "open.off";
  std::ofstream(open) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const auto r = run_cover("extrude " + q(open) + " --face 0 --distance 1 -o " + q(out));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("open.off: "), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
