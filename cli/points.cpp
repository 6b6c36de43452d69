#include "cli/points.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "solid/errors.h"

namespace cover::cli {

std::vector<Vec3> parse_points(const std::string& text, const std::string& name) {
  std::vector<Vec3> points;
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

std::vector<Vec3> read_points(const std::string& path) {
  std::string text;
  if (path == "-") {
    text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    return parse_points(text, "<stdin>");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_points(ss.str(), path);
}

}  // namespace cover::cli
