// Open meshes end to end (docs/cli.md#semantics): every kernel command accepts the open
// assimp-testmodels samples and open libcgal-demo meshes (exit 0, one warning naming the file,
// its boundary edges and the rule); --closed-only refuses them (exit 2); evaluate and clip
// refuse them (exit 2, naming the file); info reports the repair and the rule.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

/// The 16 samples of assimp-testmodels that Cover refused as open before repair (cube_uv.ply is
/// closed once welded), and open libcgal-demo meshes.
std::vector<std::filesystem::path> open_inputs() {
  std::vector<std::filesystem::path> out;
  const std::string a = "/usr/share/assimp/models/";
  for (const char* m :
       {"OBJ/WusonOBJ.obj", "OBJ/concave_polygon.obj", "OBJ/multiple_spaces.obj", "OBJ/regr01.obj",
        "OBJ/space_in_material_name.obj", "OBJ/spider.obj", "OFF/Wuson.off", "PLY/cube_uv.ply",
        "PLY/float-color.ply", "STL/Spider_ascii.stl", "STL/Spider_binary.stl", "STL/Wuson.stl",
        "STL/sphereWithHole.stl", "STL/triangle.stl", "STL/triangle_with_empty_solid.stl",
        "STL/triangle_with_two_solids.stl"})
    out.push_back(a + m);
  for (const char* m : {"elephant-with-holes.off", "mushroom.off", "cube-ouvert.off", "holes.off"})
    out.push_back(test::cgal_mesh(m));
  return out;
}

class OpenMeshes : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("open"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(OpenMeshes, EveryCommandAcceptsThemAndClosedOnlyRefuses) {
  test::write_file(dir_ / "p.txt", "0 0 0\n1 1 1\n0.1 0.2 0.3\n");
  int tried = 0;
  for (const std::filesystem::path& in : open_inputs()) {
    if (!std::filesystem::exists(in)) continue;
    ++tried;
    const bool closes = in.filename() == "cube_uv.ply";  // closed once its seams are welded
    const std::vector<std::string> commands = {
        "classify " + q(in) + " --points " + q(dir_ / "p.txt"), "volume " + q(in) + " --rays 16",
        "voxelize " + q(in) + " --res 12 -o " + q(dir_ / "v.npy"),
        "render " + q(in) + " --size 40x30 -o " + q(dir_ / "r.png"),
        "octree " + q(in) + " --depth 3 -o " + q(dir_ / "o.json")};
    for (const std::string& c : commands) {
      const auto r = run_cover(c);
      EXPECT_EQ(r.status, 0) << c << "\n" << r.err;
      EXPECT_NE(r.err.find(in.string()), std::string::npos) << c;
      EXPECT_NE(r.err.find(closes ? "closed after repair" : "generalized winding number"),
                std::string::npos)
          << c << "\n"
          << r.err;
      // The warning names the flag that refuses the leaf (the library's require_closed).
      if (!closes) EXPECT_NE(r.err.find("(--closed-only refuses)"), std::string::npos) << r.err;
    }
    if (closes) continue;
    // --closed-only: today's refusal, naming the file and its boundary edges.
    const auto r = run_cover("volume --closed-only " + q(in));
    EXPECT_EQ(r.status, 2) << in;
    EXPECT_NE(r.err.find("boundary edges (a leaf must be a closed solid)"), std::string::npos);
    EXPECT_NE(r.err.find(in.string()), std::string::npos);
  }
  EXPECT_GE(tried, 4);
}

TEST_F(OpenMeshes, ClosedOnlyOnEveryCommandEvaluateMeshesTheLeaf) {
  const std::filesystem::path in = test::cgal_mesh("elephant-with-holes.off");
  test::write_file(dir_ / "p.txt", "0 0 0\n");
  for (const std::string& c :
       {"classify --closed-only " + q(in) + " --points " + q(dir_ / "p.txt"),
        "voxelize --closed-only " + q(in) + " --res 8 -o " + q(dir_ / "v.npy"),
        "render --closed-only " + q(in) + " --size 8x8 -o " + q(dir_ / "r.png"),
        "octree --closed-only " + q(in) + " --depth 2 -o " + q(dir_ / "o.json"),
        "evaluate --closed-only " + q(in) + " -o " + q(dir_ / "e.off"),
        "clip --closed-only " + q(in) + " --plane 0,0,1,0 -o " + q(dir_ / "c.off")}) {
    const auto r = run_cover(c);
    EXPECT_EQ(r.status, 2) << c;
    EXPECT_NE(r.err.find("open mesh"), std::string::npos) << c;
  }
  const auto v = run_cover("volume --exact " + q(in));
  EXPECT_EQ(v.status, 2);
  EXPECT_NE(v.err.find(in.string() + ": open mesh (1353 boundary edges)"), std::string::npos)
      << v.err;
  // evaluate meshes the open leaf's |w| > 1/2 set first (mixed evaluation).
  const auto e =
      run_cover("evaluate " + q(in) + " -o " + q(dir_ / "e.off") + " --mesh-resolution 24 --json");
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_EQ(json::parse(e.out)["meshed"].size(), 1u);
  EXPECT_GT(json::parse(e.out)["volume"].get<double>(), 0);
}

TEST_F(OpenMeshes, InfoReportsRepairAndRule) {
  const std::filesystem::path wuson = "/usr/share/assimp/models/OFF/Wuson.off";
  if (!std::filesystem::exists(wuson)) GTEST_SKIP() << "assimp-testmodels not installed";
  auto r = run_cover("info --json --no-self-intersection " + q(wuson));
  ASSERT_EQ(r.status, 0) << r.err;
  const json leaf = json::parse(r.out)["leaves_info"][0];
  EXPECT_EQ(leaf["boundary_edges"], 2338);           // as read
  EXPECT_EQ(leaf["repair"]["boundary_edges"], 412);  // once welded: as the STL version
  EXPECT_GT(leaf["repair"]["welded_vertices"].get<int>(), 0);
  EXPECT_EQ(leaf["rule"], "generalized winding number");
  EXPECT_GT(leaf["boundary_edge_fraction"].get<double>(), 0.0);
  r = run_cover("volume --rays 16 " + q(wuson));
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.err.find("duplicate vertices welded"), std::string::npos);
  EXPECT_NE(r.err.find("open mesh: 412 boundary edges"), std::string::npos);
}

}  // namespace
}  // namespace cover
