#include "cli/points.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "solid/detail/mesh_io_detail.h"
#include "solid/errors.h"

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

/// All of standard input, read in large blocks (an istream iterator is ~4× slower than a file).
std::string read_stdin() {
  struct stat info {};
  size_t size_hint = 0;  // a redirected file: its size, plus one byte to see the end at once
  if (::fstat(STDIN_FILENO, &info) == 0 && S_ISREG(info.st_mode))
    size_hint = static_cast<size_t>(info.st_size) + 1;
  std::string data(std::max(size_hint, size_t{1} << 20), '\0');
  size_t used = 0;
  for (;;) {
    if (used == data.size()) data.resize(2 * data.size());
    const ssize_t got = ::read(STDIN_FILENO, data.data() + used, data.size() - used);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw InputError(std::string("<stdin>: cannot read: ") + std::strerror(errno));
    }
    if (got == 0) break;
    used += static_cast<size_t>(got);
  }
  data.resize(used);
  return data;
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

std::vector<Vec3> read_points(const std::string& path) {
  if (path == "-") return parse_points(read_stdin(), "<stdin>");
  return parse_points(detail::load_file(path), path);
}

}  // namespace cover::cli
