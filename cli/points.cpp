// Points of `cover classify` (cli/points.h).
// Text is parsed in two parallel passes over chunks of whole lines (a chunk spans kChunkBytes and
// then up to the end of its last line, so the split depends only on the text):
//   1. count the lines of each chunk; prefix sums give each chunk its first line number and its
//      first slot in one array of (lines) points, the bound the memory check counts;
//   2. parse each chunk into its slots, keeping the chunk's first error instead of throwing; a
//      plain "x y z" line is read straight from the buffer, any other line (comment, blank,
//      '+', error) by the general line rule, so both give the same points and messages.
// The first chunk with an error (in file order) rethrows it; otherwise the chunks' points are
// moved down over the slots of blank and comment lines, in order.

#include "cover/cli/points.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>

#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/io/npy.h"
#include "cover/io/parse.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/parallel.h"

namespace cover::cli {
namespace {

constexpr size_t kChunkBytes = size_t{1} << 18;  ///< text parsed per task (whole lines)
constexpr size_t kValueGrain = size_t{1} << 16;  ///< .npy points converted per task
constexpr const char* kRangeMessage =
    " is outside the supported range [-2^64, 2^64] (about ±1.8e19)";

/// A separator between the numbers of a line: a blank or a comma.
bool is_separator(char c) { return c == ',' || detail::is_blank(c); }

/// Pops the next comma- or blank-separated field from `line`; empty when none is left.
std::string_view next_field(std::string_view& line) {
  size_t i = 0;
  while (i < line.size() && is_separator(line[i])) ++i;
  const size_t start = i;
  while (i < line.size() && !is_separator(line[i])) ++i;
  std::string_view field = line.substr(start, i - start);
  line.remove_prefix(i);
  return field;
}

/// True when `path` ends in .npy (any case).
bool has_npy_extension(const std::string& path) { return lower_extension(path) == ".npy"; }

// ---- text ----

/// Text split into chunks of whole lines: chunk k is [begin[k], begin[k + 1]).
struct TextChunks {
  std::string_view text;       ///< without the byte order mark
  std::vector<size_t> begin;   ///< chunk starts, then text.size()
  std::vector<uint64_t> line;  ///< lines before each chunk, then the total
};

/// The number of '\n' in `s`. Byte counters per lane (at most 255 blocks of 64 bytes before
/// they are summed) let the compiler vectorize the comparisons; std::count and a memchr loop
/// over short lines are several times slower.
uint64_t count_newlines(std::string_view s) {
  constexpr size_t kLanes = 64, kBlocks = 255;
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  uint64_t count = 0;
  size_t i = 0;
  while (s.size() - i >= kLanes) {
    uint8_t lanes[kLanes] = {};
    for (size_t b = 0; b < kBlocks && s.size() - i >= kLanes; ++b, i += kLanes)
      for (size_t k = 0; k < kLanes; ++k) lanes[k] += p[i + k] == '\n';
    for (const uint8_t c : lanes) count += c;
  }
  for (; i < s.size(); ++i) count += p[i] == '\n';
  return count;
}

TextChunks split_lines(std::string_view text) {
  TextChunks c;
  c.text = detail::without_bom(text);
  const std::string_view t = c.text;
  c.begin.push_back(0);
  for (size_t at = kChunkBytes; at < t.size(); at = c.begin.back() + kChunkBytes) {
    const size_t newline = t.find('\n', at);
    if (newline == std::string_view::npos || newline + 1 == t.size()) break;
    c.begin.push_back(newline + 1);
  }
  c.begin.push_back(t.size());
  const size_t chunks = c.begin.size() - 1;
  c.line.assign(chunks + 1, 0);
  parallel_for(chunks, 1, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      const std::string_view s = t.substr(c.begin[k], c.begin[k + 1] - c.begin[k]);
      // Only the last chunk may end without a newline: its last line counts too.
      c.line[k + 1] = count_newlines(s) + (!s.empty() && s.back() != '\n' ? 1 : 0);
    }
  });
  for (size_t k = 0; k < chunks; ++k) c.line[k + 1] += c.line[k];
  return c;
}

/// Throws "FILE:LINE: x coordinate T is outside the supported range ..." unless |value| is in it.
void check_range(double value, std::string_view token, const std::string& name, uint64_t line,
                 char axis) {
  if (!(std::abs(value) <= kMaxCoordinate))
    detail::fail_line(name, line,
                      std::string(1, axis) + " coordinate " + detail::quote(token) + kRangeMessage);
}

/// Parses one line (without its terminator) under the full rule: true with `point` set for a
/// point, false for a blank or comment line; throws InputError "NAME:N: ..." for a bad line.
bool parse_line(std::string_view line, const std::string& name, uint64_t n, Vec3& point) {
  line = detail::strip_comment(line);
  double xyz[3];
  int count = 0;
  for (std::string_view field = next_field(line); !field.empty(); field = next_field(line)) {
    if (count == 3) detail::fail_line(name, n, "expected 3 numbers, got more");
    xyz[count] = detail::parse_coordinate(field, name, n, "xyz"[count]);
    check_range(xyz[count], field, name, n, "xyz"[count]);
    ++count;
  }
  if (count != 0 && count != 3)
    detail::fail_line(name, n, "expected 3 numbers, got " + std::to_string(count));
  if (count == 3) point = {xyz[0], xyz[1], xyz[2]};
  return count == 3;
}

