// `cover classify --points FILE.npy` and `--output CLASSES.npy` end to end (docs/cli.md,
// `cover classify`): .npy points written by numpy (float64, float32, big-endian, Fortran
// order) classify exactly as the same points in text; the classes file reads back through
// numpy as uint8 codes of the words; malformed .npy files and other output names exit 2 with
// one line naming the file, leaving no output behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "helpers.h"

namespace cover {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::run_cover;

#ifdef COVER_SANITIZED
constexpr char kCapped[] = "";  // AddressSanitizer reserves more address space than any cap
#else
constexpr char kCapped[] = "ulimit -v 2097152; ";  // 2 GiB: no allocation the header asks for
#endif

std::string q(const fs::path& p) { return (std::string("'") += p.string()) += "'"; }
std::string python() { return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3"; }

/// Runs `python3 -c SCRIPT ARGS...`; returns its stdout (the test fails on a non-zero status).
std::string run_python(const fs::path& dir, const std::string& script, const std::string& args) {
  test::write_file(dir / "script.py", script);
  const std::string cmd =
      python() + " " + q(dir / "script.py") + " " + args + " >" + q(dir / "py.out");
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return test::read_file(dir / "py.out");
}

/// The box [0,2]^3 and 125 lattice points at steps of 0.5 from −0.5 (outside, vertex, edge,
/// face and inside all occur; every value is exact in float32), plus one far point.
class PointsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("points-cli");
    test::write_file(dir_ / "box.json", R"({"box": {"min": [0, 0, 0], "max": [2, 2, 2]}})");
    std::string text = "# x y z\n";
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        for (int k = 0; k < 5; ++k)
          text += std::to_string(-0.5 + 0.5 * i) + " " + std::to_string(-0.5 + 0.5 * j) + " " +
                  std::to_string(-0.5 + 0.5 * k) + "\n";
    text += "1e10 -3 7.25\n";
    test::write_file(dir_ / "p.txt", text);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string classify(const std::string& points, const std::string& extra = "") {
    const auto r = run_cover("classify " + q(dir_ / "box.json") + " --points " + q(points) + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    return r.out;
  }

  fs::path dir_;
};

TEST_F(PointsCli, NpyPointsClassifyAsTheSameTextPoints) {
  const std::string words = classify((dir_ / "p.txt").string());
  ASSERT_EQ(std::count(words.begin(), words.end(), '\n'), 126);
  for (const char* word : {"inside\n", "outside\n", "face\n", "edge\n", "vertex\n"})
    EXPECT_NE(words.find(word), std::string::npos) << word;
  // numpy writes each variant (version 1.0 headers; '>f8' big-endian; asfortranarray: F order).
  run_python(dir_, R"(
import sys
import numpy as np
p = np.loadtxt(sys.argv[1], ndmin=2)
out = sys.argv[2]
np.save(out + "/f8.npy", p)
np.save(out + "/f4.npy", p.astype(np.float32))
np.save(out + "/be.npy", p.astype(">f8"))
np.save(out + "/be4.npy", p.astype(">f4"))
np.save(out + "/fortran.npy", np.asfortranarray(p))
np.lib.format.write_array(open(out + "/v2.npy", "wb"), p, version=(2, 0))
np.lib.format.write_array(open(out + "/v3.npy", "wb"), p, version=(3, 0))
)",
             q(dir_ / "p.txt") + " " + q(dir_));
  for (const char* name :
       {"f8.npy", "f4.npy", "be.npy", "be4.npy", "fortran.npy", "v2.npy", "v3.npy"})
    EXPECT_EQ(classify((dir_ / name).string()), words) << name;
  // From stdin, recognised by its magic.
  const auto r = run_cover("classify " + q(dir_ / "box.json") + " --points -",
                           test::read_file(dir_ / "f4.npy"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, words);
}

TEST_F(PointsCli, OutputWritesUint8CodesThatNumpyReads) {
  const std::string words = classify((dir_ / "p.txt").string());
  const fs::path out = dir_ / "classes.npy";
  const auto r = run_cover("classify " + q(dir_ / "box.json") + " --points " + q(dir_ / "p.txt") +
                           " --output " + q(out));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind(out.string() + ": 126 points (outside ", 0), 0u) << r.out;
  // numpy prints the names of the codes (CLASS_NAMES order), one per line, like the words.
  const std::string names = run_python(dir_, R"(
import sys
import numpy as np
c = np.load(sys.argv[1])
assert c.dtype == np.uint8 and c.shape == (126,) and c.flags.c_contiguous, (c.dtype, c.shape)
names = ("outside", "inside", "face", "edge", "vertex")
sys.stdout.write("".join(names[k] + "\n" for k in c))
)",
                                       q(out));
  EXPECT_EQ(names, words);
  // --json: counts and seconds, no classes array; an empty points file gives shape (0,).
  const json j = json::parse(classify((dir_ / "p.txt").string(), " --json --output " + q(out)));
  EXPECT_FALSE(j.contains("classes"));
  EXPECT_TRUE(j.contains("seconds"));
  size_t total = 0;
  for (const auto& [name, n] : j["counts"].items()) total += n.get<size_t>();
  EXPECT_EQ(total, 126u);
  test::write_file(dir_ / "empty.txt", "# nothing\n");
  classify((dir_ / "empty.txt").string(), " --output " + q(out));
  EXPECT_EQ(run_python(dir_, "import sys, numpy as np; print(np.load(sys.argv[1]).shape)", q(out)),
            "(0,)\n");
}

