#pragma once
// Internals shared by the mesh readers and the writer (mesh_io.cpp, read_*.cpp, write_mesh.cpp),
// and by the other readers that follow the same text rules (io/scene.cpp, cli/points.cpp);
// not part of the public API.
// Notation:
//   file   the path as the caller gave it, used verbatim as the prefix of every error message
//   data   the whole file contents (read once, parsed in place)
//   line   1-based line number (text formats); byte: 0-based offset (binary formats)
// Every error is a cover::InputError with a one-line what(): tokens copied from the file go
// through quote(), which escapes control and non-ASCII bytes and truncates long tokens.
//
// One rule for every text reader — OFF, OBJ, ASCII PLY, ASCII STL and the points files of
// `cover classify` (cli/points.cpp); JSON scenes (io/scene.cpp) follow it where JSON's own
// grammar allows:
//   * a UTF-8 byte order mark at the start of the file is skipped;
//   * a number is a whole token in std::from_chars' general format (decimal or scientific,
//     "inf", "infinity", "nan" in any case), optionally with one leading '+' (JSON: none);
//     hexadecimal and other forms are not numbers;
//   * a literal whose value overflows a double (1e400) is an error, "out-of-range x coordinate"
//     (other numbers: "out-of-range number"), never inf; one that underflows becomes a subnormal
//     or ±0 and is accepted;
//   * coordinates must be finite: inf and nan are refused as "non-finite x coordinate".

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/vec3_hash.h"

namespace cover::detail {

/// Largest vertex count / face-vertex count a PolygonMesh can index (uint32 offsets).
inline constexpr uint64_t kMaxIndexCount = 0xFFFFFFFFull;

/// The unsupported-extension message: "unsupported mesh format '.3ds' (expected ...)".
std::string unsupported_format(const std::filesystem::path& path);

/// Printable, single-line, length-limited rendering of a token, in single quotes.
std::string quote(std::string_view token);

/// Throws InputError "FILE:LINE: message".
[[noreturn]] void fail_line(const std::string& file, uint64_t line, const std::string& message);
/// Throws InputError "FILE: byte N: message".
[[noreturn]] void fail_byte(const std::string& file, uint64_t byte, const std::string& message);
/// Throws InputError "FILE: message" (whole-file problems: empty file, no faces).
[[noreturn]] void fail_file(const std::string& file, const std::string& message);

/// True when count * unit <= available (no overflow).
inline bool fits(uint64_t count, uint64_t unit, uint64_t available) {
  return unit == 0 || count <= available / unit;
}

/// Splits a text buffer into lines ("\n" or "\r\n" terminated; the last may be unterminated).
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}

  /// Next line without its terminator; false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const char* begin = text_.data() + pos_;
    size_t left = text_.size() - pos_;
    const void* newline = std::memchr(begin, '\n', left);
    size_t length = newline ? static_cast<size_t>(static_cast<const char*>(newline) - begin) : left;
    pos_ += newline ? length + 1 : length;
    ++line_;
    if (length > 0 && begin[length - 1] == '\r') --length;
    line = {begin, length};
    return true;
  }
  /// 1-based number of the line last returned (0 before the first).
  uint64_t line_number() const { return line_; }
  /// Bytes not yet returned.
  uint64_t bytes_left() const { return text_.size() - pos_; }

 private:
  std::string_view text_;
  size_t pos_ = 0;
  uint64_t line_ = 0;
};

/// Whitespace inside a line (the newline is the line separator, not a blank).
inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Removes a '#' comment and everything after it.
inline std::string_view strip_comment(std::string_view line) {
  size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// Pops the next blank-separated token from `line`; empty when none is left.
inline std::string_view next_token(std::string_view& line) {
  size_t i = 0;
  while (i < line.size() && is_blank(line[i])) ++i;
  size_t start = i;
  while (i < line.size() && !is_blank(line[i])) ++i;
  std::string_view token = line.substr(start, i - start);
  line.remove_prefix(i);
  return token;
}

/// True when only blanks are left.
inline bool only_blanks(std::string_view line) {
  for (char c : line)
    if (!is_blank(c)) return false;
  return true;
}

/// Pieces of `data` of about `bytes` each, cut after a newline (whole lines), in order; what the
/// parallel readers (read_off.cpp, read_obj.cpp) parse one per task.
inline std::vector<std::string_view> line_chunks(std::string_view data, size_t bytes) {
  std::vector<std::string_view> chunks;
  size_t at = 0;
  while (at < data.size()) {
    size_t next = std::min(data.size(), at + bytes);
    if (next < data.size()) {
      const size_t newline = data.find('\n', next);
      next = newline == std::string_view::npos ? data.size() : newline + 1;
    }
    chunks.push_back(data.substr(at, next - at));
    at = next;
  }
  return chunks;
}

/// `data` without a leading UTF-8 byte order mark.
inline std::string_view without_bom(std::string_view data) {
  return data.starts_with("\xEF\xBB\xBF") ? data.substr(3) : data;
}

/// What parse_number() found in a token.
enum class NumberStatus : uint8_t { kOk, kNotANumber, kOutOfRange };

/// For a decimal literal std::from_chars found out of range: true when it overflows (its
/// magnitude is above 1), false when it underflows. Out of line: the rare path.
bool literal_overflows(std::string_view literal);

/// Parses a whole token under the number rule (header comment): kOk with inf/nan parsed (callers
/// reject them with a specific message) and underflow rounded to ±0.
inline NumberStatus parse_number(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (token.empty() || ptr != end) return NumberStatus::kNotANumber;
  if (ec == std::errc()) return NumberStatus::kOk;
  if (literal_overflows(token)) return NumberStatus::kOutOfRange;
  value = token[0] == '-' ? -0.0 : 0.0;
  return NumberStatus::kOk;
}

/// parse_number() == kOk.
inline bool parse_double(std::string_view token, double& value) {
  return parse_number(token, value) == NumberStatus::kOk;
}

/// Parses a whole token as an integer (a leading '+' is allowed).
template <typename Int>
inline bool parse_integer(std::string_view token, Int& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && !token.empty();
}

/// Throws "FILE:LINE: ..." for a coordinate token that is missing, not a number, out of range or
/// not finite; `axis` ('x', 'y', 'z') names it in the message.
[[noreturn]] void fail_coordinate(std::string_view token, const std::string& file, uint64_t line,
                                  char axis);

/// Parses a finite coordinate; throws through fail_coordinate() otherwise.
inline double parse_coordinate(std::string_view token, const std::string& file, uint64_t line,
                               char axis) {
  double value;
  if (!parse_double(token, value) || !std::isfinite(value))
    fail_coordinate(token, file, line, axis);
  return value;
}

/// Throws "FILE:LINE: unexpected token ..." (or "out-of-range number ...") unless only blanks or
/// numbers are left (trailing colours, normals, texture coordinates).
void check_numeric_tail(std::string_view rest, const std::string& file, uint64_t line);

/// Reader entry points; `data` is the whole file, `file` the path for messages.
PolygonMesh read_off(const std::string& file, std::string_view data);
/// `uvs`, when given, receives the corners' texture coordinates (io/mesh_io.h,
/// read_mesh_with_uvs); the file is then read serially.
PolygonMesh read_obj(const std::string& file, std::string_view data,
                     std::vector<double>* uvs = nullptr);
/// `warnings`, when given, receives the non-fatal problems (one line each, naming the file).
PolygonMesh read_stl(const std::string& file, std::string_view data,
                     std::vector<std::string>* warnings = nullptr);
PolygonMesh read_ply(const std::string& file, std::string_view data);

}  // namespace cover::detail
