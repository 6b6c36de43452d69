#pragma once
// What the benchmark programs share: wall-clock seconds and integer "--name value" options.
#include <chrono>
#include <cstdlib>
#include <cstring>

namespace bench {

using Clock = std::chrono::steady_clock;

/// Seconds since t.
inline double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The integer after the first argument equal to `name`, or `fallback` when there is none.
inline long arg(int argc, char** argv, const char* name, long fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], name) == 0) return std::atol(argv[i + 1]);
  return fallback;
}

}  // namespace bench
