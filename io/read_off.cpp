// OFF reader (Geomview Object File Format, ASCII). Line-based; '#' starts a comment and blank
// lines are skipped:
//   [ST][C][N]OFF [V F [E]]     optional header keyword; the counts may follow on the same line
//   V F [E]                     counts (E is ignored)
//   V lines  x y z [numbers]    trailing numbers (normal, colour, texture coordinates) ignored
//   F lines  n i0 .. i(n-1) [numbers]   0-based indices, n >= 3; a trailing colour is ignored
// Before reserving memory the counts are checked against the bytes left in the file: a vertex
// line takes at least 6 bytes ("0 0 0\n") and a face line at least 7 ("3 0 1 2").
// A body of 256 KiB or more is parsed in parallel (read_body_parallel), the same mesh as serially.

#include <algorithm>
#include <atomic>
#include <string>
#include <vector>

#include "cover/io/parse.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::detail {
namespace {

constexpr uint64_t kMinVertexBytes = 6;
constexpr uint64_t kMinFaceBytes = 7;
/// Bodies (vertex and face lines) of at least this many bytes are read in parallel.
constexpr uint64_t kParallelBytes = uint64_t{1} << 18;

/// Line source that skips blank lines and strips comments.
class ContentLines {
 public:
  explicit ContentLines(std::string_view data) : lines_(data) {}
  /// Next line with content (comment removed); false at the end of the file.
  bool next(std::string_view& line) {
    while (lines_.next(line)) {
      line = strip_comment(line);
      if (!only_blanks(line)) return true;
    }
    return false;
  }
  uint64_t line_number() const { return lines_.line_number(); }
  uint64_t bytes_left() const { return lines_.bytes_left(); }

 private:
  LineReader lines_;
};

/// True when `token` is an OFF header keyword; throws for variants this reader does not support.
bool is_header_keyword(std::string_view token, const std::string& file, uint64_t line) {
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
  std::string_view prefix = token.substr(0, token.size() - 3);
  if (prefix.starts_with("ST")) prefix.remove_prefix(2);
  if (prefix.starts_with("C")) prefix.remove_prefix(1);
  if (prefix.starts_with("N")) prefix.remove_prefix(1);
  if (!prefix.empty())
    fail_line(
        file, line,
        "unsupported OFF variant " + quote(token) + " (expected OFF, COFF, NOFF, CNOFF or STOFF)");
  return true;
}

uint64_t parse_count(std::string_view token, const std::string& file, uint64_t line,
                     const char* what) {
  if (token.empty()) fail_line(file, line, std::string("missing ") + what);
  uint64_t value;
  if (!parse_integer(token, value))
    fail_line(file, line, std::string("expected the ") + what + ", found " + quote(token));
  return value;
}

/// The vertex and face lines of a large file (what follows the counts line) read in parallel:
/// content lines are found per chunk of about kChunkBytes (chunks end at a newline), then
/// vertices and faces are parsed in fixed ranges and the faces' indices placed by prefix sums.
/// The lines mean exactly what the serial loop in read_off() reads. Returns false on anything
/// unexpected (a bad token, a count that does not match): the serial loop then reads the file
/// again and reports its first error with its line number, so errors do not depend on this path.
bool read_body_parallel(std::string_view body, uint64_t vertex_count, uint64_t face_count,
                        const std::string& file, PolygonMesh& mesh) {
  const std::vector<std::string_view> pieces = line_chunks(body, size_t{1} << 16);
  const size_t chunks = pieces.size();
  std::vector<std::vector<std::string_view>> content(chunks);
  parallel_for(chunks, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) {
      LineReader lines(pieces[c]);
      std::string_view line;
      while (lines.next(line)) {  // as ContentLines::next
        line = strip_comment(line);
        if (!only_blanks(line)) content[c].push_back(line);
      }
    }
  });
  std::vector<std::string_view> all;
  for (const auto& c : content) all.insert(all.end(), c.begin(), c.end());
  content = {};
  if (all.size() != vertex_count + face_count) return false;
  std::atomic<bool> failed{false};
  constexpr size_t kGrain = size_t{1} << 12;
  mesh.vertices.resize(vertex_count);
  parallel_for(vertex_count, kGrain, [&](size_t begin, size_t end) {
    try {
      for (size_t v = begin; v < end; ++v) {
        std::string_view line = all[v];
        Vec3& p = mesh.vertices[v];
        p.x = parse_coordinate(next_token(line), file, 0, 'x');
        p.y = parse_coordinate(next_token(line), file, 0, 'y');
        p.z = parse_coordinate(next_token(line), file, 0, 'z');
        check_numeric_tail(line, file, 0);
      }
    } catch (const InputError&) {
      failed = true;
    }
  });
  if (failed) return false;
  // Faces in ranges of kGrain: each range's sizes and indices, then placed by prefix sums.
  const size_t ranges = (face_count + kGrain - 1) / kGrain;
  std::vector<std::vector<uint32_t>> sizes(ranges), indices(ranges);
  parallel_for(face_count, kGrain, [&](size_t begin, size_t end) {
    const size_t r = begin / kGrain;
    try {
      sizes[r].reserve(end - begin);
      indices[r].reserve(3 * (end - begin));
      for (size_t f = begin; f < end; ++f) {
        std::string_view line = all[vertex_count + f];
        uint64_t size;
        if (!parse_integer(next_token(line), size) || size < 3 || size > kMaxIndexCount) {
          failed = true;
          return;
        }
        for (uint64_t k = 0; k < size; ++k) {
          int64_t index;
          if (!parse_integer(next_token(line), index) || index < 0 ||
              static_cast<uint64_t>(index) >= vertex_count) {
            failed = true;
            return;
          }
          indices[r].push_back(static_cast<uint32_t>(index));
        }
        check_numeric_tail(line, file, 0);
        sizes[r].push_back(static_cast<uint32_t>(size));
      }
    } catch (const InputError&) {
      failed = true;
    }
  });
  if (failed) return false;
  std::vector<uint64_t> offset(ranges + 1, 0);
  for (size_t r = 0; r < ranges; ++r) offset[r + 1] = offset[r] + indices[r].size();
  if (offset[ranges] > kMaxIndexCount) return false;
  mesh.face_start.resize(face_count + 1);
  mesh.face_vertices.resize(offset[ranges]);
  parallel_for(ranges, 1, [&](size_t begin, size_t end) {
    for (size_t r = begin; r < end; ++r) {
      uint32_t at = static_cast<uint32_t>(offset[r]);
      std::copy(indices[r].begin(), indices[r].end(), mesh.face_vertices.begin() + at);
      for (size_t k = 0; k < sizes[r].size(); ++k) {
        at += sizes[r][k];
        mesh.face_start[r * kGrain + k + 1] = at;
      }
    }
  });
  return true;
}

}  // namespace

