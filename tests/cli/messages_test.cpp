// The `cover` program's messages and small input rules, end to end: one-line errors naming the
// file and place, option messages, warnings, byte-order marks, number rules, output failures.
// Inputs that reproduce a case live in tests/data/ (and tests/data/fuzz/ as fuzz seeds).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::filesystem::path data_file(const std::string& name) {
  return test::source_dir() / "tests" / "data" / name;
}

/// Exit status 2 and exactly "cover: error: <message>\n" on stderr.
void expect_error(const test::RunResult& r, const std::string& message) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "cover: error: " + message + "\n");
}

/// Exit status 2 and one line "cover: error: ..." on stderr containing every fragment.
void expect_error_with(const test::RunResult& r, const std::vector<std::string>& fragments) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err.rfind("cover: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const std::string& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << r.err;
}

class CliMessages : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("small");
    test::write_file(dir_ / "box.json", R"({"box": {"min": [0,0,0], "max": [1,1,1]}})");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string box() const { return q(dir_ / "box.json"); }
  std::filesystem::path dir_;
};

TEST_F(CliMessages, RenderRefusesUnknownExtension) {
  // PNG bytes are written only to a .png name.
  for (const std::string name : {"pic.jpg", "pic"}) {
    const auto r = run_cover("render " + box() + " --size 16x12 -o " + q(dir_ / name));
    expect_error_with(r,
                      {(dir_ / name).string() + ": unsupported image format", "(expected .png)"});
    EXPECT_FALSE(std::filesystem::exists(dir_ / name)) << name;
  }
  auto r = run_cover("render " + box() + " --size 16x12 -o " + q(dir_ / "a.png") + " --depth " +
                     q(dir_ / "d.tif"));
  expect_error_with(r, {"d.tif: unsupported image format '.tif'"});
  EXPECT_FALSE(std::filesystem::exists(dir_ / "a.png"));  // refused before any work
  r = run_cover("render " + box() + " --size 16x12 -o " + q(dir_ / "A.PNG"));
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(CliMessages, DuplicateJsonKey) {
  // nlohmann kept the last "min" silently.
  const auto file = data_file("duplicate_key.json");
  expect_error(run_cover("info " + q(file)), file.string() + ": /union/0/box: duplicate key 'min'");
}

TEST_F(CliMessages, PointsDirectory) {
  // A folder given to --points exited 0 with no output.
  std::filesystem::create_directories(dir_ / "pts");
  const auto r = run_cover("classify " + box() + " --points " + q(dir_ / "pts"));
  expect_error_with(r, {(dir_ / "pts").string() + ": "});
  EXPECT_EQ(r.out, "");
}

TEST_F(CliMessages, ClassifyStdinEqualsFile) {
  // `--points -` reads the same text as a file, through the same parallel parser (its speed
  // against the file's is measured by bench/parse_points.cpp, not here).
  std::string points;
  for (int i = 0; i < 250000; ++i)
    points += std::to_string(10 + i % 7 * 0.25) + " " + std::to_string(i % 11 * 0.125) + ", " +
              std::to_string(i % 13 * 0.1) + "\n";
  points += "0.5 0.5 0.5\n";
  test::write_file(dir_ / "p.txt", points);
  auto r = run_cover("classify --json " + box() + " --points " + q(dir_ / "p.txt"));
  ASSERT_EQ(r.status, 0) << r.err;
  const json from_file = json::parse(r.out)["counts"];
  r = run_cover("classify --json " + box() + " --points -", points);
  ASSERT_EQ(r.status, 0) << r.err;
  const json from_stdin = json::parse(r.out)["counts"];
  EXPECT_EQ(from_stdin, from_file);
  EXPECT_EQ(from_file["inside"].get<int>(), 1);
  EXPECT_EQ(from_file["outside"].get<int>(), 250000);
}

TEST_F(CliMessages, BomInPointsFilesAndScenes) {
  // A UTF-8 byte order mark was refused in points files (OFF, OBJ and JSON accepted it).
  auto r = run_cover("classify " + q(data_file("bom_ascii.stl")) + " --points " +
                     q(data_file("bom_points.txt")));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "inside\noutside\n");
  r = run_cover("classify " + box() + " --points -", std::string("\xEF\xBB\xBF") + "0.5 0.5 0.5\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "inside\n");
  test::write_file(dir_ / "bom.json", "\xEF\xBB\xBF" + test::read_file(dir_ / "box.json"));
  EXPECT_EQ(run_cover("info " + q(dir_ / "bom.json")).status, 0);
  EXPECT_EQ(run_cover("info " + q(data_file("bom_ascii.ply"))).status, 0);
}

TEST_F(CliMessages, BinaryStlTrailingBytesWarnOnStderr) {
  // Refused before; the other readers' way is to go on with a warning.
  const auto file = data_file("trailing_bytes.stl");
  const auto r = run_cover("volume " + q(file));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("volume 0.1666666"), std::string::npos) << r.out;
  EXPECT_EQ(r.err, "cover: warning: " + file.string() +
                       ": 7 trailing bytes after the last triangle ignored\n");
  test::write_file(dir_ / "s.json", R"({"mesh": ")" + file.string() + R"("})");
  EXPECT_NE(run_cover("info " + q(dir_ / "s.json")).err.find("7 trailing bytes"),
            std::string::npos);
}