/// The common line, three numbers between separators, read straight from the buffer: the end of
/// the line (past its '\n', or `end`) with `point` set, or nullptr for any other line (a '+',
/// a comment, an error, an underflow...), which then takes parse_line(). A number ends where
/// std::from_chars stops, which must be at a separator or the line's end: that is exactly the
/// whole-token rule of parse_line(), as no separator can continue a number.
const char* parse_plain_line(const char* p, const char* end, Vec3& point) {
  double xyz[3];
  for (double& v : xyz) {
    while (p < end && is_separator(*p)) ++p;
    const auto [stop, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || stop == p || !(std::abs(v) <= kMaxCoordinate)) return nullptr;
    p = stop;
    if (p < end && !is_separator(*p) && *p != '\n') return nullptr;
  }
  while (p < end && is_separator(*p)) ++p;
  if (p < end && *p != '\n') return nullptr;
  point = {xyz[0], xyz[1], xyz[2]};
  return p < end ? p + 1 : end;
}

/// Parses the lines of `chunk`, the first numbered `first_line` + 1, into out[0..); returns the
/// number of points. Throws InputError "NAME:LINE: ..." at the first bad line.
size_t parse_chunk(std::string_view chunk, const std::string& name, uint64_t first_line,
                   Vec3* out) {
  size_t count = 0;
  uint64_t n = first_line;
  const char* p = chunk.data();
  const char* const end = p + chunk.size();
  while (p < end) {
    ++n;
    if (const char* next = parse_plain_line(p, end, out[count])) {
      ++count;
      p = next;
      continue;
    }
    const auto* newline =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    std::string_view line(p, static_cast<size_t>((newline ? newline : end) - p));
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (parse_line(line, name, n, out[count])) ++count;
    p = newline ? newline + 1 : end;
  }
  return count;
}

std::vector<Vec3> parse_chunks(const TextChunks& c, const std::string& name) {
  const size_t chunks = c.begin.size() - 1;
  std::vector<Vec3> points(static_cast<size_t>(c.line.back()));
  std::vector<size_t> found(chunks, 0);
  std::vector<std::exception_ptr> errors(chunks);
  parallel_for(chunks, 1, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      try {
        found[k] = parse_chunk(c.text.substr(c.begin[k], c.begin[k + 1] - c.begin[k]), name,
                               c.line[k], points.data() + c.line[k]);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  size_t size = 0;
  for (size_t k = 0; k < chunks; ++k) {
    const auto from = points.begin() + static_cast<std::ptrdiff_t>(c.line[k]);
    if (c.line[k] != size)
      std::copy(from, from + static_cast<std::ptrdiff_t>(found[k]),
                points.begin() + static_cast<std::ptrdiff_t>(size));
    size += found[k];
  }
  points.resize(size);
  return points;
}

// ---- NumPy ----

/// Where the points of an .npy file are and how to read them.
struct NpyPoints {
  std::string_view data;  ///< the N·3 values
  uint64_t count = 0;     ///< N
  bool single = false;    ///< float32 (else float64)
  bool swap = false;      ///< byte order opposite to this machine's
  bool fortran = false;   ///< value (i, a) at a·N + i (else 3·i + a)
};

std::string shape_text(const std::vector<uint64_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

/// Checks everything but the values: header, dtype, shape, and that the data fills the file.
NpyPoints check_npy(std::string_view data, const std::string& name) {
  const NpyHeader h = parse_npy_header(data, name);
  NpyPoints p;
  const std::string_view d = h.descr;
  const bool little = std::endian::native == std::endian::little;
  if (d.size() != 3 || (d[0] != '<' && d[0] != '>' && d[0] != '=') || d[1] != 'f' ||
      (d[2] != '8' && d[2] != '4'))
    detail::fail_file(name, "unsupported .npy dtype " + detail::quote(h.descr) +
                                " (expected float64 '<f8' or float32 '<f4', either byte order)");
  p.single = d[2] == '4';
  p.swap = (d[0] == '<' && !little) || (d[0] == '>' && little);
  p.fortran = h.fortran_order;
  if (h.shape.size() != 2 || h.shape[1] != 3)
    detail::fail_file(name, ".npy shape " + shape_text(h.shape) + " is not (N, 3)");
  p.count = h.shape[0];
  const uint64_t item = p.single ? 4 : 8;
  const uint64_t available = data.size() - h.data_offset;
  if (!detail::fits(p.count, 3 * item, available) || p.count * 3 * item != available)
    detail::fail_file(
        name, ".npy shape " + shape_text(h.shape) + " of " + h.descr + " needs " +
                  (detail::fits(p.count, 3 * item, UINT64_MAX) ? std::to_string(p.count * 3 * item)
                                                               : std::string("more than 2^64")) +
                  " data bytes, the file has " + std::to_string(available));
  p.data = data.substr(h.data_offset);
  return p;
}

/// Value `index` of the data as a double.
double npy_value(const NpyPoints& p, uint64_t index) {
  if (p.single) {
    uint32_t bits;
    std::memcpy(&bits, p.data.data() + 4 * index, 4);
    if (p.swap) bits = __builtin_bswap32(bits);
    return static_cast<double>(std::bit_cast<float>(bits));
  }
  uint64_t bits;
  std::memcpy(&bits, p.data.data() + 8 * index, 8);
  if (p.swap) bits = __builtin_bswap64(bits);
  return std::bit_cast<double>(bits);
}

std::vector<Vec3> convert_npy(const NpyPoints& p, const std::string& name) {
  const size_t n = static_cast<size_t>(p.count);
  std::vector<Vec3> points(n);
  const size_t tasks = (n + kValueGrain - 1) / kValueGrain;
  std::vector<uint64_t> bad(tasks, UINT64_MAX);  // first bad value (index·3 + axis) per task
  parallel_for(n, kValueGrain, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      double xyz[3];
      for (uint64_t a = 0; a < 3; ++a) {
        xyz[a] = npy_value(p, p.fortran ? a * n + i : 3 * i + a);
        if (!(std::abs(xyz[a]) <= kMaxCoordinate) && bad[first / kValueGrain] == UINT64_MAX)
          bad[first / kValueGrain] = 3 * i + a;
      }
      points[i] = {xyz[0], xyz[1], xyz[2]};
    }
  });
  for (const uint64_t b : bad) {
    if (b == UINT64_MAX) continue;
    const double v = points[b / 3][static_cast<int>(b % 3)];
    char value[32];
    std::snprintf(value, sizeof value, "%.17g", v);
    detail::fail_file(name, "point " + std::to_string(b / 3) + " (counting from 0): " +
                                (std::isfinite(v) ? "" : "non-finite ") + "xyz"[b % 3] +
                                " coordinate " + value + (std::isfinite(v) ? kRangeMessage : ""));
  }
  return points;
}

}  // namespace

