// What the CLI reports (docs/cli.md: timing keys, `cover volume --exact`): every
// command's --json output carries `seconds_detail` {load, kernel, write}, and `volume --exact`
// equals `evaluate`'s volume on nested scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <set>

#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

/// The path in single quotes, for run_cover's shell (built with += : GCC 12 warns falsely on
/// "'" + std::string + "'", bug 105329).
std::string q(const std::filesystem::path& p) {
  std::string quoted = "'";
  quoted += p.string();
  quoted += '\'';
  return quoted;
}

class CliReports : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::temp_dir("reports"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  json run_json(const std::string& args, const std::string& stdin_text = "") {
    const test::RunResult r = run_cover(args + " --json", stdin_text);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return r.status == 0 ? json::parse(r.out) : json::object();
  }

  std::filesystem::path scene(const std::string& name, const std::string& text) {
    const std::filesystem::path p = dir_ / name;
    test::write_file(p, text);
    return p;
  }

  std::filesystem::path dir_;
};

TEST_F(CliReports, SecondsDetailInEveryCommand) {
  const std::string in = q(scene("part.json", R"({"union": [
    {"difference": [{"box": {"min": [0,0,0], "max": [2,2,2]}},
                    {"sphere": {"center": [2,2,2], "radius": 1, "segments": 16}}]},
    {"box": {"min": [1.5,0.5,0.5], "max": [3.5,1,1]}}]})"));
  const std::string d = dir_.string() + "/";
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"info " + in, ""},
      {"volume " + in, ""},
      {"volume --exact " + in, ""},
      {"classify " + in + " --points -", "0.5 0.5 0.5\n3 0.75 0.75\n"},
      {"render " + in + " --size 64x48 -o " + q(d + "a.png"), ""},
      {"voxelize " + in + " --res 16 -o " + q(d + "a.npy"), ""},
      {"octree " + in + " --depth 3 -o " + q(d + "a.htg"), ""},
      {"clip " + in + " --plane 0,0,1,1 -o " + q(d + "top.off") + " --below " + q(d + "bottom.off"),
       ""},
      {"evaluate " + in + " -o " + q(d + "a.off"), ""},
  };
  for (const auto& [args, input] : commands) {
    const json j = run_json(args, input);
    ASSERT_TRUE(j.contains("seconds_detail")) << args;
    const json& s = j["seconds_detail"];
    double sum = 0;
    for (const char* key : {"load", "kernel", "write"}) {
      ASSERT_TRUE(s.contains(key) && s[key].is_number()) << args << " " << key;
      EXPECT_GE(s[key].get<double>(), 0) << args << " " << key;
      sum += s[key].get<double>();
    }
    ASSERT_TRUE(j["seconds"].is_number()) << args;
    EXPECT_LE(sum, j["seconds"].get<double>() + 1e-9) << args;
    EXPECT_GT(s["load"].get<double>(), 0) << args;  // the input is always read
  }
}

TEST_F(CliReports, VolumeExactEqualsEvaluateOnNestedScenes) {
  const std::vector<std::string> scenes = {
      // (A − B) ∪ C, the expression the paper's single threshold gets wrong
      R"({"union": [{"difference": [{"box": {"min": [0,0,0], "max": [2,2,2]}},
                                    {"sphere": {"center": [1,1,1], "radius": 0.8,
                                                "segments": 12}}]},
                    {"box": {"min": [0.5,0.5,0.5], "max": [1.5,1.5,2.5]}}]})",
      // intersection of unions, with a rotated operand
      R"({"intersection": [
          {"union": [{"box": {"min": [0,0,0], "max": [2,1,1]}},
                     {"box": {"min": [0,0,0], "max": [1,2,1]}}]},
          {"union": [{"sphere": {"center": [1,0.5,0.5], "radius": 0.9, "segments": 10}},
                     {"cylinder": {"base": [0,0,0.5], "top": [2,2,0.5], "radius": 0.4,
                                   "segments": 9},
                      "transform": {"rotate": {"axis": [0,0,1], "degrees": 7}}}]}]})",
      // a difference whose subtrahend is a complement (a double complement in effect)
      R"({"difference": [{"box": {"min": [0,0,0], "max": [3,3,3]}},
                         {"complement": {"sphere": {"center": [1.5,1.5,1.5], "radius": 1.4,
                                                    "segments": 14}}}]})",
      // a mesh leaf in a nested expression
      R"({"difference": [{"union": [{"mesh": )" + std::string("\"") +
          (test::source_dir() / "models" / "torus.off").string() + R"("},
                                    {"box": {"min": [-0.5,-0.5,-0.5], "max": [0.5,0.5,0.5]}}]},
                         {"box": {"min": [0,0,-2], "max": [3,3,2]}}]})",
  };
  for (size_t i = 0; i < scenes.size(); ++i) {
    const std::string in = q(scene("nested" + std::to_string(i) + ".json", scenes[i]));
    const json exact = run_json("volume --exact " + in);
    const json evaluated = run_json("evaluate " + in + " -o " + q(dir_ / "e.off"));
    ASSERT_TRUE(exact.contains("volume")) << i;
    EXPECT_EQ(exact["method"], "brep") << i;
    EXPECT_EQ(exact["error_bound"].get<double>(), 0) << i;
    EXPECT_GT(exact["volume"].get<double>(), 0) << i;
    // The exact result's volume against the written (rounded) mesh's, summed in doubles.
    EXPECT_NEAR(exact["volume"].get<double>(), evaluated["volume"].get<double>(),
                1e-12 * exact["volume"].get<double>())
        << i;
    EXPECT_EQ(exact["area"].get<double>(), evaluated["area"].get<double>()) << i;
    // The default (rays, or the B-rep where their bound misses) agrees within its bound.
    const json v = run_json("volume " + in);
    EXPECT_LE(std::abs(v["volume"].get<double>() - exact["volume"].get<double>()),
              v["error_bound"].get<double>() + 1e-12 * exact["volume"].get<double>())
        << i;
  }
}