TEST_F(CliMessages, NumberRuleSameInPointsAndScenes) {
  // Points refused '+1' and called 1e400 "not a number"; scenes reported 1e400 as invalid JSON
  // on line 1. Now: '+' accepted, underflow is 0, overflow is "out-of-range" with the place.
  auto r = run_cover("classify " + box() + " --points -", "+0.5 +5e-1 0.5\n1e-400 0.5 0.5\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "inside\nface\n");
  expect_error(run_cover("classify " + box() + " --points -", "0 0 0\n0.5 1e400 0\n"),
               "<stdin>:2: out-of-range y coordinate '1e400'");
  expect_error(run_cover("classify " + box() + " --points -", "0 0 nan\n"),
               "<stdin>:1: non-finite z coordinate 'nan'");
  test::write_file(dir_ / "big.json", "{\"box\": {\"min\": [0,0,0],\n \"max\": [1e400,1,1]}}");
  expect_error(run_cover("info " + q(dir_ / "big.json")),
               (dir_ / "big.json").string() + ": /box/max/0: out-of-range number '1e400'");
}

TEST_F(CliMessages, ErrorsNameTheFile) {
  test::write_file(dir_ / "comp.json",
                   R"({"complement": {"box": {"min": [0,0,0], "max": [1,1,1]}}})");
  const std::string comp = (dir_ / "comp.json").string();
  expect_error_with(run_cover("volume " + q(comp)), {comp + ": the result is unbounded"});
  // clip: an unbounded solid is refused, not clipped as if it were its leaf.
  expect_error_with(run_cover("clip " + q(comp) + " --plane 0,0,1,0.5 -o " + q(dir_ / "a.off")),
                    {comp + ": the result is unbounded"});
  test::write_file(dir_ / "cut.json",
                   R"({"intersection": [{"box": {"min": [0,0,0], "max": [2,2,2]}},
      {"complement": {"box": {"min": [0,0,0], "max": [1,1,1]}}}]})");
  const auto r =
      run_cover("clip " + q(dir_ / "cut.json") + " --plane 0,0,1,0.5 -o " + q(dir_ / "a.json"));
  expect_error_with(r, {(dir_ / "cut.json").string() + ": a scene with a complement cannot be "
                                                       "clipped leaf by leaf"});
  EXPECT_FALSE(std::filesystem::exists(dir_ / "a.leaf0.off"));  // refused before writing
  // Two cubes of one mesh sharing an edge (a valid solid the half-edge kernel cannot hold):
  // the kernel's message, after the file.
  test::write_file(dir_ / "flip.off",
                   "OFF\n14 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                   "2 1 0\n2 2 0\n1 2 0\n2 1 1\n2 2 1\n1 2 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n"
                   "4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n4 2 10 9 8\n4 6 11 12 13\n4 2 8 11 6\n"
                   "4 8 9 12 11\n4 9 10 13 12\n4 10 2 6 13\n");
  const std::string flip = (dir_ / "flip.off").string();
  expect_error_with(run_cover("clip " + q(flip) + " --plane 0,0,1,0.5 -o " + q(dir_ / "a.off")),
                    {flip + ": edge ", "used twice"});
  test::write_file(dir_ / "flip.json", R"({"union": [{"mesh": "flip.off"}]})");
  expect_error_with(
      run_cover("clip " + q(dir_ / "flip.json") + " --plane 0,0,1,0.5 -o " + q(dir_ / "b.json")),
      {(dir_ / "flip.json").string() + ": /union/0/mesh: edge "});
  expect_error(run_cover("clip " + q(flip) + " --plane 0,0,1,nan -o " + q(dir_ / "a.off")),
               "--plane: expected 4 numbers, got '0,0,1,nan'");
  // Scene leaves and the scene file itself.
  const auto missing = data_file("missing_mesh.json");
  expect_error(run_cover("info " + q(missing)),
               missing.string() + ": /union/1/mesh: " + data_file("nothere.off").string() +
                   ": cannot open: No such file or directory");
  const auto empty = data_file("empty_mesh_path.json");
  expect_error(run_cover("info " + q(empty)),
               empty.string() + ": /mesh: expected a non-empty file path");
  std::filesystem::create_directories(dir_ / "x.json");
  const auto r2 = run_cover("info " + q(dir_ / "x.json"));
  expect_error_with(r2, {(dir_ / "x.json").string() + ": "});
  EXPECT_EQ(r2.err.find("invalid JSON"), std::string::npos) << r2.err;
}

