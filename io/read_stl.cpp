// STL reader, binary and ASCII. A file is binary when its size is exactly 84 + 50·n where n is
// the little-endian uint32 at byte 80 (a "solid" prefix alone does not make a file ASCII: many
// binary writers start the 80-byte header with it). Otherwise it is ASCII when it starts with
// "solid" (after an optional UTF-8 byte order mark and blanks) and its first 84 bytes hold no NUL;
// failing that, a file longer than 84 + 50·n is binary with trailing bytes, which are ignored
// with a warning (some exporters pad or append metadata). ASCII:
//   solid [name]
//     facet normal nx ny nz        (the normal is checked to be numeric and ignored)
//       outer loop
//         vertex x y z             (three or more)
//       endloop
//     endfacet
//   endsolid [name]                (several solids may follow each other)
// Keywords are case-insensitive. Vertices are welded by exact coordinate equality (−0 == +0),
// so a closed STL surface becomes an indexed mesh; triangles keep their vertex order, and a
// triangle whose corners weld together keeps its repeated index.
// Binary triangle records: normal (3 float), 3 × vertex (3 float), uint16 attribute, 50 bytes.

#include <bit>
#include <string>
#include <unordered_map>

#include "cover/io/parse.h"

namespace cover::detail {
namespace {

constexpr uint64_t kHeaderBytes = 84;
constexpr uint64_t kTriangleBytes = 50;

/// Maps coordinates to vertex indices, adding new vertices to the mesh.
class Welder {
 public:
  explicit Welder(PolygonMesh& mesh, size_t expected) : mesh_(mesh) { index_.reserve(expected); }
  /// Index of `p`; false when a new vertex would exceed the uint32 index range.
  bool add(Vec3 p, uint32_t& index) {
    auto [it, inserted] = index_.try_emplace(p, static_cast<uint32_t>(mesh_.vertices.size()));
    if (inserted) {
      if (mesh_.vertices.size() >= kMaxIndexCount) return false;
      mesh_.vertices.push_back(p);
    }
    index = it->second;
    return true;
  }

