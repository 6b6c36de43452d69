// OBJ reader (Wavefront, polygon geometry only). Line-based; '#' starts a comment:
//   v x y z [numbers]      vertex; trailing numbers (w, colour) are ignored
//   f r0 r1 r2 ...         face with >= 3 references; a reference is i, i/t, i//n or i/t/n where
//                          i is 1-based, or negative: relative to the last vertex defined so far
//   vt vn vp g o s usemtl mtllib l p and the free-form curve/surface statements are ignored.
// Any other statement is an error (that is what binary garbage or a wrong format looks like).
// Positive indices may refer forward, so they are checked once the whole file is read; the
// message names the line where the largest index first appeared.

#include <algorithm>
#include <array>
#include <string>

#include "solid/detail/mesh_io_detail.h"

namespace cover::detail {
namespace {

/// Statements that carry no polygon geometry.
constexpr std::array<std::string_view, 31> kIgnored = {
    "vt",   "vn",   "vp",     "g",        "o",        "s",      "usemtl", "mtllib",
    "l",    "p",    "cstype", "deg",      "bmat",     "step",   "curv",   "curv2",
    "surf", "parm", "trim",   "hole",     "scrv",     "sp",     "end",    "con",
    "mg",   "lod",  "bevel",  "c_interp", "d_interp", "usemap", "maplib"};

/// True for the tail of a reference after the vertex index: "", "/t", "//n", "/t/n".
bool is_reference_tail(std::string_view tail) {
  if (tail.empty()) return true;
  if (tail[0] != '/') return false;
  return std::all_of(tail.begin(), tail.end(),
                     [](char c) { return (c >= '0' && c <= '9') || c == '-' || c == '/'; });
}

}  // namespace

PolygonMesh read_obj(const std::string& file, std::string_view data) {
  data = without_bom(data);
  PolygonMesh mesh;
  LineReader lines(data);
  std::string_view line;
  uint64_t max_index = 0;       // largest positive (1-based) index seen
  uint64_t max_index_line = 0;  // where it first appeared
  while (lines.next(line)) {
    const uint64_t n = lines.line_number();
    line = strip_comment(line);
    std::string_view keyword = next_token(line);
    if (keyword.empty()) continue;
    if (keyword == "v") {
      if (mesh.vertices.size() >= kMaxIndexCount) fail_line(file, n, "more than 2^32-1 vertices");
      Vec3 p;
      p.x = parse_coordinate(next_token(line), file, n, 'x');
      p.y = parse_coordinate(next_token(line), file, n, 'y');
      p.z = parse_coordinate(next_token(line), file, n, 'z');
      check_numeric_tail(line, file, n);
      mesh.vertices.push_back(p);
    } else if (keyword == "f") {
      const size_t first = mesh.face_vertices.size();
      const uint64_t defined = mesh.vertices.size();
      for (std::string_view token = next_token(line); !token.empty(); token = next_token(line)) {
        int64_t index = 0;
        const char* end = token.data() + token.size();
        auto [ptr, ec] = std::from_chars(token.data(), end, index);
        if (ec != std::errc() || !is_reference_tail({ptr, static_cast<size_t>(end - ptr)}))
          fail_line(file, n, "expected a vertex reference, found " + quote(token));
        uint64_t resolved;
        if (index == 0) {
          fail_line(file, n, "vertex index 0 is invalid (OBJ indices start at 1)");
        } else if (index < 0) {
          const uint64_t back = 0 - static_cast<uint64_t>(index);
          if (back > defined)
            fail_line(file, n,
                      "relative vertex index " + std::to_string(index) +
                          " reaches before the first vertex (" + std::to_string(defined) +
                          " defined so far)");
          resolved = defined - back;
        } else {
          const auto one_based = static_cast<uint64_t>(index);
          if (one_based > kMaxIndexCount)
            fail_line(file, n, "vertex index " + std::to_string(index) + " exceeds 2^32-1");
          if (one_based > max_index) {
            max_index = one_based;
            max_index_line = n;
          }
          resolved = one_based - 1;
        }
        mesh.face_vertices.push_back(static_cast<uint32_t>(resolved));
      }
      const size_t size = mesh.face_vertices.size() - first;
      if (size < 3)
        fail_line(file, n, "face with " + std::to_string(size) + " vertices (at least 3 needed)");
      if (mesh.face_vertices.size() > kMaxIndexCount)
        fail_line(file, n, "more than 2^32-1 face vertices in total");
      mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
    } else if (std::find(kIgnored.begin(), kIgnored.end(), keyword) == kIgnored.end()) {
      fail_line(file, n, "unknown OBJ statement " + quote(keyword));
    }
  }
  if (mesh.face_count() == 0) fail_file(file, "no faces");
  if (max_index > mesh.vertices.size())
    fail_line(file, max_index_line,
              "vertex index " + std::to_string(max_index) + " out of range (the file has " +
                  std::to_string(mesh.vertices.size()) + " vertices)");
  return mesh;
}

}  // namespace cover::detail
