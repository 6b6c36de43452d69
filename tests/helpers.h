#pragma once
// Shared test helpers: model locations, temp folders, running the CLI.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace cover::test {

/// Stride through the cases of the heaviest randomized tests: every case in Release, every
/// fourth in the checked build (ASan + UBSan at -O1, about 10× slower), which hunts memory and
/// undefined-behaviour errors on the same code paths rather than rare answers.
#ifdef COVER_SANITIZED
inline constexpr int kCheckedStride = 4;
#else
inline constexpr int kCheckedStride = 1;
#endif

inline std::filesystem::path source_dir() { return COVER_SOURCE_DIR; }
/// libcgal-demo meshes (extracted at configure time), e.g. cgal_mesh("elephant.off").
inline std::filesystem::path cgal_mesh(const std::string& name) {
  return std::filesystem::path(COVER_CGAL_MESHES) / name;
}
inline std::filesystem::path assimp_models() { return COVER_ASSIMP_MODELS; }

/// A fresh empty folder under the system temp dir, unique per call.
inline std::filesystem::path temp_dir(const std::string& tag) {
  static std::mt19937_64 rng(std::random_device{}());
  auto dir =
      std::filesystem::temp_directory_path() / ("cover-test-" + tag + "-" + std::to_string(rng()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct RunResult {
  int status = -1;  ///< exit status
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// Runs `cover ARGS` (a shell-quoted argument string), capturing stdout and stderr. `shell_prefix`
/// goes before the command, e.g. "ulimit -v 2097152; timeout 20 " to cap memory and time.
inline RunResult run_cover(const std::string& args, const std::string& stdin_text = "",
                           const std::string& shell_prefix = "") {
  auto dir = temp_dir("run");
  auto out = dir / "out", err = dir / "err", in = dir / "in";
  write_file(in, stdin_text);
  std::string cmd = shell_prefix + "'" + COVER_BIN + "' " + args + " <'" + in.string() + "' >'" +
                    out.string() + "' 2>'" + err.string() + "'";
  int raw = std::system(cmd.c_str());
  RunResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = read_file(out);
  r.err = read_file(err);
  std::filesystem::remove_all(dir);
  return r;
}

}  // namespace cover::test

#include "cover/solid/polygon_mesh.h"

namespace cover::test {

/// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward, volume 1/6.
inline PolygonMesh unit_tetrahedron() {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.add_face({0, 2, 1});
  m.add_face({0, 1, 3});
  m.add_face({0, 3, 2});
  m.add_face({1, 2, 3});
  return m;
}

/// Fan-triangulates every face (for faces without false edges).
inline PolygonMesh triangulate(const PolygonMesh& m) {
  PolygonMesh t;
  t.vertices = m.vertices;
  for (size_t f = 0; f < m.face_count(); ++f) {
    auto face = m.face(f);
    for (size_t i = 1; i + 1 < face.size(); ++i) t.add_face({face[0], face[i], face[i + 1]});
  }
  return t;
}

/// A box [lo, hi]³ with a square through-hole [hlo, hhi]² along z ("picture frame"): the top
/// and bottom faces are single faces whose hole loop is joined by false edges
/// ([Segura2004 §3 Fig. 1]).
inline PolygonMesh frame_box(double lo, double hi, double hlo, double hhi) {
  PolygonMesh m;
  // Outer corners 0..7 (bit0 x, bit1 y, bit2 z), inner corners 8..15 likewise.
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) ? hi : lo, (i & 2) ? hi : lo, (i & 4) ? hi : lo});
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) ? hhi : hlo, (i & 2) ? hhi : hlo, (i & 4) ? hi : lo});
  // Top (z = hi, normal +z): outer loop CCW 4,5,7,6, false edge 4→12, hole loop CW 12,14,15,13,
  // back along the false edge 12→4.
  m.add_face({4, 5, 7, 6, 4, 12, 14, 15, 13, 12});
  // Bottom (z = lo, normal −z): outer CW seen from above 0,2,3,1, hole 8,9,11,10.
  m.add_face({0, 2, 3, 1, 0, 8, 9, 11, 10, 8});
  // Outer sides.
  m.add_face({0, 1, 5, 4});
  m.add_face({2, 6, 7, 3});
  m.add_face({0, 4, 6, 2});
  m.add_face({1, 3, 7, 5});
  // Hole walls, normals pointing into the hole (away from the material).
  m.add_face({8, 12, 13, 9});    // y = hlo wall, normal +y
  m.add_face({10, 11, 15, 14});  // y = hhi wall, normal −y
  m.add_face({8, 10, 14, 12});   // x = hlo wall, normal +x
  m.add_face({9, 13, 15, 11});   // x = hhi wall, normal −x
  return m;
}

}  // namespace cover::test