 private:
  PolygonMesh& mesh_;
  std::unordered_map<Vec3, uint32_t, Vec3Hash> index_;
};

float load_float(const char* bytes) {
  uint32_t bits;
  std::memcpy(&bits, bytes, 4);
  if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
  return std::bit_cast<float>(bits);
}

uint32_t load_u32(const char* bytes) {
  uint32_t value;
  std::memcpy(&value, bytes, 4);
  if constexpr (std::endian::native == std::endian::big) value = __builtin_bswap32(value);
  return value;
}

PolygonMesh read_binary(const std::string& file, std::string_view data, uint64_t count) {
  if (count == 0) fail_byte(file, 80, "no faces (triangle count is 0)");
  PolygonMesh mesh;
  mesh.face_start.reserve(count + 1);
  mesh.face_vertices.reserve(3 * count);
  Welder welder(mesh, count / 2 + 3);
  for (uint64_t t = 0; t < count; ++t) {
    const uint64_t offset = kHeaderBytes + t * kTriangleBytes;
    const char* record = data.data() + offset;
    for (size_t corner = 0; corner < 3; ++corner) {
      const char* xyz = record + 12 + 12 * corner;
      Vec3 p{load_float(xyz), load_float(xyz + 4), load_float(xyz + 8)};
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail_file(file, "triangle " + std::to_string(t + 1) + " (byte " +
                            std::to_string(offset + 12 + 12 * corner) +
                            "): non-finite vertex coordinate");
      uint32_t index;
      if (!welder.add(p, index))
        fail_file(file, "triangle " + std::to_string(t + 1) + ": more than 2^32-1 vertices");
      mesh.face_vertices.push_back(index);
    }
    mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
  }
  return mesh;
}

/// ASCII-case-insensitive comparison with a lower-case keyword.
bool keyword_is(std::string_view token, std::string_view lower) {
  if (token.size() != lower.size()) return false;
  for (size_t i = 0; i < token.size(); ++i) {
    char c = token[i];
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c != lower[i]) return false;
  }
  return true;
}

PolygonMesh read_ascii(const std::string& file, std::string_view data) {
  enum class State { kOutside, kSolid, kFacet, kLoop, kLoopDone };
  static constexpr const char* kExpected[] = {"'solid'", "'facet' or 'endsolid'", "'outer loop'",
                                              "'vertex' or 'endloop'", "'endfacet'"};
  PolygonMesh mesh;
  Welder welder(mesh, data.size() / 256);
  LineReader lines(data);
  std::string_view line;
  State state = State::kOutside;
  size_t loop_start = 0;
  while (lines.next(line)) {
    const uint64_t n = lines.line_number();
    std::string_view keyword = next_token(line);
    if (keyword.empty()) continue;
    auto unexpected = [&] {
      fail_line(file, n,
                "expected " + std::string(kExpected[static_cast<int>(state)]) + ", found " +
                    quote(keyword));
    };
    switch (state) {
      case State::kOutside:
        if (!keyword_is(keyword, "solid")) unexpected();
        state = State::kSolid;
        break;
      case State::kSolid:
        if (keyword_is(keyword, "endsolid")) {
          state = State::kOutside;
          break;
        }
        if (!keyword_is(keyword, "facet")) unexpected();
        if (std::string_view normal = next_token(line); !normal.empty()) {
          if (!keyword_is(normal, "normal"))
            fail_line(file, n, "expected 'normal', found " + quote(normal));
          for (char axis : {'x', 'y', 'z'}) {
            double ignored;
            std::string_view token = next_token(line);
            if (!parse_double(token, ignored)) fail_coordinate(token, file, n, axis);
          }
        }
        if (!only_blanks(line)) fail_line(file, n, "unexpected text after the facet normal");
        state = State::kFacet;
        break;
      case State::kFacet:
        if (!keyword_is(keyword, "outer") || !keyword_is(next_token(line), "loop")) unexpected();
        loop_start = mesh.face_vertices.size();
        state = State::kLoop;
        break;
      case State::kLoop:
        if (keyword_is(keyword, "endloop")) {
          const size_t size = mesh.face_vertices.size() - loop_start;
          if (size < 3)
            fail_line(file, n,
                      "facet with " + std::to_string(size) + " vertices (at least 3 needed)");
          state = State::kLoopDone;
          break;
        }
        if (!keyword_is(keyword, "vertex")) unexpected();
        {
          Vec3 p;
          p.x = parse_coordinate(next_token(line), file, n, 'x');
          p.y = parse_coordinate(next_token(line), file, n, 'y');
          p.z = parse_coordinate(next_token(line), file, n, 'z');
          if (!only_blanks(line)) fail_line(file, n, "unexpected text after the vertex");
          uint32_t index;
          if (!welder.add(p, index)) fail_line(file, n, "more than 2^32-1 vertices");
          mesh.face_vertices.push_back(index);
          if (mesh.face_vertices.size() > kMaxIndexCount)
            fail_line(file, n, "more than 2^32-1 face vertices in total");
        }
        break;
      case State::kLoopDone:
        if (!keyword_is(keyword, "endfacet")) unexpected();
        mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
        state = State::kSolid;
        break;
    }
  }
  if (state != State::kOutside)
    fail_line(
        file, lines.line_number(),
        "unexpected end of file: expected " + std::string(kExpected[static_cast<int>(state)]));
  if (mesh.face_count() == 0) fail_file(file, "no faces");
  return mesh;
}

}  // namespace

PolygonMesh read_stl(const std::string& file, std::string_view data,
                     std::vector<std::string>* warnings) {
  const uint64_t count = data.size() >= kHeaderBytes ? load_u32(data.data() + 80) : 0;
  const uint64_t needed = kHeaderBytes + count * kTriangleBytes;
  if (data.size() >= kHeaderBytes && data.size() == needed) return read_binary(file, data, count);
  const std::string_view text = without_bom(data);
  std::string_view start = text;
  while (!start.empty() && (is_blank(start.front()) || start.front() == '\n'))
    start.remove_prefix(1);
  // ASCII STL has no NUL byte; a binary header that starts with "solid" is followed by one in
  // the (small) triangle count, so such a file is read as binary below.
  const bool has_nul = data.substr(0, kHeaderBytes).find('\0') != std::string_view::npos;
  if (start.size() >= 5 && keyword_is(start.substr(0, 5), "solid") && !has_nul)
    return read_ascii(file, text);
  if (data.size() < kHeaderBytes)
    fail_byte(file, data.size(), "truncated: neither ASCII STL nor a binary STL header (84 bytes)");
  if (data.size() < needed)
    fail_byte(file, 80,
              "binary STL declares " + std::to_string(count) + " triangles, which need " +
                  std::to_string(needed) + " bytes, but the file has " +
                  std::to_string(data.size()));
  PolygonMesh mesh = read_binary(file, data, count);
  if (warnings)
    warnings->push_back(file + ": " + std::to_string(data.size() - needed) +
                        " trailing bytes after the last triangle ignored");
  return mesh;
}

}  // namespace cover::detail
