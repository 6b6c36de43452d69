#include "cli/points.h"

#include <algorithm>
#include <iostream>

#include "solid/detail/mesh_io_detail.h"
#include "solid/errors.h"
#include "solid/memory_limit.h"

namespace cover::cli {
namespace {

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

}  // namespace

std::vector<Vec3> parse_points(std::string_view text, const std::string& name) {
  std::vector<Vec3> points;
  detail::LineReader lines(detail::without_bom(text));
  std::string_view line;
  while (lines.next(line)) {
    const uint64_t n = lines.line_number();
    line = detail::strip_comment(line);
    double xyz[3];
    int count = 0;
    for (std::string_view field = next_field(line); !field.empty(); field = next_field(line)) {
      if (count == 3)
        throw InputError(name + ":" + std::to_string(n) + ": expected 3 numbers, got more");
      xyz[count] = detail::parse_coordinate(field, name, n, "xyz"[count]);
      ++count;
    }
    if (count != 0 && count != 3)
      throw InputError(name + ":" + std::to_string(n) + ": expected 3 numbers, got " +
                       std::to_string(count));
    if (count == 3) points.push_back({xyz[0], xyz[1], xyz[2]});
  }
  return points;
}

std::vector<Vec3> read_points(const std::string& path, uint64_t max_bytes, size_t bytes_per_point) {
  const std::string name = path == "-" ? "<stdin>" : path;
  const std::string text =
      path == "-" ? read_stream(std::cin, max_bytes, name) : read_regular_file(path, max_bytes);
  // Every line may hold a point: at most newlines + 1 of them.
  const size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  check_memory(static_cast<double>(text.size()) + static_cast<double>(lines) * bytes_per_point,
               max_bytes, name + ": classifying " + std::to_string(lines) + " lines of points");
  return parse_points(text, name);
}

}  // namespace cover::cli
