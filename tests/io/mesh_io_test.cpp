// Tests for io/mesh_io.h: round trips, real models (libcgal-demo, assimp-testmodels), and a
// corpus of malformed files that must raise a one-line InputError naming the file.

#include "cover/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cover/solid/errors.h"
#include "helpers.h"

namespace {

using cover::FaceLabels;
using cover::InputError;
using cover::PolygonMesh;
using cover::Vec3;
namespace fs = std::filesystem;
namespace test = cover::test;

/// A cube whose top face has a square hole joined to the outer loop by the false edge 4–8.
/// Coordinates are chosen to have no short decimal form.
PolygonMesh holed_cube() {
  const double lo = -1.0 / 3, hi = 0.1 + 2.0 / 3, a = 0.1, b = 0.2 + 1e-13;
  PolygonMesh mesh;
  mesh.vertices = {{lo, lo, lo}, {hi, lo, lo}, {hi, hi, lo},         {lo, hi, lo}, {lo, lo, hi},
                   {hi, lo, hi}, {hi, hi, hi}, {lo, hi, hi},         {a, a, hi},   {a, b, hi},
                   {b, b, hi},   {b, a, hi},   {1e300, 5e-324, -0.0}};
  mesh.add_face({0, 3, 2, 1});
  mesh.add_face({0, 1, 5, 4});
  mesh.add_face({1, 2, 6, 5});
  mesh.add_face({2, 3, 7, 6});
  mesh.add_face({3, 0, 4, 7});
  mesh.add_face({4, 5, 6, 7, 4, 8, 9, 10, 11, 8});
  return mesh;
}

bool same_bits(const Vec3& p, const Vec3& q) {
  return std::bit_cast<uint64_t>(p.x) == std::bit_cast<uint64_t>(q.x) &&
         std::bit_cast<uint64_t>(p.y) == std::bit_cast<uint64_t>(q.y) &&
         std::bit_cast<uint64_t>(p.z) == std::bit_cast<uint64_t>(q.z);
}

/// Structural invariants every mesh returned by read_mesh must satisfy.
void expect_consistent(const PolygonMesh& mesh) {
  ASSERT_FALSE(mesh.face_start.empty());
  EXPECT_EQ(mesh.face_start.front(), 0u);
  EXPECT_EQ(mesh.face_start.back(), mesh.face_vertices.size());
  EXPECT_GT(mesh.face_count(), 0u);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    ASSERT_GE(mesh.face_start[f + 1], mesh.face_start[f] + 3) << "face " << f;
    for (uint32_t v : mesh.face(f)) ASSERT_LT(v, mesh.vertices.size()) << "face " << f;
  }
  for (const Vec3& p : mesh.vertices)
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
}

/// Checks an InputError message: one line that names the file.
void expect_good_message(const std::string& message, const fs::path& path) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.find('\r'), std::string::npos) << message;
  EXPECT_NE(message.find(path.string()), std::string::npos) << message;
}

/// read_mesh must throw InputError; returns its message.
std::string expect_input_error(const fs::path& path) {
  try {
    PolygonMesh mesh = cover::read_mesh(path);
    ADD_FAILURE() << path << " was accepted (" << mesh.vertices.size() << " vertices, "
                  << mesh.face_count() << " faces)";
  } catch (const InputError& e) {
    expect_good_message(e.what(), path);
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": not an InputError: " << e.what();
  }
  return "";
}

/// read_mesh either returns a consistent mesh or throws a well-formed InputError.
void expect_parses_or_throws(const fs::path& path) {
  try {
    expect_consistent(cover::read_mesh(path));
  } catch (const InputError& e) {
    expect_good_message(e.what(), path);
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": not an InputError: " << e.what();
  }
}

/// Writes `bytes` to dir/name and expects read_mesh to fail; returns the message.
std::string bad_file(const fs::path& dir, const std::string& name, const std::string& bytes) {
  SCOPED_TRACE(name);
  test::write_file(dir / name, bytes);
  return expect_input_error(dir / name);
}

PolygonMesh read_text(const fs::path& dir, const std::string& name, const std::string& bytes) {
  test::write_file(dir / name, bytes);
  return cover::read_mesh(dir / name);
}

/// Vertex and face counts from an OFF header ("OFF" then "V F E", '#' comments allowed).
std::pair<size_t, size_t> off_header_counts(const fs::path& path) {
  std::istringstream in(test::read_file(path));
  std::vector<std::string> words;
  for (std::string line; words.size() < 3 && std::getline(in, line);) {
    std::istringstream tokens(line.substr(0, line.find('#')));
    for (std::string word; tokens >> word;) words.push_back(word);
  }
  if (!words.empty() && words[0].find("OFF") != std::string::npos) words.erase(words.begin());
  return {std::stoul(words.at(0)), std::stoul(words.at(1))};
}

std::string little_endian(const void* value, size_t size) {
  std::string bytes(static_cast<const char*>(value), size);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  return bytes;
}
template <typename T>
std::string le(T value) {
  return little_endian(&value, sizeof value);
}
template <typename T>
std::string be(T value) {
  std::string bytes = le(value);
  std::reverse(bytes.begin(), bytes.end());
  return bytes;
}

/// A binary STL with the given triangles (9 floats each).
std::string binary_stl(const std::vector<std::array<float, 9>>& triangles,
                       const std::string& header) {
  std::string bytes = header;
  bytes.resize(80, '\0');
  bytes += le(static_cast<uint32_t>(triangles.size()));
  for (const auto& t : triangles) {
    for (int i = 0; i < 3; ++i) bytes += le(0.0f);
    for (float c : t) bytes += le(c);
    bytes += le(uint16_t{0});
  }
  return bytes;
}

// ---- round trips ---------------------------------------------------------------------------