TEST_F(CliMessages, OptionMessages) {
  // CLI11's own: a 300-digit range, "Value abc not in range", "A subcommand is required".
  expect_error(run_cover("volume --rays 0 " + box()),
               "--rays: expected a whole number from 1 to 2048, got '0'");
  expect_error(run_cover("voxelize " + box() + " --res abc -o " + q(dir_ / "v.npy")),
               "--res: expected a whole number from 1 to 16384, got 'abc'");
  expect_error(run_cover("voxelize " + box() + " --res 10 --max-memory -1 -o " + q(dir_ / "v.npy")),
               "--max-memory: expected a positive whole number, got '-1'");
  expect_error(run_cover("octree " + box() + " --depth 2.5 -o " + q(dir_ / "o.bt")),
               "--depth: expected a whole number from 0 to 16, got '2.5'");
  expect_error(run_cover("octree " + box() + " --depth 2 --threshold x -o " + q(dir_ / "o.bt")),
               "--threshold: expected a number from 0 to 1, got 'x'");
  expect_error(run_cover("info --threads 0 " + box()),
               "--threads: expected a whole number from 1 to 4096, got '0'");
  const std::string commands =
      "info, volume, classify, distance, field, render, view, voxelize, octree, clip, evaluate, "
      "polygonize, decompose, subdivide, modify, pipe, extrude";
  expect_error(run_cover("bogus"), "unknown command 'bogus' (expected " + commands + ")");
  expect_error(run_cover(""), "no command given (expected " + commands + "; try --help)");
  // Whole numbers are decimal: a leading zero is not octal, and '+' is allowed.
  const auto r = run_cover("voxelize " + box() + " --res +010 -o " + q(dir_ / "v.npy") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(json::parse(r.out)["res"], 10);
}

TEST_F(CliMessages, OctreeTouchingCellsEmpty) {
  // Cells beside a box face are empty or full where they touch it, not partial (occupancy 0
  // or 1) down to the maximum depth.
  const auto r = run_cover("octree " + box() + " --depth 4 --bounds -1,-1,-1,4 --json -o " +
                           q(dir_ / "o.json"));
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  // The box is exactly the depth-2 cell [0, 1]³: one full leaf, and its 7 siblings and the
  // root's 7 other children, which only touch the box, are empty leaves.
  EXPECT_EQ(j["leaves"], json({{"full", 1}, {"empty", 14}, {"partial", 0}}));
  EXPECT_EQ(j["nodes"], 17);
}

TEST_F(CliMessages, OpenMeshRefusedOnceWithoutAWarningFirst) {
  // volume --exact needs closed leaves, and --closed-only refuses open leaves everywhere: one
  // error line naming the file once, no open-mesh warning printed just before the refusal.
  test::write_file(dir_ / "open.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n");
  const std::string in = q(dir_ / "open.off"), name = (dir_ / "open.off").string();
  const std::string refused = name + ": open mesh (3 boundary edges): ";
  const std::string closed_only =
      name + ": open mesh: 3 boundary edges (a leaf must be a closed solid)";
  expect_error(run_cover("clip --closed-only " + in + " --plane 0,0,1,0.5 -o " + q(dir_ / "a.off")),
               closed_only);
  expect_error(run_cover("evaluate --closed-only " + in + " -o " + q(dir_ / "e.off")), closed_only);
  expect_error(
      run_cover("evaluate --closed-only " + in + " -o " + q(dir_ / "e.off") + " --cells 2"),
      closed_only);
  expect_error(run_cover("decompose --closed-only " + in + " -o " + q(dir_ / "d")), closed_only);
  expect_error(run_cover("volume --exact " + in),
               refused + "no exact volume; the winding method estimates it (without --exact)");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "d"));
}

