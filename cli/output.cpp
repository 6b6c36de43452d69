#include "cover/cli/output.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"

namespace cover::cli {

std::vector<double> parse_numbers(const std::string& text, const std::string& option, size_t count,
                                  const char* separators) {
  std::vector<double> out;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t next = text.find_first_of(separators, pos);
    const std::string item =
        text.substr(pos, next == std::string::npos ? std::string::npos : next - pos);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v))
      throw InputError(option + ": expected " + std::to_string(count) + " numbers, got '" + text +
                       "'");
    out.push_back(v);
    if (next == std::string::npos) break;
    pos = next + 1;
  }
  if (out.size() != count)
    throw InputError(option + ": expected " + std::to_string(count) + " numbers, got '" + text +
                     "'");
  return out;
}

namespace {

/// True when `text` from `at` on is `parts` runs of digits joined by '_', then a mesh extension.
bool numbers_then_mesh(const std::string& text, size_t at, int parts) {
  for (int p = 0; p < parts; ++p) {
    const size_t start = at;
    while (at < text.size() && text[at] >= '0' && text[at] <= '9') ++at;
    if (at == start) return false;
    if (p + 1 < parts && (at >= text.size() || text[at++] != '_')) return false;
  }
  const std::string ext = text.substr(at);
  return ext.find('.', 1) == std::string::npos && is_mesh_extension("piece" + ext);
}

bool own_piece_name(const std::string& name) {
  if (name == "pieces.json") return true;
  if (name.rfind("piece_", 0) == 0) return numbers_then_mesh(name, 6, 1);
  if (name.rfind("cell_", 0) == 0) return numbers_then_mesh(name, 5, 3);
  return false;
}

}  // namespace

std::unique_ptr<OutputFolder> pieces_folder(const std::string& dir) {
  return std::make_unique<OutputFolder>(dir, "the pieces", [](const std::filesystem::path& folder) {
    return refuse_unless_own_folder(folder, "pieces.json", own_piece_name, "a pieces folder");
  });
}
void check_bounds_range(const Vec3& min, double size) {
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(min[a]) <= kMaxCoordinate && std::abs(min[a] + size) <= kMaxCoordinate))
      throw InputError(
          "--bounds: the cube reaches beyond the supported coordinate range ±2^64 "
          "(about ±1.8e19) on " +
          std::string(1, "xyz"[a]));
}

Progress::Progress(std::string label, bool quiet)
    : label_(std::move(label)),
      enabled_(!quiet && isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::finish() {
  if (shown_) std::fprintf(stderr, "\r\033[K");
  shown_ = false;
}

void Progress::update(size_t done, size_t total) {
  if (!enabled_ || total == 0 || seconds_since(start_) < 1.0) return;
  shown_ = true;
  const int width = 40;
  const int filled = static_cast<int>(width * done / total);
  std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled,
               "########################################", width - filled, "",
               static_cast<int>(100 * done / total));
  std::fflush(stderr);
}

nlohmann::json to_json(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json to_json(const Bbox& b) {
  if (b.empty()) return nullptr;
  return nlohmann::json::array({to_json(b.min), to_json(b.max)});
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Timing::lap(Phase phase) {
  const auto now = std::chrono::steady_clock::now();
  phase_[phase] += std::chrono::duration<double>(now - mark_).count();
  mark_ = now;
}

void Timing::put(nlohmann::json& j) const {
  j["seconds"] = total();
  j["seconds_detail"] = {
      {"load", phase_[kLoad]}, {"kernel", phase_[kKernel]}, {"write", phase_[kWrite]}};
}

}  // namespace cover::cli