TEST(MeshIoTest, RoundTripIsExactForOffObjPly) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh mesh = holed_cube();
  for (const char* name : {"m.off", "m.obj", "m.ply", "M.OFF", "m.Ply"}) {
    SCOPED_TRACE(name);
    cover::write_mesh(dir / name, mesh);
    const PolygonMesh back = cover::read_mesh(dir / name);
    ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
      EXPECT_TRUE(same_bits(back.vertices[v], mesh.vertices[v])) << "vertex " << v;
    EXPECT_EQ(back.face_start, mesh.face_start);
    EXPECT_EQ(back.face_vertices, mesh.face_vertices);
  }
  fs::remove_all(dir);
}

// Issue 24: an OFF body of 256 KiB or more is parsed in parallel chunks; the mesh must be the one
// the line-by-line reading gives (comments, blank lines, CRLF, mixed face sizes across chunk
// ends), and an error deep inside must name the same line as before (the serial re-read).
/// The message of reading `bytes` as dir/name (read_text), or "no error".
std::string read_error(const fs::path& dir, const std::string& name, const std::string& bytes) {
  try {
    read_text(dir, name, bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

/// Same vertices (bit for bit) and faces.
void expect_same_mesh(const PolygonMesh& back, const PolygonMesh& want) {
  ASSERT_EQ(back.vertices.size(), want.vertices.size());
  for (size_t v = 0; v < want.vertices.size(); ++v)
    ASSERT_TRUE(same_bits(back.vertices[v], want.vertices[v])) << "vertex " << v;
  EXPECT_EQ(back.face_start, want.face_start);
  EXPECT_EQ(back.face_vertices, want.face_vertices);
}

TEST(MeshIoTest, LargeOffParsedInParallelGivesTheSameMeshAndErrors) {
  const fs::path dir = test::temp_dir("mesh-io");
  constexpr uint32_t kV = 40000, kF = 40000;
  std::ostringstream text;
  text << "OFF\n# a large file\n" << kV << " " << kF << " 0\n";
  PolygonMesh want;
  uint64_t line = 3;
  std::vector<uint64_t> line_of_vertex(kV), line_of_face(kF), vertex_offset(kV);
  for (uint32_t v = 0; v < kV; ++v) {
    if (v % 997 == 0) text << "\n# comment line\n", line += 2;
    const Vec3 p{v * 0.001, -1.0 / (v + 1), v % 7 == 0 ? 1e-300 : 3.25};
    want.vertices.push_back(p);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g%s", p.x, p.y, p.z,
                  v % 5 == 0 ? " 0.5 0.5 0.5\r\n" : "\n");
    vertex_offset[v] = static_cast<uint64_t>(text.tellp());
    text << buf;
    line_of_vertex[v] = ++line;
  }
  for (uint32_t f = 0; f < kF; ++f) {
    if (f % 1009 == 0) text << "  # indented comment\n", ++line;
    const uint32_t n = 3 + f % 3;
    std::vector<uint32_t> loop;
    for (uint32_t k = 0; k < n; ++k) loop.push_back((f * 7 + k * 13) % kV);
    want.add_face(loop);
    text << n;
    for (uint32_t i : loop) text << ' ' << i;
    text << (f % 11 == 0 ? " 255 0 0 # colour\n" : "\n");
    line_of_face[f] = ++line;
  }
  const std::string good = text.str();
  ASSERT_GT(good.size(), size_t{1} << 20);
  expect_same_mesh(read_text(dir, "big.off", good), want);
  // Errors deep in the body: a bad coordinate, an index out of range, a missing face.
  auto error_of = [&](const std::string& t) { return read_error(dir, "big.off", t); };
  const std::string file = (dir / "big.off").string();
  {
    std::string t = good;
    const size_t start = vertex_offset[29999], y = t.find(' ', start) + 1;
    t[y] = 'x';  // vertex 29999's y coordinate becomes a bad token
    const std::string token = t.substr(y, t.find(' ', y) - y);
    EXPECT_EQ(error_of(t), file + ":" + std::to_string(line_of_vertex[29999]) +
                               ": expected a number for the y coordinate, found '" + token + "'");
  }
  {
    std::string t = good;
    t.insert(t.rfind("\n", t.size() - 2) + 1, "3 0 1 " + std::to_string(kV) + "\n");
    EXPECT_EQ(error_of(t), file + ":" + std::to_string(line_of_face[kF - 1]) + ": vertex index " +
                               std::to_string(kV) + " out of range [0, " + std::to_string(kV) +
                               ")");
  }
  {
    std::string t = good.substr(0, good.rfind("\n", good.size() - 2) + 1);  // last face gone
    EXPECT_EQ(error_of(t), file + ":" + std::to_string(line_of_face[kF - 1] - 1) +
                               ": unexpected end of file: expected " + std::to_string(kF) +
                               " faces, found " + std::to_string(kF - 1));
  }
  fs::remove_all(dir);
}

TEST(MeshIoTest, StlRoundTripFanTriangulatesAndWelds) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh mesh = holed_cube();
  cover::write_mesh(dir / "m.stl", mesh);
  const PolygonMesh back = cover::read_mesh(dir / "m.stl");
  expect_consistent(back);
  auto as_float = [](Vec3 p) {
    return Vec3{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  };
  size_t t = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t i = 1; i + 1 < face.size(); ++i, ++t) {
      ASSERT_LT(t, back.face_count());
      ASSERT_EQ(back.face(t).size(), 3u);
      const uint32_t corners[3] = {face[0], face[i], face[i + 1]};
      for (int k = 0; k < 3; ++k)
        EXPECT_TRUE(back.vertices[back.face(t)[k]] == as_float(mesh.vertices[corners[k]]));
    }
  }
  EXPECT_EQ(back.face_count(), t);
  EXPECT_EQ(back.vertices.size(), 12u);  // the unreferenced vertex is not written
  fs::remove_all(dir);
}

