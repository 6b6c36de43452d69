// cli/points.h: text points parsed in parallel chunks give the points and the error lines of a
// plain line-by-line reading, for any thread count; .npy points (every supported dtype, byte
// order, layout and format version) equal the same points as text; malformed .npy data is
// refused with one line naming the file, before any allocation the header asks for.
#include "cover/cli/points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "helpers.h"

namespace cover {
namespace {

using cli::parse_npy_points;
using cli::parse_points;

/// The InputError message of f(), or "" when it does not throw.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// `n` seeded random points with a few magnitudes.
std::vector<Vec3> random_points(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> p(n);
  for (size_t i = 0; i < n; ++i) {
    const double scale = i % 7 == 0 ? 1e-300 : i % 5 == 0 ? 1e15 : 10;
    p[i] = {scale * u(rng), scale * u(rng), scale * u(rng)};
  }
  return p;
}

std::string number(double v) {
  char s[40];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

/// Text of `points` in varied spellings: commas, tabs, comments, blank and comment-only lines,
/// CRLF on some lines, a leading '+'.
std::string varied_text(const std::vector<Vec3>& points) {
  std::string t;
  for (size_t i = 0; i < points.size(); ++i) {
    if (i % 11 == 0) t += "# comment line " + std::to_string(i) + "\n";
    if (i % 13 == 0) t += "\n   \t\n";
    const char* sep = i % 3 == 0 ? ", " : i % 3 == 1 ? "\t" : " ";
    if (i % 17 == 0 && points[i].x >= 0) t += '+';
    for (int a = 0; a < 3; ++a) (t += number(points[i][a])) += a < 2 ? sep : "";
    t += i % 4 == 0 ? "  # trailing\r\n" : i % 4 == 1 ? "\r\n" : "\n";
  }
  return t;
}

TEST(Points, ParallelTextEqualsThePointsWrittenForEveryThreadCount) {
  const std::vector<Vec3> expected = random_points(120000, 7);  // ~60 chunks of text
  std::string text = varied_text(expected);
  ASSERT_EQ(text.back(), '\n');
  const std::string unterminated = text.substr(0, text.size() - 1);
  for (const std::string& variant :
       {text, "\xEF\xBB\xBF" + text, unterminated, unterminated + "\r"}) {
    for (int threads : {1, 2, 3}) {
      ThreadLimit limit(threads);
      EXPECT_EQ(parse_points(variant, "p.txt"), expected) << threads << " threads";
    }
  }
}

TEST(Points, PlainLinesReadAsTheGeneralLineRuleReadsThem) {
  // Each line alone takes the direct path where it can; with a trailing comment (or a leading
  // '+') it takes the general one. Both give the same points, or the same message.
  const std::vector<std::string> lines = {"1 2 3",     ".5 5. -0",   "1e-400 -1e-320 4E+2",
                                          ",1,,2\t3,", "1\v2\f3 \r", "0x10 1 2",
                                          "1e5x 2 3",  "nan 1 2",    "1 inf 2",
                                          "1 2 1e400", "1 2 1e20",   "1 2",
                                          "1 2 3 4",   "- 1 2",      "1 2 3.0.0"};
  for (const std::string& line : lines) {
    const std::string plain = error_of([&] { parse_points(line + "\n", "p.txt"); });
    EXPECT_EQ(plain, error_of([&] { parse_points(line + " # c\n", "p.txt"); })) << line;
    if (!plain.empty()) continue;
    EXPECT_EQ(parse_points(line + "\n", "p.txt"), parse_points(line + "#\n", "p.txt")) << line;
    if (line[0] != ',') {
      EXPECT_EQ(parse_points(line, "p.txt"), parse_points("+" + line, "p.txt")) << line;
    }
  }
  EXPECT_EQ(parse_points("1e-400 -1e-320 4E+2\n", "p.txt"),
            (std::vector<Vec3>{{0.0, -1e-320, 400}}));
  EXPECT_EQ(error_of([] { parse_points("1e5x 2 3\n", "p.txt"); }),
            "p.txt:1: expected a number for the x coordinate, found '1e5x'");
}

TEST(Points, SmallAndEmptyTexts) {
  EXPECT_TRUE(parse_points("", "p.txt").empty());
  EXPECT_TRUE(parse_points("\xEF\xBB\xBF", "p.txt").empty());
  EXPECT_TRUE(parse_points("# only a comment", "p.txt").empty());
  EXPECT_EQ(parse_points("1 2 3", "p.txt"), (std::vector<Vec3>{{1, 2, 3}}));
  EXPECT_EQ(parse_points("1,2,3\r\n\r\n4 5 6 # x\n", "p.txt"),
            (std::vector<Vec3>{{1, 2, 3}, {4, 5, 6}}));
}

/// Lines of exactly 32 bytes ("%10d %10d %9d\n"), so that line L starts at byte 32·(L−1) and a
/// bad line can be placed next to a chunk boundary.
std::string fixed_width_lines(size_t lines) {
  std::string t;
  char line[40];
  for (size_t i = 0; i < lines; ++i) {
    std::snprintf(line, sizeof line, "%10zu %10zu %9zu\n", i, i + 1, i + 2);
    t += line;
  }
  return t;
}

/// `text` with line `n` (1-based, 32 bytes) replaced by a bad line of the same width.
std::string with_bad_line(std::string text, size_t n, const char* bad) {
  char line[40];
  std::snprintf(line, sizeof line, "%-31s\n", bad);
  text.replace(32 * (n - 1), 32, line);
  return text;
}

TEST(Points, ErrorsNameTheFirstBadLineInFileOrder) {
  const size_t lines = 40000;  // 1.28 MB: five chunks of 2^18 bytes and a bit
  const std::string text = fixed_width_lines(lines);
  // Chunk boundaries fall after the line holding byte 2^18·k: lines 8193, 16386, ...
  for (size_t n : {size_t{1}, size_t{8192}, size_t{8193}, size_t{8194}, size_t{16386},
                   size_t{16387}, size_t{20000}, lines - 1, lines}) {
    const std::string bad = with_bad_line(text, n, "1 abc 3");
    const std::string want = "p.txt:" + std::to_string(n) + ": expected a number for the y";
    for (int threads : {1, 2}) {
      ThreadLimit limit(threads);
      EXPECT_EQ(error_of([&] { parse_points(bad, "p.txt"); }).rfind(want, 0), 0u)
          << "line " << n << ", " << threads << " threads";
    }
  }
  // Two bad lines in different chunks: the first in the file wins, whatever finishes first.
  std::string two = with_bad_line(text, 39000, "1 2");
  two = with_bad_line(two, 8000, "1 2 3 4");
  for (int threads : {1, 2}) {
    ThreadLimit limit(threads);
    EXPECT_EQ(error_of([&] { parse_points(two, "p.txt"); }),
              "p.txt:8000: expected 3 numbers, got more");
  }
  // The last line without its newline, behind a byte order mark and CRLF lines.
  std::string crlf = "\xEF\xBB\xBF";
  for (size_t i = 0; i < 30000; ++i) crlf += "1 2 3\r\n";
  EXPECT_EQ(error_of([&] { parse_points(crlf + "1 2", "p.txt"); }),
            "p.txt:30001: expected 3 numbers, got 2");
  EXPECT_EQ(error_of([&] { parse_points(crlf + "# x\n1 2 nan\r\n", "p.txt"); }),
            "p.txt:30002: non-finite z coordinate 'nan'");
}

TEST(Points, CoordinatesOutsideTheSupportedRangeAreRefused) {
  EXPECT_EQ(parse_points("1.8446744073709552e19 0 -1.8446744073709552e19\n", "p.txt")[0].x, 0x1p64);
  const std::string e = error_of([] { parse_points("0 0 0\n0 1e20 0\n", "p.txt"); });
  EXPECT_EQ(e.rfind("p.txt:2: y coordinate '1e20' is outside the supported range", 0), 0u) << e;
  EXPECT_EQ(error_of([] { parse_points("0 0 1e400\n", "p.txt"); }),
            "p.txt:1: out-of-range z coordinate '1e400'");
}

// ---- .npy ----

/// An .npy file written by hand (independently of io/npy.cpp): `header` is the dict text.
std::string npy_file(const std::string& header, const std::string& data, int major = 1) {
  std::string h = header;
  const size_t preamble = major == 1 ? 10 : 12;
  h.append((64 - (preamble + h.size() + 1) % 64) % 64, ' ');
  h += '\n';
  std::string out = "\x93NUMPY";
  out += static_cast<char>(major);
  out += '\0';
  for (size_t i = 0; i < (major == 1 ? 2u : 4u); ++i)
    out += static_cast<char>((h.size() >> (8 * i)) & 0xff);
  return out + h + data;
}

/// The values of `points` in C or Fortran order as float64 or float32, either byte order.
std::string npy_data(const std::vector<Vec3>& points, bool single, bool big, bool fortran) {
  std::string out;
  const size_t n = points.size();
  for (size_t k = 0; k < 3 * n; ++k) {
    const size_t i = fortran ? k % n : k / 3;
    const int a = static_cast<int>(fortran ? k / n : k % 3);
    char bytes[8];
    const size_t size = single ? 4 : 8;
    if (single) {
      const auto bits = std::bit_cast<uint32_t>(static_cast<float>(points[i][a]));
      std::memcpy(bytes, &bits, 4);
    } else {
      const auto bits = std::bit_cast<uint64_t>(points[i][a]);
      std::memcpy(bytes, &bits, 8);
    }
    if (big) std::reverse(bytes, bytes + size);
    out.append(bytes, size);
  }
  return out;
}

std::string dict(const std::string& descr, bool fortran, const std::string& shape) {
  return "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
         ", 'shape': " + shape + ", }";
}

TEST(Points, NpyEqualsTheSamePointsAsText) {
  std::vector<Vec3> points = random_points(70000, 3);  // two conversion tasks and a bit
  std::vector<Vec3> floats = points;                   // float32-representable, in range
  for (Vec3& p : floats)
    p = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  std::string text;
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) (text += number(p[a])) += a < 2 ? " " : "\n";
  const std::vector<Vec3> from_text = parse_points(text, "p.txt");
  ASSERT_EQ(from_text, points);
  const std::string shape = "(" + std::to_string(points.size()) + ", 3)";
  for (bool single : {false, true})
    for (bool big : {false, true})
      for (bool fortran : {false, true})
        for (int major : {1, 2, 3}) {
          const std::string descr = std::string(big ? ">" : "<") + (single ? "f4" : "f8");
          const std::string file =
              npy_file(dict(descr, fortran, shape), npy_data(points, single, big, fortran), major);
          ThreadLimit limit(major);  // 1, 2, 3 threads
          EXPECT_EQ(parse_npy_points(file, "p.npy"), single ? floats : from_text)
              << descr << (fortran ? " F" : " C") << " v" << major;
        }
  // Key order, quotes and spacing are Python's business; an empty array is fine.
  EXPECT_EQ(parse_npy_points(npy_file("{\"shape\":(1,3),\"fortran_order\":False,\"descr\":\"<f8\"}",
                                      npy_data({{1, 2, 3}}, false, false, false)),
                             "p.npy"),
            (std::vector<Vec3>{{1, 2, 3}}));
  EXPECT_TRUE(parse_npy_points(npy_file(dict("<f8", false, "(0, 3)"), ""), "p.npy").empty());
}

TEST(Points, MalformedNpyIsOneLineNamingTheFile) {
  const std::string good =
      npy_file(dict("<f8", false, "(2, 3)"), npy_data({{1, 2, 3}, {4, 5, 6}}, false, false, false));
  const std::string huge = std::to_string(uint64_t{1} << 62);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "not a NumPy .npy file"},
      {"\x93NUMPX\x01\x00", "not a NumPy .npy file"},
      {"\x93NUMPY", "truncated .npy file (no version)"},
      {std::string("\x93NUMPY\x01\x00\x10", 9), "truncated .npy file (no header length)"},
      {std::string("\x93NUMPY\x04\x00", 8) + good.substr(8), "unsupported .npy version 4.0"},
      {good.substr(0, 40), "truncated .npy header"},
      {good.substr(0, good.size() - 1), "needs 48 data bytes, the file has 47"},
      {good + "x", "needs 48 data bytes, the file has 49"},
      {npy_file(dict("<i8", false, "(2, 3)"), std::string(48, '\0')),
       "unsupported .npy dtype '<i8'"},
      {npy_file(dict("<f2", false, "(2, 3)"), std::string(12, '\0')),
       "unsupported .npy dtype '<f2'"},
      {npy_file(dict("|u1", false, "(2, 3)"), std::string(6, '\0')),
       "unsupported .npy dtype '|u1'"},
      {npy_file(dict("<f8", false, "(6,)"), std::string(48, '\0')), "shape (6,) is not (N, 3)"},
      {npy_file(dict("<f8", false, "(3, 2)"), std::string(48, '\0')), "shape (3, 2) is not (N, 3)"},
      {npy_file(dict("<f8", false, "(2, 3, 1)"), std::string(48, '\0')),
       "shape (2, 3, 1) is not (N, 3)"},
      {npy_file(dict("<f8", false, "()"), std::string(8, '\0')), "shape () is not (N, 3)"},
      {npy_file(dict("<f8", false, "(" + huge + ", 3)"), ""), "needs more than 2^64 data bytes"},
      {npy_file(dict("<f8", false, "(99999999999999999999999, 3)"), ""), "is too large"},
      {npy_file(dict("<f8", false, "(-2, 3)"), ""), "expected a whole number in 'shape'"},
      {npy_file("{'descr': '<f8', 'shape': (2, 3)}", std::string(48, '\0')),
       "missing key 'fortran_order'"},
      {npy_file("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), 'x': 1}", ""),
       "unexpected key 'x'"},
      {npy_file("{'descr': '<f8', 'fortran_order': false, 'shape': (2, 3)}", ""),
       "expected True or False"},
      {npy_file("{'descr': [('x', '<f8')], 'fortran_order': False, 'shape': (2,)}", ""),
       "expected a dtype string"},
      {npy_file("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3)} junk", ""),
       "after the dict"},
      {npy_file("'descr': '<f8'", ""), "expected '{'"},
      {npy_file("{'descr: '<f8', 'fortran_order': False, 'shape': (2, 3)}", ""), "expected ':'"},
      {npy_file(dict("<f8", false, "(1099511627776, 3)"), ""),
       "needs 26388279066624 data bytes, the file has 0"},
      {npy_file(dict("<f8", false, "(2, 3)"),
                npy_data({{1, 2, 3}, {4, 1e300, 6}}, false, false, false)),
       "point 1 (counting from 0): y coordinate 1.0000000000000001e+300 is outside the supported "
       "range"},
      {npy_file(dict("<f8", false, "(2, 3)"),
                npy_data({{1, 2, 3}, {4, 5, NAN}}, false, false, false)),
       "point 1 (counting from 0): non-finite z coordinate nan"},
      {npy_file(dict(">f4", true, "(2, 3)"),
                npy_data({{1, INFINITY, 3}, {-INFINITY, 5, 6}}, true, true, true)),
       "point 0 (counting from 0): non-finite y coordinate inf"},
  };
  for (const auto& [bytes, needle] : cases) {
    const std::string e = error_of([&] { parse_npy_points(bytes, "p.npy"); });
    EXPECT_EQ(e.rfind("p.npy: ", 0), 0u) << needle << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_NE(e.find(needle), std::string::npos) << needle << ": " << e;
  }
}