PolygonMesh read_off(const std::string& file, std::string_view data) {
  data = without_bom(data);
  ContentLines lines(data);
  std::string_view line;
  if (!lines.next(line)) fail_line(file, lines.line_number(), "no OFF header or counts");
  std::string_view rest = line;
  std::string_view first = next_token(rest);
  if (is_header_keyword(first, file, lines.line_number())) {
    if (only_blanks(rest) && !lines.next(rest))
      fail_line(file, lines.line_number(),
                "unexpected end of file: missing vertex and face counts");
    std::string_view peek = rest;
    if (next_token(peek) == "BINARY")
      fail_line(file, lines.line_number(), "binary OFF is not supported");
  } else {
    rest = line;
  }
  const uint64_t count_line = lines.line_number();
  const uint64_t vertex_count = parse_count(next_token(rest), file, count_line, "vertex count");
  const uint64_t face_count = parse_count(next_token(rest), file, count_line, "face count");
  std::string_view edges = next_token(rest);
  if (!edges.empty()) parse_count(edges, file, count_line, "edge count");
  std::string_view extra = next_token(rest);
  if (!extra.empty())
    fail_line(file, count_line, "unexpected token " + quote(extra) + " after the counts");

  if (vertex_count > kMaxIndexCount)
    fail_line(file, count_line, "vertex count " + std::to_string(vertex_count) + " exceeds 2^32-1");
  if (face_count == 0) fail_line(file, count_line, "no faces (face count is 0)");
  const uint64_t left = lines.bytes_left();
  if (!fits(vertex_count, kMinVertexBytes, left) ||
      !fits(face_count, kMinFaceBytes, left - vertex_count * kMinVertexBytes))
    fail_line(file, count_line,
              std::to_string(vertex_count) + " vertices and " + std::to_string(face_count) +
                  " faces cannot fit in the " + std::to_string(left) + " bytes left in the file");

  // A large body is read in parallel (read_body_parallel); any error there: read serially below.
  if (left >= kParallelBytes) {
    PolygonMesh mesh;
    if (read_body_parallel(data.substr(data.size() - left), vertex_count, face_count, file, mesh))
      return mesh;
  }
  PolygonMesh mesh;
  mesh.vertices.reserve(vertex_count);
  mesh.face_start.reserve(face_count + 1);
  mesh.face_vertices.reserve(3 * face_count);

  for (uint64_t v = 0; v < vertex_count; ++v) {
    if (!lines.next(line))
      fail_line(file, lines.line_number(),
                "unexpected end of file: expected " + std::to_string(vertex_count) +
                    " vertices, found " + std::to_string(v));
    const uint64_t n = lines.line_number();
    Vec3 p;
    p.x = parse_coordinate(next_token(line), file, n, 'x');
    p.y = parse_coordinate(next_token(line), file, n, 'y');
    p.z = parse_coordinate(next_token(line), file, n, 'z');
    check_numeric_tail(line, file, n);
    mesh.vertices.push_back(p);
  }

  for (uint64_t f = 0; f < face_count; ++f) {
    if (!lines.next(line))
      fail_line(file, lines.line_number(),
                "unexpected end of file: expected " + std::to_string(face_count) +
                    " faces, found " + std::to_string(f));
    const uint64_t n = lines.line_number();
    const uint64_t size = parse_count(next_token(line), file, n, "number of face vertices");
    if (size < 3)
      fail_line(file, n, "face with " + std::to_string(size) + " vertices (at least 3 needed)");
    for (uint64_t k = 0; k < size; ++k) {
      std::string_view token = next_token(line);
      if (token.empty())
        fail_line(file, n,
                  "face lists " + std::to_string(size) + " vertices but has only " +
                      std::to_string(k) + " indices");
      int64_t index;
      if (!parse_integer(token, index))
        fail_line(file, n, "expected a vertex index, found " + quote(token));
      if (index < 0 || static_cast<uint64_t>(index) >= vertex_count)
        fail_line(file, n,
                  "vertex index " + std::to_string(index) + " out of range [0, " +
                      std::to_string(vertex_count) + ")");
      mesh.face_vertices.push_back(static_cast<uint32_t>(index));
    }
    check_numeric_tail(line, file, n);
    if (mesh.face_vertices.size() > kMaxIndexCount)
      fail_line(file, n, "more than 2^32-1 face vertices in total");
    mesh.face_start.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
  }

  if (lines.next(line))
    fail_line(file, lines.line_number(),
              "unexpected content after the last face " + quote(line) + " (wrong counts?)");
  return mesh;
}

}  // namespace cover::detail