// The writers format vertex and face lines in parallel chunks, a block of chunks at a time
// (write_mesh.cpp): the file must be the text written line by line, here assembled serially with
// the same number format (std::to_chars, shortest round trip), across several blocks, with mixed
// face sizes and OBJ groups that change inside chunks and at chunk ends.
TEST(MeshIoTest, ParallelFormattingWritesTheSerialText) {
  const fs::path dir = test::temp_dir("mesh-io");
  constexpr uint32_t kV = 300000, kF = 290000;  // more than two blocks of 64 × 2048 lines
  PolygonMesh mesh;
  for (uint32_t v = 0; v < kV; ++v)
    mesh.vertices.push_back({v * 0.001, -1.0 / (v + 1), v % 7 == 0 ? 1e-300 : v * 3.25});
  FaceLabels labels;
  labels.ply_property = "leaf";
  labels.obj_groups = {"a", "b_1", "c"};
  for (uint32_t f = 0; f < kF; ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t k = 0; k < 3 + f % 3; ++k) loop.push_back((f * 7 + k * 13) % kV);
    mesh.add_face(loop);
    labels.labels.push_back(f % 2048 == 0 || f % 1000 < 3 ? (f / 7) % 3 : 1);
  }
  auto number = [](std::string& s, auto x) {
    char digits[32];
    s.append(digits, std::to_chars(digits, digits + sizeof digits, x).ptr);
  };
  std::string off = "OFF\n" + std::to_string(kV) + " " + std::to_string(kF) + " 0\n";
  std::string obj = "# written by Cover\n";
  for (const Vec3& p : mesh.vertices) {
    obj += "v ";
    for (std::string* s : {&off, &obj})
      number(*s, p.x), *s += ' ', number(*s, p.y), *s += ' ', number(*s, p.z), *s += '\n';
  }
  for (uint32_t f = 0; f < kF; ++f) {
    number(off, mesh.face(f).size());
    if (f == 0 || labels.labels[f] != labels.labels[f - 1])
      obj += "g " + labels.obj_groups[labels.labels[f]] + "\n";
    obj += 'f';
    for (uint32_t v : mesh.face(f)) off += ' ', number(off, v), obj += ' ', number(obj, v + 1);
    off += '\n', obj += '\n';
  }
  cover::write_mesh(dir / "m.off", mesh);
  cover::write_mesh(dir / "m.obj", mesh, labels);
  EXPECT_TRUE(test::read_file(dir / "m.off") == off);
  EXPECT_TRUE(test::read_file(dir / "m.obj") == obj);
  fs::remove_all(dir);
}

TEST(MeshIoTest, WriteIsAtomicAndReportsFailures) {
  const fs::path dir = test::temp_dir("mesh-io");
  test::write_file(dir / "m.off", "old contents");
  cover::write_mesh(dir / "m.off", holed_cube());
  EXPECT_EQ(cover::read_mesh(dir / "m.off").face_count(), 6u);
  size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1u);  // no temporary left behind

  auto expect_write_error = [&](const fs::path& path, const PolygonMesh& mesh) {
    try {
      cover::write_mesh(path, mesh);
      ADD_FAILURE() << path << " was written";
    } catch (const InputError& e) {
      expect_good_message(e.what(), path);
    }
  };
  expect_write_error(dir / "missing-folder" / "m.off", holed_cube());
  expect_write_error(dir / "m.3ds", holed_cube());
  PolygonMesh bad = holed_cube();
  bad.face_vertices[3] = 99;
  expect_write_error(dir / "bad.obj", bad);
  EXPECT_FALSE(fs::exists(dir / "bad.obj"));
  fs::remove_all(dir);
}

TEST(MeshIoTest, PlyWriterWidensTheListCountForLargeFaces) {
  const fs::path dir = test::temp_dir("mesh-io");
  PolygonMesh mesh;
  std::vector<uint32_t> loop;
  for (uint32_t i = 0; i < 300; ++i) {
    const double angle = 2 * std::numbers::pi * i / 300;
    mesh.vertices.push_back({std::cos(angle), std::sin(angle), 0});
    loop.push_back(i);
  }
  mesh.add_face(loop);
  cover::write_mesh(dir / "disk.ply", mesh);
  EXPECT_NE(test::read_file(dir / "disk.ply").find("property list uint int vertex_indices"),
            std::string::npos);
  const PolygonMesh back = cover::read_mesh(dir / "disk.ply");
  EXPECT_EQ(back.face_vertices, mesh.face_vertices);
  fs::remove_all(dir);
}

// ---- real models ---------------------------------------------------------------------------

TEST(MeshIoTest, CgalModelsMatchTheirOffHeaders) {
  for (const char* name :
       {"elephant.off", "knot1.off", "armadillo.off", "bunny00.off", "fandisk.off"}) {
    SCOPED_TRACE(name);
    const fs::path path = test::cgal_mesh(name);
    const auto [v, f] = off_header_counts(path);
    const PolygonMesh mesh = cover::read_mesh(path);
    EXPECT_EQ(mesh.vertices.size(), v);
    EXPECT_EQ(mesh.face_count(), f);
    EXPECT_GT(f, 0u);
    expect_consistent(mesh);
  }
}

TEST(MeshIoTest, AssimpValidModels) {
  const fs::path models = test::assimp_models();
  struct Case {
    const char* file;
    size_t vertices, faces;
  };
  for (const Case& c :
       {Case{"OFF/Cube.off", 8, 6}, Case{"PLY/cube.ply", 8, 6}, Case{"PLY/cube_binary.ply", 8, 12},
        Case{"OBJ/box.obj", 8, 6}, Case{"STL/Spider_binary.stl", 722, 1368}}) {
    SCOPED_TRACE(c.file);
    const PolygonMesh mesh = cover::read_mesh(models / c.file);
    EXPECT_EQ(mesh.vertices.size(), c.vertices);
    EXPECT_EQ(mesh.face_count(), c.faces);
    expect_consistent(mesh);
  }
  const PolygonMesh ascii = cover::read_mesh(models / "STL/Spider_ascii.stl");
  const PolygonMesh binary = cover::read_mesh(models / "STL/Spider_binary.stl");
  EXPECT_EQ(ascii.vertices.size(), binary.vertices.size());
  EXPECT_EQ(ascii.face_count(), binary.face_count());
  EXPECT_EQ(ascii.face_vertices.size(), binary.face_vertices.size());
  expect_consistent(ascii);
}