TEST(Points, ReadPointsChecksTheMemoryLimitBeforeConverting) {
  const auto dir = test::temp_dir("points");
  // 1000 points in a 24 kB file; at 10 kB per point they need ~10 MB, over a 1 MiB limit.
  std::vector<Vec3> points(1000, Vec3{1, 2, 3});
  test::write_file(dir / "p.npy", npy_file(dict("<f8", false, "(1000, 3)"),
                                           npy_data(points, false, false, false)));
  EXPECT_EQ(cli::read_points((dir / "p.npy").string(), 1 << 20, 24), points);
  const std::string e =
      error_of([&] { cli::read_points((dir / "p.npy").string(), 1 << 20, 10000); });
  // The library's name of the limit (the CLI's main shows --max-memory: messages_test.cpp).
  EXPECT_NE(e.find("p.npy: classifying 1000 points needs 10 MiB, over max_memory 1 MiB"),
            std::string::npos)
      << e;
  // Any name: the magic decides; a .npy name without it is refused.
  std::filesystem::copy_file(dir / "p.npy", dir / "p.txt");
  EXPECT_EQ(cli::read_points((dir / "p.txt").string(), 1 << 20, 24), points);
  test::write_file(dir / "q.NPY", "1 2 3\n");
  EXPECT_NE(error_of([&] {
              cli::read_points((dir / "q.NPY").string(), 1 << 20, 24);
            }).find("q.NPY: not a NumPy .npy file"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
