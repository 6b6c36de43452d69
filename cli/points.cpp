#include "cli/points.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iostream>

#include "solid/errors.h"
#include "solid/memory_limit.h"

namespace cover::cli {
namespace {

/// `lines`: the text's line count, reserved as the most points it can hold.
std::vector<Vec3> parse_points(const std::string& text, const std::string& name, size_t lines) {
  std::vector<Vec3> points;
  points.reserve(lines);
  const char* p = text.data();
  const char* const end = p + text.size();
  size_t line = 0;
  while (p < end) {
    ++line;
    const char* eol = p;
    while (eol < end && *eol != '\n') ++eol;
    const char* stop = p;
    while (stop < eol && *stop != '#') ++stop;
    double xyz[3];
    int n = 0;
    const char* c = p;
    auto separator = [](char ch) { return ch == ' ' || ch == '\t' || ch == ',' || ch == '\r'; };
    for (;;) {
      while (c < stop && separator(*c)) ++c;
      if (c == stop) break;
      double v;
      auto [next, ec] = std::from_chars(c, stop, v);
      if (ec != std::errc() || (next < stop && !separator(*next)))
        throw InputError(name + ":" + std::to_string(line) + ": expected a number, got '" +
                         std::string(c, std::min<size_t>(static_cast<size_t>(stop - c), 20)) + "'");
      if (n == 3)
        throw InputError(name + ":" + std::to_string(line) + ": expected 3 numbers, got more");
      if (!std::isfinite(v))
        throw InputError(name + ":" + std::to_string(line) + ": coordinate is not finite");
      xyz[n++] = v;
      c = next;
    }
    if (n != 0 && n != 3)
      throw InputError(name + ":" + std::to_string(line) + ": expected 3 numbers, got " +
                       std::to_string(n));
    if (n == 3) points.push_back({xyz[0], xyz[1], xyz[2]});
    p = eol + 1;
  }
  return points;
}

}  // namespace

std::vector<Vec3> read_points(const std::string& path, uint64_t max_bytes, size_t bytes_per_point) {
  const std::string name = path == "-" ? "<stdin>" : path;
  const std::string text =
      path == "-" ? read_stream(std::cin, max_bytes, name) : read_regular_file(path, max_bytes);
  // Every line may hold a point: at most newlines + 1 of them.
  const size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  check_memory(static_cast<double>(text.size()) + static_cast<double>(lines) * bytes_per_point,
               max_bytes, name + ": classifying " + std::to_string(lines) + " lines of points");
  return parse_points(text, name, lines);
}

}  // namespace cover::cli