TEST(MeshIoTest, EveryAssimpInvalidFileIsRefused) {
  size_t count = 0;
  for (const auto& entry : fs::directory_iterator(test::assimp_models() / "invalid")) {
    SCOPED_TRACE(entry.path().string());
    expect_input_error(entry.path());
    ++count;
  }
  EXPECT_GE(count, 10u);
}

// ---- format details ------------------------------------------------------------------------

TEST(MeshIoTest, OffVariants) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh colored = read_text(dir, "c.off",
                                        "# comment\nCOFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n"
                                        "0 1 0 1 0 0 1 # red\n\n3 0 1 2 255 0 0\n");
  EXPECT_EQ(colored.vertices.size(), 3u);
  EXPECT_EQ(colored.face_vertices, (std::vector<uint32_t>{0, 1, 2}));
  const PolygonMesh inline_counts =
      read_text(dir, "i.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 2 1 0");
  EXPECT_EQ(inline_counts.face_vertices, (std::vector<uint32_t>{2, 1, 0}));
  const PolygonMesh headless =
      read_text(dir, "h.off", "3 1\r\n0 0 0\r\n1 0 0\r\n+0 1 0\r\n3 0 1 2\r\n");
  EXPECT_EQ(headless.vertices[2].y, 1.0);
  fs::remove_all(dir);
}

TEST(MeshIoTest, ObjReferencesAndIgnoredStatements) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh mesh = read_text(dir, "m.obj",
                                     "mtllib a.mtl\no thing\ng group\ns off\nusemtl red\n"
                                     "v 0 0 0\nv 1 0 0 1\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0\n"
                                     "vt 0 0\nvn 0 0 1\nl 1 2\np 1\n# comment\n"
                                     "f 1/1 2/1/1 3//1 4\nf -4 -2 -1\nf 1 5 2\nv 2 2 2\n");
  EXPECT_EQ(mesh.vertices.size(), 5u);  // the forward reference to vertex 5 is fine
  EXPECT_EQ(mesh.face_vertices, (std::vector<uint32_t>{0, 1, 2, 3, 0, 2, 3, 0, 4, 1}));
  fs::remove_all(dir);
}

// An OBJ of 1 MiB or more is read in parallel chunks (read_obj.cpp): vertices and faces
// interleaved, relative and forward references across chunk borders, comments and ignored
// statements give the same mesh; errors deep in the file name their line as before.
TEST(MeshIoTest, LargeObjParsedInParallelGivesTheSameMeshAndErrors) {
  const fs::path dir = test::temp_dir("mesh-io");
  std::ostringstream text;
  text << "# big\nmtllib a.mtl\n";
  PolygonMesh want;
  uint64_t line = 2;
  std::vector<uint64_t> line_of_vertex, offset_of_vertex;
  constexpr uint32_t kV = 60000;
  for (uint32_t v = 0; v < kV; ++v) {
    const Vec3 p{v * 0.001, -1.0 / (v + 1), v % 7 == 0 ? 1e-300 : 3.25};
    want.vertices.push_back(p);
    char buf[96];
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g%s", p.x, p.y, p.z,
                  v % 5 == 0 ? " 1\r\n" : "\n");
    offset_of_vertex.push_back(static_cast<uint64_t>(text.tellp()));
    text << buf;
    line_of_vertex.push_back(++line);
    if (v % 3 == 2) {  // a face right after its vertices: relative and absolute references
      want.add_face({v - 2, v - 1, v});
      text << "f -3 " << v << "/1 " << v + 1 << "//2\n";
      ++line;
    }
    if (v % 1000 == 999) text << "vt 0 0\ng part\n# note\n", line += 3;
  }
  text << "f 1 " << kV << " 2\n";  // refers forward from nowhere in particular: fine at the end
  want.add_face({0, kV - 1, 1});
  const std::string good = text.str();
  ASSERT_GT(good.size(), size_t{1} << 20);
  expect_same_mesh(read_text(dir, "big.obj", good), want);
  auto error_of = [&](const std::string& t) { return read_error(dir, "big.obj", t); };
  const std::string file = (dir / "big.obj").string();
  {  // a bad coordinate deep in the file
    std::string t = good;
    const size_t at = t.find(' ', offset_of_vertex[45000] + 2) + 1;
    t[at] = 'x';
    EXPECT_NE(error_of(t).find(file + ":" + std::to_string(line_of_vertex[45000]) + ":"),
              std::string::npos)
        << error_of(t);
  }
  {  // an index past the end
    std::string t = good + "f 1 2 " + std::to_string(kV + 5) + "\n";
    EXPECT_NE(error_of(t).find(":" + std::to_string(line + 2) + ": vertex index " +
                               std::to_string(kV + 5) + " out of range"),
              std::string::npos)
        << error_of(t);
  }
  fs::remove_all(dir);
}