std::vector<Vec3> parse_points(std::string_view text, const std::string& name) {
  return parse_chunks(split_lines(text), name);
}

std::vector<Vec3> parse_npy_points(std::string_view data, const std::string& name) {
  return convert_npy(check_npy(data, name), name);
}

std::vector<Vec3> read_points(const std::string& path, uint64_t max_bytes, size_t bytes_per_point) {
  const std::string name = path == "-" ? "<stdin>" : path;
  const FileBytes data =
      path == "-" ? read_stream(std::cin, max_bytes, name) : read_regular_file(path, max_bytes);
  const auto need = [&](uint64_t count, const std::string& what) {
    check_memory(static_cast<double>(data.size()) + static_cast<double>(count) * bytes_per_point,
                 max_bytes, name + ": classifying " + std::to_string(count) + " " + what);
  };
  if ((path != "-" && has_npy_extension(path)) || has_npy_magic(data)) {
    const NpyPoints p = check_npy(data, name);
    need(p.count, "points");
    return convert_npy(p, name);
  }
  const TextChunks chunks = split_lines(data);
  need(chunks.line.back(), "lines of points");
  return parse_chunks(chunks, name);
}

void check_classes_path(const std::string& path) {
  if (!has_npy_extension(path))
    detail::fail_file(path, "unsupported classes format " +
                                detail::quote(std::filesystem::path(path).extension().string()) +
                                " (expected .npy)");
}

void write_npy_vector(const std::string& path, std::string_view descr, const void* data,
                      size_t count, size_t item_bytes, const std::string& what) {
  check_classes_path(path);
  const std::array<uint64_t, 1> shape{count};
  const std::string header = npy_header(descr, shape);
  write_atomically(
      path,
      [&](const std::filesystem::path& temporary) {
        std::FILE* file = std::fopen(temporary.c_str(), "wb");
        if (file == nullptr)
          detail::fail_file(path, std::string("cannot write: ") + std::strerror(errno));
        const bool written = std::fwrite(header.data(), 1, header.size(), file) == header.size() &&
                             (count == 0 || std::fwrite(data, item_bytes, count, file) == count) &&
                             std::fflush(file) == 0;
        const int error = errno;
        if (std::fclose(file) != 0 || !written)
          detail::fail_file(path,
                            std::string("cannot write: ") + std::strerror(written ? errno : error));
        return true;
      },
      what);
}

void write_classes(const std::string& path, std::span<const PointClass> classes) {
  static_assert(sizeof(PointClass) == 1, "classes are written as their uint8 codes");
  write_npy_vector(path, "|u1", classes.data(), classes.size(), 1, "the classes");
}

}  // namespace cover::cli