TEST_F(CliMessages, LeafIdsHelpNamesTheObjGroupsWritten) {
  const auto help = run_cover("evaluate --help");
  EXPECT_NE(help.out.find("OBJ groups 'g leaf_<i>'"), std::string::npos) << help.out;
  EXPECT_EQ(help.out.find("leaf_<i>_<name>"), std::string::npos) << help.out;
  ASSERT_EQ(run_cover("evaluate " + box() + " --leaf-ids -o " + q(dir_ / "e.obj")).status, 0);
  EXPECT_NE(test::read_file(dir_ / "e.obj").find("\ng leaf_0\n"), std::string::npos);
}

TEST_F(CliMessages, CellsMemoryRefusalReadsAsASentence) {
  expect_error_with(
      run_cover("evaluate " + box() + " -o " + q(dir_ / "e.off") + " --cells 100 --max-memory 1"),
      {"--cells 100: cutting into cells needs ", " MiB, over --max-memory 1 MiB"});
}

TEST_F(CliMessages, VoxelSizeTooSmallShowsItsValue) {
  expect_error(run_cover("voxelize " + box() + " --voxel-size 1e-10 -o " + q(dir_ / "v.npy")),
               "--voxel-size: 1e-10 gives more than 16384 voxels on an axis");
}

TEST_F(CliMessages, EmptyPathOrListValueIsAnError) {
  const std::string e = "evaluate " + box() + " -o " + q(dir_ / "e.off");
  expect_error(run_cover(e + " --cells 2 --pieces ''"), "--pieces: expected a folder, got ''");
  expect_error(run_cover("render " + box() + " -o " + q(dir_ / "r.png") + " --views ''"),
               "--views: expected views, e.g. iso,front,top, got ''");
  expect_error(run_cover("decompose " + box() + " -o ''"), "--output: expected a folder, got ''");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "e.off"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "r.png"));
}

TEST_F(CliMessages, BoundsBeyondTheCoordinateRangeRefused) {
  // size 1e308 would overflow the cells' corners; the cube must stay within ±2^64.
  const std::string message =
      "--bounds: the cube reaches beyond the supported coordinate range ±2^64 (about ±1.8e19) on x";
  expect_error(
      run_cover("voxelize " + box() + " --res 8 --bounds 0,0,0,1e308 -o " + q(dir_ / "v.npy")),
      message);
  expect_error(
      run_cover("octree " + box() + " --depth 2 --bounds 0,0,0,1e308 -o " + q(dir_ / "o.json")),
      message);
  expect_error(run_cover("evaluate " + box() + " -o " + q(dir_ / "e.off") +
                         " --cells 2 --bounds 0,0,0,1e308"),
               message);
  expect_error(
      run_cover("voxelize " + box() + " --res 8 --bounds -2e19,0,0,1 -o " + q(dir_ / "v.npy")),
      message);
  // Up to the range itself is accepted.
  EXPECT_EQ(run_cover("voxelize " + box() + " --res 8 --bounds 0,0,0,1e19 -o " + q(dir_ / "v.npy"))
                .status,
            0);
}

TEST_F(CliMessages, PngWriteFailureGivesTheReason) {
  expect_error(
      run_cover("render " + box() + " --size 8x8 -o " + q(dir_ / "missing" / "r.png")),
      (dir_ / "missing" / "r.png").string() + ": cannot write PNG (No such file or directory)");
}

}  // namespace
}  // namespace cover