TEST_F(PointsCli, OutputOtherThanNpyOrUnwritableExitsTwo) {
  for (const char* name : {"classes.txt", "classes", "classes.npz"}) {
    const auto r = run_cover("classify " + q(dir_ / "missing.json") + " --points " +
                             q(dir_ / "p.txt") + " --output " + q(dir_ / name));
    EXPECT_EQ(r.status, 2) << name;
    EXPECT_EQ(r.err, "cover: error: " + (dir_ / name).string() + ": unsupported classes format '" +
                         fs::path(name).extension().string() + "' (expected .npy)\n");
    EXPECT_FALSE(fs::exists(dir_ / name));
  }
  const fs::path missing = dir_ / "missing" / "classes.npy";
  const auto r = run_cover("classify " + q(dir_ / "box.json") + " --points " + q(dir_ / "p.txt") +
                           " --output " + q(missing));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("cover: error: " + missing.string() + ": cannot write", 0), 0u) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(PointsCli, MalformedNpyExitsTwoWithOneLineAndWritesNothing) {
  const std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
  auto npy = [](const std::string& dict, const std::string& data) {
    std::string h = dict + std::string(118 - dict.size(), ' ') + "\n";
    return std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(h.size()) + '\0' + h + data;
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"magic.npy", "x y z\n"},
      {"truncated.npy", npy(header, std::string(47, '\0'))},
      {"long.npy", npy(header, std::string(49, '\0'))},
      {"header.npy", npy(header, "").substr(0, 50)},
      {"lies.npy",
       npy("{'descr': '<f8', 'fortran_order': False, 'shape': (4611686018427387904, 3), }", "")},
      {"dtype.npy",
       npy("{'descr': '<i4', 'fortran_order': False, 'shape': (2, 3), }", std::string(24, '\0'))},
      {"shape.npy",
       npy("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }", std::string(48, '\0'))},
      {"version.npy",
       std::string("\x93NUMPY\x09\x00", 8) + npy(header, std::string(48, '\0')).substr(8)},
      {"nan.npy",
       npy(header, std::string(40, '\0') + std::string("\x00\x00\x00\x00\x00\x00\xf8\x7f", 8))},
      {"range.npy",
       npy(header, std::string(40, '\0') + std::string("\x00\x00\x00\x00\x00\x00\x00\x44", 8))},
  };
  for (const auto& [name, bytes] : cases) {
    test::write_file(dir_ / name, bytes);
    const auto r = run_cover("classify " + q(dir_ / "box.json") + " --points " + q(dir_ / name) +
                                 " --output " + q(dir_ / "out.npy"),
                             "", kCapped);
    EXPECT_EQ(r.status, 2) << name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("cover: error: " + (dir_ / name).string() + ": ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "out.npy")) << name;
  }
}

}  // namespace
}  // namespace cover