TEST(MeshIoTest, PlyTypesListsAndSkippedElements) {
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string header_tail =
      "element vertex 3\nproperty uchar red\nproperty int x\nproperty double y\n"
      "property list uchar float texture\nproperty short z\n"
      "element edge 1\nproperty list int int ends\nproperty float weight\n"
      "element face 1\nproperty uchar flags\nproperty list int uint vertex_index\n"
      "element material 2\nproperty float shine\nend_header\n";
  const PolygonMesh ascii = read_text(dir, "a.ply",
                                      "ply\nformat ascii 1.0\ncomment x\n" + header_tail +
                                          "7 0 0 2 0.5 0.5 0\n7 1 0 0 0\n7 0 1.5 1 9 -3\n"
                                          "2 0 1 1.0\n0 3 2 1 0\n1\n2\n");
  EXPECT_EQ(ascii.vertices.size(), 3u);
  EXPECT_TRUE(ascii.vertices[2] == (Vec3{0, 1.5, -3}));
  EXPECT_EQ(ascii.face_vertices, (std::vector<uint32_t>{2, 1, 0}));

  for (bool big : {false, true}) {
    auto v = [&](auto value) { return big ? be(value) : le(value); };
    std::string body;
    const int xs[] = {0, 1, 0};
    const double ys[] = {0, 0, 1.5};
    const int16_t zs[] = {0, 0, -3};
    for (int i = 0; i < 3; ++i)
      body += v(uint8_t{7}) + v(xs[i]) + v(ys[i]) + v(uint8_t{1}) + v(0.5f) + v(zs[i]);
    body += v(2) + v(0) + v(1) + v(1.0f);
    body += v(uint8_t{0}) + v(3) + v(2u) + v(1u) + v(0u);
    body += v(1.0f) + v(2.0f);
    const std::string format = big ? "binary_big_endian" : "binary_little_endian";
    const PolygonMesh binary =
        read_text(dir, "b.ply", "ply\nformat " + format + " 1.0\n" + header_tail + body);
    EXPECT_TRUE(binary.vertices[2] == (Vec3{0, 1.5, -3}));
    EXPECT_EQ(binary.face_vertices, ascii.face_vertices);
    // The same bytes under the other byte order are garbage and must be refused.
    const std::string other = big ? "binary_little_endian" : "binary_big_endian";
    bad_file(dir, "swapped.ply", "ply\nformat " + other + " 1.0\n" + header_tail + body);
  }
  fs::remove_all(dir);
}

TEST(MeshIoTest, StlDetectionAndWelding) {
  const fs::path dir = test::temp_dir("mesh-io");
  const std::vector<std::array<float, 9>> two = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
                                                 {1, 0, 0, 1, 1, 0, -0.0f, 1, 0}};
  // A binary file whose header starts with "solid" is still binary.
  const PolygonMesh binary = read_text(dir, "b.stl", binary_stl(two, "solid but binary"));
  EXPECT_EQ(binary.vertices.size(), 4u);
  EXPECT_EQ(binary.face_vertices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  const PolygonMesh ascii = read_text(dir, "a.stl",
                                      "solid t\n facet normal 0 0 1\n  outer loop\n"
                                      "   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
                                      "  endloop\n endfacet\nendsolid t\n"
                                      "SOLID u\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 1 0 0\n"
                                      "VERTEX 1 1 0\nVERTEX -0 1 0\nENDLOOP\nENDFACET\nENDSOLID\n");
  EXPECT_EQ(ascii.face_vertices, binary.face_vertices);
  fs::remove_all(dir);
}

// ---- malformed files -----------------------------------------------------------------------

TEST(MeshIoTest, MessagesNameFileAndPlace) {
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string off = (dir / "a.off").string();
  EXPECT_EQ(bad_file(dir, "a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n"),
            off + ":5: expected a number for the z coordinate, found 'x'");
  EXPECT_EQ(bad_file(dir, "a.3ds", "x"),
            (dir / "a.3ds").string() +
                ": unsupported mesh format '.3ds' (expected .obj, .off, .stl, .ply)");
  EXPECT_EQ(bad_file(dir, "e.obj", ""), (dir / "e.obj").string() + ": empty file");
  EXPECT_NE(bad_file(dir, "n.obj", "v 0 0 0\n"), "");
  const std::string stl = bad_file(
      dir, "nan.stl", binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 1, 0, 0, NAN, 1, 0}}, ""));
  EXPECT_NE(stl.find(": triangle 2 (byte "), std::string::npos) << stl;
  const std::string ply =
      bad_file(dir, "p.ply",
               "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
               "property float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n" +
                   std::string(36, '\0') + le(uint8_t{3}) + le(0) + le(1) + le(7));
  EXPECT_NE(ply.find(": byte "), std::string::npos) << ply;
  expect_input_error(dir / "does-not-exist.off");
  fs::create_directories(dir / "folder.off");
  expect_input_error(dir / "folder.off");
  fs::remove_all(dir);
}