TEST_F(CliReports, SeveralViewsFromOneLoadEqualSingleRenders) {
  const std::string in = q(test::source_dir() / "models" / "default.json");
  const std::string d = dir_.string() + "/";
  const json views = run_json("render " + in + " --size 96x64 --views iso,front,top -o " +
                              q(d + "v.png") + " --depth " + q(d + "d.png"));
  ASSERT_EQ(views["frames"].size(), 3u);
  EXPECT_EQ(views["rays"].get<size_t>(), 3u * 96 * 64 * 5);  // --samples 2: 2×2 + 1 a pixel
  for (const std::string view : {"iso", "front", "top"}) {
    run_json("render " + in + " --size 96x64 --view " + view + " -o " + q(d + "one.png") +
             " --depth " + q(d + "one_depth.png"));
    EXPECT_EQ(test::read_file(d + "v_" + view + ".png"), test::read_file(d + "one.png")) << view;
    EXPECT_EQ(test::read_file(d + "d_" + view + ".png"), test::read_file(d + "one_depth.png"))
        << view;
  }
  // Turntable frame k is the view turned by 360·k/N about the up axis, every frame with
  // one framing (the box seen from every azimuth), so its scale and depth range never change.
  const json turn = run_json("render " + in + " --size 96x64 --turntable 4 -o " + q(d + "t.png"));
  ASSERT_EQ(turn["frames"].size(), 4u);
  std::set<std::string> distinct;
  for (int k = 0; k < 4; ++k) {
    const std::string frame = d + "t_00" + std::to_string(k) + ".png";
    const json one = run_json("render " + in + " --size 96x64 --azimuth " + std::to_string(90 * k) +
                              " -o " + q(d + "one.png"));
    const json& cam = turn["frames"][k]["camera"];
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(cam["forward"][i].get<double>(), one["camera"]["forward"][i].get<double>(), 1e-15)
          << k;
      EXPECT_NEAR(cam["up"][i].get<double>(), one["camera"]["up"][i].get<double>(), 1e-15) << k;
    }
    EXPECT_EQ(cam["pixel_size"], turn["camera"]["pixel_size"]) << k;
    EXPECT_EQ(cam["depth_near"], turn["camera"]["depth_near"]) << k;
    EXPECT_EQ(cam["depth_far"], turn["camera"]["depth_far"]) << k;
    distinct.insert(test::read_file(frame));
  }
  EXPECT_EQ(distinct.size(), 4u);  // the scene is not symmetric under quarter turns
  // With --turntable 1 the one frame is that framing of the view itself.
  run_json("render " + in + " --size 96x64 --turntable 1 --azimuth 90 -o " + q(d + "t1.png"));
  EXPECT_EQ(test::read_file(d + "t1_000.png"), test::read_file(d + "t_001.png"));
  // Bad lists are one-line errors, and nothing is written.
  for (const std::string bad :
       {"--views iso,sideways", "--views iso,iso", "--views iso --turntable 2", "--turntable 0"}) {
    const test::RunResult r =
        run_cover("render " + in + " --size 8x8 " + bad + " -o " + q(d + "bad.png"));
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << r.err;
    EXPECT_FALSE(std::filesystem::exists(d + "bad_iso.png")) << bad;
  }
}

}  // namespace
}  // namespace cover
