// Mesh reading: extension dispatch and the helpers shared by the readers (io/parse.h).
//
// Why the readers are hand-written instead of using CGAL::IO::read_polygon_soup or assimp:
//   * errors: every malformed input becomes one InputError line naming the file and the line
//     (text) or byte / triangle (binary); read_polygon_soup returns a bare `false` (checked on
//     assimp's invalid/OutOfMemory.off and malformed.obj, and on out-of-range indices);
//   * bounded allocation: header counts are checked against the file size before anything is
//     reserved, so a 40-byte file claiming 10^9 faces is refused instead of allocating gigabytes;
//   * speed: the file is read whole and parsed in place with std::from_chars (only a regular
//     file, no larger than the memory limit: solid/memory_limit.h).
// Parsing in place reads an OFF about 11× faster than CGAL::IO::read_polygon_soup (median of 21
// reads from the page cache; docs/benchmarks.md#mesh-readers).

#include "cover/io/mesh_io.h"

#include <string>

#include "cover/io/parse.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"

namespace cover {
namespace detail {

std::string quote(std::string_view token) {
  constexpr size_t kMaxShown = 40;
  std::string out = "'";
  for (size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (token.size() > kMaxShown) out += "...";
  out += "'";
  return out;
}

void fail_line(const std::string& file, uint64_t line, const std::string& message) {
  throw InputError(file + ":" + std::to_string(line) + ": " + message);
}

void fail_byte(const std::string& file, uint64_t byte, const std::string& message) {
  throw InputError(file + ": byte " + std::to_string(byte) + ": " + message);
}

void fail_file(const std::string& file, const std::string& message) {
  throw InputError(file + ": " + message);
}

bool literal_overflows(std::string_view literal) {
  // The decimal exponent E of the first significant digit (value = d.ddd·10^E): overflow needs
  // E ≥ 308 and underflow E ≤ −324, so its sign decides. The literal is valid (from_chars read
  // all of it): [-] digits [. digits] [(e|E) [+|-] digits], with a nonzero digit.
  size_t i = literal.starts_with('-') ? 1 : 0;
  int64_t before_point = 0, digits = 0, first_significant = -1;
  bool point = false;
  for (; i < literal.size() && literal[i] != 'e' && literal[i] != 'E'; ++i) {
    if (literal[i] == '.') {
      point = true;
      continue;
    }
    if (first_significant < 0 && literal[i] != '0') first_significant = digits;
    ++digits;
    before_point += !point;
  }
  int64_t exponent = 0;
  bool negative = false;
  if (i < literal.size()) {
    ++i;
    negative = i < literal.size() && literal[i] == '-';
    if (i < literal.size() && (literal[i] == '-' || literal[i] == '+')) ++i;
    for (; i < literal.size(); ++i)  // saturated: far beyond any double's exponent
      exponent = std::min<int64_t>(10 * exponent + (literal[i] - '0'), int64_t{1} << 40);
  }
  return before_point - 1 - first_significant + (negative ? -exponent : exponent) > 0;
}

void fail_coordinate(std::string_view token, const std::string& file, uint64_t line, char axis) {
  const std::string what = std::string(1, axis) + " coordinate";
  if (token.empty()) fail_line(file, line, "missing " + what);
  double value;
  switch (parse_number(token, value)) {
    case NumberStatus::kNotANumber:
      fail_line(file, line, "expected a number for the " + what + ", found " + quote(token));
    case NumberStatus::kOutOfRange:
      fail_line(file, line, "out-of-range " + what + " " + quote(token));
    case NumberStatus::kOk:
      break;
  }
  fail_line(file, line, "non-finite " + what + " " + quote(token));
}

void check_numeric_tail(std::string_view rest, const std::string& file, uint64_t line) {
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    double ignored;
    const NumberStatus status = parse_number(token, ignored);
    if (status == NumberStatus::kOutOfRange)
      fail_line(file, line, "out-of-range number " + quote(token));
    if (status == NumberStatus::kNotANumber)
      fail_line(file, line, "unexpected token " + quote(token));
  }
}

std::string unsupported_format(const std::filesystem::path& path) {
  return "unsupported mesh format " + quote(path.extension().string()) +
         " (expected .obj, .off, .stl, .ply)";
}

}  // namespace detail

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

bool is_mesh_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".obj" || ext == ".off" || ext == ".stl" || ext == ".ply";
}

bool is_mesh_output_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return is_mesh_extension(path) || ext == ".gltf" || ext == ".glb" || ext == ".3mf";
}

PolygonMesh read_mesh(const std::filesystem::path& path, uint64_t max_file_bytes,
                      std::vector<std::string>* warnings) {
  const std::string file = path.string();
  const std::string ext = lower_extension(path);
  if (!is_mesh_extension(path)) detail::fail_file(file, detail::unsupported_format(path));
  const FileBytes data = read_regular_file(path, max_file_bytes);
  if (data.empty()) detail::fail_file(file, "empty file");
  if (ext == ".off") return detail::read_off(file, data);
  if (ext == ".obj") return detail::read_obj(file, data);
  if (ext == ".stl") return detail::read_stl(file, data, warnings);
  return detail::read_ply(file, data);
}

PolygonMesh read_mesh_with_uvs(const std::filesystem::path& path, std::vector<double>& uvs,
                               uint64_t max_file_bytes, std::vector<std::string>* warnings) {
  uvs.clear();
  if (lower_extension(path) != ".obj") return read_mesh(path, max_file_bytes, warnings);
  const FileBytes data = read_regular_file(path, max_file_bytes);
  if (data.empty()) detail::fail_file(path.string(), "empty file");
  return detail::read_obj(path.string(), data, &uvs);
}

}  // namespace cover