TEST(MeshIoTest, MalformedTextCorpus) {
  const fs::path dir = test::temp_dir("mesh-io");
  // Padded coordinates, so that the counts pass the size check and the parser itself is tested.
  const std::string v3 = "0.0 0.0 0.0\n1.0 0.0 0.0\n0.0 1.0 0.0\n";
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n";
  struct Case {
    std::string name, bytes, expected;  ///< expected: a fragment of the message
  };
  const std::vector<Case> cases = {
      {"huge.off", "OFF\n1000000000 1000000000 0\n",
       ":2: 1000000000 vertices and 1000000000 faces cannot fit"},
      {"huge2.off", "OFF\n3 99999999999999999999999 0\n" + v3 + "3 0 1 2\n",
       ":2: expected the face count"},
      {"overflow.off", "OFF\n18446744073709551615 18446744073709551615 0\n", ":2: vertex count"},
      {"nofaces.off", "OFF\n3 0 0\n" + v3, ":2: no faces"},
      {"onlyheader.off", "OFF\n", ":1: unexpected end of file"},
      {"comment.off", "# nothing\n", ":1: no OFF header"},
      {"range.off", "OFF\n3 1 0\n" + v3 + "3 0 1 3\n", ":6: vertex index 3 out of range"},
      {"negative.off", "OFF\n3 1 0\n" + v3 + "3 0 -1 2\n", ":6: vertex index -1 out of range"},
      {"bigindex.off", "OFF\n3 1 0\n" + v3 + "3 0 1 4294967296\n",
       ":6: vertex index 4294967296 out"},
      {"nan.off", "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n",
       ":3: non-finite z coordinate 'nan'"},
      {"inf.off", "OFF\n3 1 0\n0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n", ":4: non-finite y coordinate"},
      {"e999.off", "OFF\n3 1 0\n0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n",
       ":3: out-of-range z coordinate"},
      {"missing.off", "OFF\n3 1 0\n0 0\n" + v3 + "3 0 1 2\n", ":3: missing z coordinate"},
      {"hex.off", "OFF\n3 1 0\n0x1 0 0\n" + v3 + "3 0 1 2\n", ":3: expected a number for the x"},
      {"twogon.off", "OFF\n3 1 0\n" + v3 + "2 0 1\n", ":6: face with 2 vertices"},
      {"shortface.off", "OFF\n3 1 0\n" + v3 + "4 0 1 2\n",
       ":6: face lists 4 vertices but has only 3"},
      {"fewfaces.off", "OFF\n3 2 0\n" + v3 + "3 0 1 2\n",
       "unexpected end of file: expected 2 faces"},
      {"fewvertices.off", "OFF\n4 1 0\n" + v3, "unexpected end of file: expected 4 vertices"},
      {"extraface.off", "OFF\n3 1 0\n" + v3 + "3 0 1 2\n3 2 1 0\n", ":7: unexpected content"},
      {"word.off", "OFF\n3 1 0\n" + v3 + "3 0 1 2 red\n", ":6: unexpected token 'red'"},
      {"4off.off", "4OFF\n3 1 0\n" + v3 + "3 0 1 2\n", ":1: unsupported OFF variant"},
      {"binary.off", "OFF BINARY\n3 1 0\n", ":1: binary OFF"},
      {"nolines.obj", "# only a comment\n", ": no faces"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n",
       ":4: vertex index 4 out of range"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4: vertex index 0"},
      {"before.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n", ":3: relative vertex index -3"},
      {"huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967297\n",
       ":4: vertex index 4294967297 exceeds"},
      {"twogon.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3: face with 2 vertices"},
      {"emptyf.obj", "v 0 0 0\nf\n", ":2: face with 0 vertices"},
      {"nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", ":2: non-finite z"},
      {"inf.obj", "v 0 0 0\nv 1 0 infinity\nv 0 1 0\nf 1 2 3\n", ":2: non-finite z"},
      {"missing.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1: missing z"},
      {"word.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", ":2: expected a number for the y"},
      {"ref.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n", ":4: expected a vertex reference"},
      {"unknown.obj", "v 0 0 0\nbogus 1 2\n", ":2: unknown OBJ statement 'bogus'"},
      {"nofaces.stl", "solid x\nendsolid x\n", ": no faces"},
      {"unterminated.stl", "solid x\n" + facet, ":5: unexpected end of file"},
      {"twovertex.stl", "solid x\n" + facet + "endloop\nendfacet\nendsolid\n",
       ":6: facet with 2 vertices"},
      {"nan.stl", "solid x\n" + facet + "vertex 0 1 nan\nendloop\nendfacet\nendsolid\n",
       ":6: non-finite z"},
      {"noendsolid.stl", "solid x\n" + facet + "vertex 0 1 0\nendloop\nendfacet\n",
       "expected 'facet' or 'endsolid'"},
      {"notstl.stl", "hello world\n", ": byte 12: truncated"},
      {"noply.ply", "plx\nformat ascii 1.0\nend_header\n", ":1: not a PLY file"},
      {"noheaderend.ply", "ply\nformat ascii 1.0\nelement vertex 3\n",
       ":3: unexpected end of file"},
      {"format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n",
       ":2: unknown PLY format"},
      {"type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n0\n",
       ":4: unknown PLY property type 'float128'"},
      {"noz.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 "
       "2\n",
       ":3: vertex element needs properties x, y and z"},
      {"floatindex.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar float vertex_indices\n"
       "end_header\n" +
           v3 + "3 0 1 2\n",
       ":7: vertex_indices must have an integer"},
      {"hugecount.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
       "property float x\nproperty float y\nproperty float z\nelement face 1\n"
       "property list uchar int vertex_indices\nend_header\n",
       ":3: element 'vertex' with"},
      {"uint32.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 5000000000\n"
       "property float x\nproperty float y\nproperty float z\nelement face 1\n"
       "property list uchar int vertex_indices\nend_header\n",
       ":3: vertex count 5000000000 exceeds"},
      {"hugeother.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement junk 1000000000000\nproperty int a\nelement face 1\n"
       "property list uchar int vertex_indices\nend_header\n" +
           v3 + "3 0 1 2\n",
       ":7: element 'junk' with 1000000000000 entries cannot fit"},
      {"range.ply", ply_head + v3 + "3 0 1 3\n", ":13: vertex index 3 of face 0 out of range"},
      {"negative.ply", ply_head + v3 + "3 0 -1 2\n", ":13: vertex index -1"},
      {"twogon.ply", ply_head + v3 + "2 0 1\n", ":13: face 0 has 2 vertices"},
      {"nan.ply", ply_head + "0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n", ":12: non-finite y"},
      {"short.ply", ply_head + v3 + "3 0 1\n", "unexpected end of file in element 'face' entry 0"},
      {"extra.ply", ply_head + v3 + "3 0 1 2\n7\n", ":14: unexpected data after the last element"},
      {"word.ply", ply_head + "0 0 0\n1 0 0\n0 one 0\n3 0 1 2\n",
       ":12: expected a number for the y"},
  };
  for (const Case& c : cases) {
    const std::string message = bad_file(dir, c.name, c.bytes);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << message << "\nexpected: " << c.expected;
  }
  fs::remove_all(dir);
}

TEST(MeshIoTest, MalformedBinaryCorpus) {
  const fs::path dir = test::temp_dir("mesh-io");
  const std::array<float, 9> tri = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string stl = binary_stl({tri, tri}, "");
  std::string lying = stl;
  lying.replace(80, 4, le(uint32_t{0xFFFFFFFFu}));
  bad_file(dir, "count.stl", lying);
  bad_file(dir, "zero.stl", binary_stl({}, ""));
  bad_file(dir, "inf.stl", binary_stl({tri, {0, 0, 0, 1, 0, 0, 0, INFINITY, 0}}, ""));
  bad_file(dir, "short.stl", std::string(83, '\0'));

  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  std::string vertices;
  for (float c : tri) vertices += le(c);
  const std::string face = le(uint8_t{3}) + le(0) + le(1) + le(2);
  EXPECT_EQ(read_text(dir, "ok.ply", header + vertices + face).face_count(), 1u);
  bad_file(dir, "trailing.ply", header + vertices + face + "\n");
  bad_file(dir, "range.ply", header + vertices + le(uint8_t{3}) + le(0) + le(1) + le(3));
  bad_file(dir, "negative.ply", header + vertices + le(uint8_t{3}) + le(0) + le(-1) + le(2));
  bad_file(dir, "twogon.ply", header + vertices + le(uint8_t{2}) + le(0) + le(1) + le(2));
  std::string nan_vertices = vertices;
  nan_vertices.replace(4, 4, le(NAN));
  bad_file(dir, "nan.ply", header + nan_vertices + face);
  fs::remove_all(dir);
}

/// Every prefix (in steps) of each valid file either fails or parses to a consistent mesh;
/// prefixes that cut a required part off must fail.
TEST(MeshIoTest, TruncatedFiles) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh mesh = holed_cube();
  for (const char* name : {"v.off", "v.obj", "v.ply", "v.stl"}) {
    SCOPED_TRACE(name);
    cover::write_mesh(dir / name, mesh);
    const std::string bytes = test::read_file(dir / name);
    const std::string ext = fs::path(name).extension().string();
    const bool binary = ext == ".ply" || ext == ".stl";
    const size_t last_line = bytes.rfind('\n', bytes.size() - 2) + 1;
    for (size_t length = 0; length < bytes.size(); ++length) {
      const fs::path cut = dir / ("cut" + ext);
      test::write_file(cut, bytes.substr(0, length));
      if (binary || (ext == ".off" && length < last_line))
        expect_input_error(cut);
      else
        expect_parses_or_throws(cut);
    }
  }
  const std::string elephant = test::read_file(test::cgal_mesh("elephant.off"));
  const size_t elephant_last_line = elephant.rfind('\n', elephant.size() - 2) + 1;
  for (size_t length = 0; length < elephant_last_line; length += 997) {
    test::write_file(dir / "elephant.off", elephant.substr(0, length));
    expect_input_error(dir / "elephant.off");
  }
  fs::remove_all(dir);
}

