// Every command agrees with the others, end to end through the `cover` program, on inputs that
// are easy to answer wrongly: a flipped face, assimp exports, inconsistent leaves, a repeated
// loop, a thin union, the coordinate range, unbounded roots (tests/data/ holds the models, also
// fuzz seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string data(const std::string& name) {
  return "'" + (test::source_dir() / "tests" / "data" / name).string() + "'";
}

class CommandsAgree : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("agree"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string out(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  json run_json(const std::string& args) const {
    const auto r = run_cover(args + " --json");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? json::parse(r.out) : json::object();
  }
  /// volume, volume --exact, evaluate and voxel counting (res 64, within its voxel error).
  void expect_agreement(const std::string& input, double expected) const {
    const json v = run_json("volume " + input);
    EXPECT_NEAR(v["volume"].get<double>(), expected,
                v["error_bound"].get<double>() + 1e-12 * expected);
    const json x = run_json("volume --exact " + input);
    EXPECT_NEAR(x["volume"].get<double>(), expected, 1e-9 * expected);
    EXPECT_EQ(x["error_bound"].get<double>(), 0.0);
    const json e = run_json("evaluate " + input + " -o " + out("e.off"));
    EXPECT_NEAR(e["volume"].get<double>(), expected, 1e-9 * expected);
    const json g = run_json("voxelize " + input + " --res 64 -o " + out("v.npy"));
    EXPECT_NEAR(g["volume_estimate"].get<double>(), expected, 0.1 * expected);
  }
  std::filesystem::path dir_;
};

TEST_F(CommandsAgree, FlippedFaceCube) {
  const auto r = run_cover("volume " + data("flipped_face_cube.off"));
  EXPECT_NE(r.err.find("flipped_face_cube.off: faces not consistently oriented"), std::string::npos)
      << r.err;
  expect_agreement(data("flipped_face_cube.off"), 1.0);
  const json c = run_json("clip " + data("flipped_face_cube.off") + " --plane 0,0,1,0.5 -o " +
                          out("a.off") + " --below " + out("b.off"));
  EXPECT_NEAR(c["above"]["volume"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(c["below"]["volume"].get<double>(), 0.5, 1e-12);
}

TEST_F(CommandsAgree, AssimpBoxLongline) {
  const std::string box = "'" + (test::assimp_models() / "OBJ" / "box_longline.obj").string() + "'";
  expect_agreement(box, 1.0);
}

TEST_F(CommandsAgree, Assimp3DSMaxExport) {
  // 24 overlapping outward shells, two of them glued to others along rings that kept a cap disk
  // (edges of three faces): the caps are dropped, and the leaf evaluates as the union of shells.
  const std::string m = "'" + (test::assimp_models() / "STL" / "3DSMaxExport.STL").string() + "'";
  const json x = run_json("volume --exact " + m);
  EXPECT_EQ(x["method"], "brep");
  const double exact = x["volume"].get<double>();
  EXPECT_GT(exact, 900.0);
  const json v = run_json("volume " + m);
  EXPECT_NEAR(v["volume"].get<double>(), exact, v["error_bound"].get<double>() + 1e-12 * exact);
  const json r = run_json("volume --rays 256 " + m);  // the ray method's proven bound, independent
  EXPECT_EQ(r["method"], "rays");
  EXPECT_LE(std::abs(r["volume"].get<double>() - exact), r["error_bound"].get<double>());
  const json e = run_json("evaluate " + m + " -o " + out("e.off"));
  EXPECT_NEAR(e["volume"].get<double>(), exact, 1e-12 * exact);  // the rounded mesh's float sum
  const json g = run_json("voxelize " + m + " --res 256 -o " + out("v.npy"));
  EXPECT_NEAR(g["volume_estimate"].get<double>(), exact, 0.005 * exact);
}

TEST_F(CommandsAgree, InconsistentLeavesRepairedOrRefused) {
  // A tetrahedron with three of its four faces reversed: re-oriented.
  test::write_file(dir_ / "t.off",
                   "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                   "3 0 1 2\n3 0 1 3\n3 1 2 3\n3 0 2 3\n");
  expect_agreement(out("t.off"), 1.0 / 6);
  // A cube with its top face written twice: the extra copy is dropped (one membrane patch).
  test::write_file(dir_ / "d.off",
                   "OFF\n8 7 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n"
                   "0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n"
                   "4 3 0 4 7\n4 4 5 6 7\n");
  const auto d = run_cover("volume " + out("d.off"));
  EXPECT_NE(d.err.find("d.off: 1 face(s) spanning edges"), std::string::npos) << d.err;
  expect_agreement(out("d.off"), 1.0);
  // The 6-vertex real projective plane: closed, every edge two-sided, not orientable.
  test::write_file(dir_ / "rp2.off",
                   "OFF\n6 10 0\n0 0 1\n1 0 0\n0.3 1 0\n-0.8 0.6 0\n-0.8 -0.6 0\n0.3 -1 0\n"
                   "3 0 1 2\n3 0 2 3\n3 0 3 4\n3 0 4 5\n3 0 5 1\n"
                   "3 1 2 4\n3 2 3 5\n3 3 4 1\n3 4 5 2\n3 5 1 3\n");
  for (const std::string& cmd : std::vector<std::string>{"volume", "evaluate -o " + out("e.off"),
                                                         "voxelize --res 8 -o " + out("v.npy"),
                                                         "render -o " + out("r.png")}) {
    const auto r = run_cover(cmd + " " + out("rp2.off"));
    EXPECT_EQ(r.status, 2) << cmd;
    EXPECT_NE(r.err.find("rp2.off: non-orientable surface"), std::string::npos) << cmd << r.err;
  }
}

TEST_F(CommandsAgree, RepeatedLoopFace) {
  const auto r = run_cover("volume " + data("repeated_loop_cube.off"));
  EXPECT_NE(r.err.find("repeat one loop"), std::string::npos) << r.err;
  expect_agreement(data("repeated_loop_cube.off"), 1.0);
}

TEST_F(CommandsAgree, ThinUnionRayVolume) {
  // The default answer is exact (ray bound missed the target → B-rep); fixed grids tell the truth.
  const json v = run_json("volume " + data("thin_union.json"));
  EXPECT_NEAR(v["volume"].get<double>(), 1.5, v["error_bound"].get<double>() + 1e-12);
  for (const char* rays : {"1", "2", "16", "64", "256"}) {
    const json f = run_json("volume --rays " + std::string(rays) + " " + data("thin_union.json"));
    EXPECT_LE(std::abs(f["volume"].get<double>() - 1.5), f["error_bound"].get<double>()) << rays;
  }
}

TEST_F(CommandsAgree, CoordinateRange) {
  for (const char* cmd : {"volume", "render -o x.png", "evaluate -o x.off",
                          "voxelize --res 8 -o x.npy", "octree --depth 2 -o x.bt",
                          "classify --points /dev/null", "clip --plane 0,0,1,0 -o x.off"}) {
    const auto r = run_cover(std::string(cmd) + " " + data("huge_coordinates.off"));
    EXPECT_EQ(r.status, 2) << cmd;
    EXPECT_NE(r.err.find("huge_coordinates.off: vertex 0"), std::string::npos) << cmd << r.err;
  }
  test::write_file(dir_ / "s.json", R"({"sphere":{"center":[0,0,0],"radius":1e200}})");
  const auto s = run_cover("render -o " + out("s.png") + " " + out("s.json"));
  EXPECT_EQ(s.status, 2);
  EXPECT_NE(s.err.find("s.json: /sphere: vertex"), std::string::npos) << s.err;
  // Inside the range every command answers: a box at 2^62.
  const double big = std::ldexp(1.0, 62);
  test::write_file(dir_ / "b.json",
                   "{\"difference\":[{\"box\":{\"min\":[0,0,0],\"max\":[" + std::to_string(big) +
                       "," + std::to_string(big) + "," + std::to_string(big) +
                       "]}},{\"box\":{\"min\":[0,0,0],\"max\":[" + std::to_string(big / 2) + "," +
                       std::to_string(big / 2) + "," + std::to_string(big / 2) + "]}}]}");
  const double expected = 0.875 * big * big * big;
  const json x = run_json("volume --exact " + out("b.json"));
  EXPECT_NEAR(x["volume"].get<double>(), expected, 1e-12 * expected);
  const json v = run_json("volume " + out("b.json"));
  EXPECT_NEAR(v["volume"].get<double>(), expected,
              v["error_bound"].get<double>() + 1e-12 * expected);
  for (const char* cmd :
       {"render -o x.png", "voxelize --res 8 -o x.npy", "octree --depth 2 -o x.bt"}) {
    const auto r = run_cover(
        std::string(cmd).replace(std::string(cmd).find(" x."), 3, " " + (dir_ / "x.").string()) +
        " " + out("b.json"));
    EXPECT_EQ(r.status, 0) << cmd << r.err;
  }
}

TEST_F(CommandsAgree, UnboundedRoots) {
  for (const std::string& cmd : std::vector<std::string>{
           "volume", "evaluate -o " + out("c.off"), "clip --plane 0,0,1,0.5 -o " + out("c.off"),
           "voxelize --res 8 -o " + out("c.npy")}) {
    const auto r = run_cover(cmd + " " + data("complement_root.json"));
    EXPECT_EQ(r.status, 2) << cmd;
    EXPECT_NE(r.err.find("complement_root.json: the result is unbounded"), std::string::npos)
        << cmd << r.err;
  }
  const json v = run_json("volume " + data("double_complement.json"));
  EXPECT_NEAR(v["volume"].get<double>(), 1.0, v["error_bound"].get<double>() + 1e-12);
  const json e = run_json("evaluate " + data("double_complement.json") + " -o " + out("d.off"));
  EXPECT_NEAR(e["volume"].get<double>(), 1.0, 1e-12);
}

}  // namespace
}  // namespace cover
