#pragma once
// Small helpers for the CLI's outputs: progress on a terminal, and JSON of shared types.

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cover/io/atomic_file.h"
#include "cover/solid/types.h"

namespace cover::cli {

/// A progress bar on stderr, shown only when stderr is a terminal, not quiet, and the work has
/// already taken more than a second. update() is called from the coordinating thread only.
class Progress {
 public:
  Progress(std::string label, bool quiet);
  ~Progress();
  void update(size_t done, size_t total);
  /// Clears the bar (if shown) so that the command's own output starts on a clean line.
  void finish();

 private:
  std::string label_;
  bool enabled_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point start_;
};

nlohmann::json to_json(const Vec3& v);
nlohmann::json to_json(const Bbox& b);

/// Splits "a,b,c" at any of `separators` into exactly `count` finite numbers; throws InputError
/// naming `option` otherwise.
std::vector<double> parse_numbers(const std::string& text, const std::string& option, size_t count,
                                  const char* separators);

/// The output folder of `--pieces DIR` and `decompose -o DIR` (io/atomic_file.h OutputFolder):
/// built beside DIR and swapped in whole at the batch's commit. An existing DIR is replaced only
/// when it is empty or a pieces folder Cover wrote: pieces.json, and only regular files named
/// pieces.json, piece_N.EXT or cell_I_J_K.EXT (EXT a mesh extension); anything else is refused.
std::unique_ptr<OutputFolder> pieces_folder(const std::string& dir);

/// Refuses (InputError "--bounds: ...") a cube reaching beyond the supported coordinate range
/// ±kMaxCoordinate (solid/types.h) on some axis: its cells and their corners would overflow or
/// leave the range every exact predicate is proven for.
void check_bounds_range(const Vec3& min, double size);

/// Seconds since `start` as a double.
double seconds_since(std::chrono::steady_clock::time_point start);

/// The timing keys of every --json output (docs/cli.md#conventions-of-every-command):
/// `seconds`, the whole command from its start, and `seconds_detail` {load, kernel, write}: reading
/// and validating the input, the command's own work, and writing its files and building its stdout.
/// Each phase ends with lap(); time between laps goes to the phase named there.
class Timing {
 public:
  enum Phase { kLoad, kKernel, kWrite };
  Timing() : start_(std::chrono::steady_clock::now()), mark_(start_) {}
  /// Adds the time since the previous lap (or the start) to `phase`.
  void lap(Phase phase);
  /// Adds `seconds` to {"seconds", "seconds_detail"} of `j` (the whole command up to now).
  void put(nlohmann::json& j) const;
  double total() const { return seconds_since(start_); }

 private:
  std::chrono::steady_clock::time_point start_, mark_;
  double phase_[3] = {0, 0, 0};
};

}  // namespace cover::cli