/// Random bytes, and valid files with random bytes overwritten, never crash the readers.
TEST(MeshIoTest, GarbageAndMutations) {
  const fs::path dir = test::temp_dir("mesh-io");
  const PolygonMesh mesh = holed_cube();
  std::mt19937 rng(12345);
  for (const char* ext : {".off", ".obj", ".ply", ".stl"}) {
    SCOPED_TRACE(ext);
    const fs::path path = dir / (std::string("g") + ext);
    for (int round = 0; round < 50; ++round) {
      std::string bytes(1 + rng() % 3000, '\0');
      for (char& c : bytes) c = static_cast<char>(rng());
      if (std::string(ext) == ".stl" && bytes.size() >= 84)  // no size matches this count
        bytes.replace(80, 4, le(uint32_t{0xFFFFFFFFu}));
      test::write_file(path, bytes);
      expect_input_error(path);
    }
    cover::write_mesh(dir / (std::string("valid") + ext), mesh);
    const std::string valid = test::read_file(dir / (std::string("valid") + ext));
    for (int round = 0; round < 300; ++round) {
      std::string bytes = valid;
      for (uint32_t k = 0, n = 1 + rng() % 4; k < n; ++k)
        bytes[rng() % bytes.size()] = static_cast<char>(rng());
      test::write_file(path, bytes);
      expect_parses_or_throws(path);
    }
  }
  fs::remove_all(dir);
}

// ---- small defects (issue 17, group 8) ------------------------------------------------------

fs::path data_file(const std::string& name) { return test::source_dir() / "tests" / "data" / name; }

/// The unit tetrahedron's 4 vertices and 4 faces, as read back.
void expect_tetrahedron(const PolygonMesh& mesh) {
  expect_consistent(mesh);
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.face_count(), 4u);
}

TEST(MeshIoTest, BomInEveryTextFormat) {
  // A UTF-8 byte order mark was refused in PLY and misread as binary in ASCII STL.
  expect_tetrahedron(cover::read_mesh(data_file("bom_ascii.stl")));
  expect_tetrahedron(cover::read_mesh(data_file("bom_ascii.ply")));
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string bom = "\xEF\xBB\xBF";
  const std::string v3 = "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_EQ(read_text(dir, "b.off", bom + "OFF\n3 1 0\n" + v3 + "3 0 1 2\n").face_count(), 1u);
  EXPECT_EQ(read_text(dir, "b.obj", bom + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").face_count(), 1u);
  // Binary PLY: the mark precedes the header, and byte offsets still count from the file start.
  std::string body;
  for (float c : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) body += le(c);
  const std::string header =
      bom +
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  EXPECT_EQ(
      read_text(dir, "b.ply", header + body + le(uint8_t{3}) + le(0) + le(1) + le(2)).face_count(),
      1u);
  const std::string message =
      bad_file(dir, "r.ply", header + body + le(uint8_t{3}) + le(0) + le(1) + le(3));
  EXPECT_NE(message.find(": byte " + std::to_string(header.size() + body.size() + 9)),
            std::string::npos)
      << message;
  fs::remove_all(dir);
}

TEST(MeshIoTest, BinaryStlTrailingBytesWarns) {
  // Refused before; now read, with one warning naming the file and the byte count.
  std::vector<std::string> warnings;
  const fs::path file = data_file("trailing_bytes.stl");
  expect_tetrahedron(cover::read_mesh(file, cover::kDefaultMaxMemoryBytes, &warnings));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], file.string() + ": 7 trailing bytes after the last triangle ignored");
  expect_tetrahedron(cover::read_mesh(file));  // no list given: the warning is dropped
  // Too short for its count is still an error, and an exact size gives no warning.
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string exact = test::read_file(file).substr(0, 84 + 4 * 50);
  warnings.clear();
  test::write_file(dir / "exact.stl", exact);
  expect_tetrahedron(cover::read_mesh(dir / "exact.stl", cover::kDefaultMaxMemoryBytes, &warnings));
  EXPECT_TRUE(warnings.empty());
  EXPECT_NE(
      bad_file(dir, "short.stl", exact.substr(0, exact.size() - 1)).find("declares 4 triangles"),
      std::string::npos);
  fs::remove_all(dir);
}

TEST(MeshIoTest, NumberRuleSameInEveryReader) {
  // A leading '+' and an underflowing literal (1e-400 → 0) are accepted everywhere, not refused
  // as out of range. Overflow is "out-of-range <axis> coordinate" in every format.
  const PolygonMesh off = cover::read_mesh(data_file("plus_and_underflow.off"));
  expect_tetrahedron(off);
  EXPECT_EQ(off.vertices[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(off.vertices[3], (Vec3{0, 0, 1}));
  const fs::path dir = test::temp_dir("mesh-io");
  const auto files = [](const std::string& a, const std::string& b, const std::string& c) {
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string stl = "solid s\nfacet normal 0 0 +1\nouter loop\n";
    return std::vector<std::pair<std::string, std::string>>{
        {"n.off", "OFF\n3 1 0\n" + a + "\n" + b + "\n" + c + "\n3 0 1 2\n"},
        {"n.obj", "v " + a + "\nv " + b + "\nv " + c + "\nf 1 2 3\n"},
        {"n.ply", ply + a + "\n" + b + "\n" + c + "\n3 0 1 2\n"},
        {"n.stl", stl + "vertex " + a + "\nvertex " + b + "\nvertex " + c +
                      "\nendloop\nendfacet\nendsolid s\n"}};
  };
  for (const auto& [name, bytes] : files("+0 -1e-400 0", "+1.5 0 0", "0 +1e+0 0")) {
    SCOPED_TRACE(name);
    const PolygonMesh mesh = read_text(dir, name, bytes);
    ASSERT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.vertices[0], (Vec3{0, 0, 0}));
    EXPECT_EQ(mesh.vertices[1], (Vec3{1.5, 0, 0}));
    EXPECT_EQ(mesh.vertices[2], (Vec3{0, 1, 0}));
  }
  for (const auto& [name, bytes] : files("0 0 0", "1 +1e400 0", "0 1 0")) {
    const std::string message = bad_file(dir, name, bytes);
    EXPECT_NE(message.find("out-of-range y coordinate '+1e400'"), std::string::npos) << message;
  }
  for (const auto& [name, bytes] : files("0 0 0", "1 0 +nan", "0 1 0")) {
    const std::string message = bad_file(dir, name, bytes);
    EXPECT_NE(message.find("non-finite z coordinate '+nan'"), std::string::npos) << message;
  }
  // Numbers that are read past (an OFF colour, an OBJ w, a skipped PLY property) obey it too.
  const std::string tail =
      bad_file(dir, "t.off", "OFF\n3 1 0\n0 0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_NE(tail.find(":3: out-of-range number '1e999'"), std::string::npos) << tail;
  EXPECT_EQ(read_text(dir, "w.obj", "v 0 0 0 +1e-999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").face_count(),
            1u);
  const std::string skipped =
      bad_file(dir, "s.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nproperty float w\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n0 0 0 1e400\n1 0 0 0\n0 1 0 0\n"
               "3 0 1 2\n");
  EXPECT_NE(skipped.find(":11: out-of-range number in element 'vertex' entry 0: '1e400'"),
            std::string::npos)
      << skipped;
  fs::remove_all(dir);
}

TEST(MeshIoTest, PlyFreeTextBeforeTheFirstElementIsAComment) {
  // assimp's PLY/Wuson.ply (Blender 2.47) has "Created by Blender3D 247 - www.blender.org, source
  // file: " as its third header line, without the comment keyword.
  const fs::path wuson = test::assimp_models() / "PLY/Wuson.ply";
  if (fs::exists(wuson)) {
    const PolygonMesh mesh = cover::read_mesh(wuson);
    EXPECT_EQ(mesh.vertices.size(), 11184u);
    EXPECT_EQ(mesh.face_count(), 3732u);
  }
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string tail =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const PolygonMesh mesh =
      read_text(dir, "created.ply", "ply\nformat ascii 1.0\nCreated by Blender3D 247\n" + tail);
  EXPECT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.face_count(), 1u);
  // After the first element an unknown keyword is still an error: a misspelt property line
  // would shift every value after it.
  const std::string misspelt =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "propety float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_NE(
      bad_file(dir, "misspelt.ply", misspelt).find(":6: unknown PLY header keyword 'propety'"),
      std::string::npos);
  fs::remove_all(dir);
}

TEST(MeshIoTest, VertexIndexOf2To63IsPrintedAsWritten) {
  // 2^63 does not fit a signed 64-bit index: every reader names the token as written, never a
  // negative number.
  const fs::path dir = test::temp_dir("mesh-io");
  const std::string big = "9223372036854775808";
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  const std::vector<std::pair<std::string, std::string>> files = {
      {"big.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 " + big + "\n"},
      {"big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " + big + "\n"},
      {"big.ply", ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 " + big + "\n"}};
  for (const auto& [name, bytes] : files) {
    const std::string message = bad_file(dir, name, bytes);
    EXPECT_NE(message.find("'" + big + "'"), std::string::npos) << message;
    EXPECT_EQ(message.find("-9223372036854775808"), std::string::npos) << message;
  }
  fs::remove_all(dir);
}

}  // namespace
