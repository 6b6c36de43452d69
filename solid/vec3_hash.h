#pragma once
// A hash of Vec3 for exact-equality vertex maps (io/read_stl.cpp, mesh/repair.cpp); internal, not
// installed.

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "cover/solid/types.h"

namespace cover::detail {

/// A hash of a point for exact-equality welding (STL readers, vertex repair): −0 and +0 are the
/// same point.
struct Vec3Hash {
  size_t operator()(const Vec3& p) const {
    auto bits = [](double d) {
      uint64_t b;
      d += 0.0;  // −0 → +0
      std::memcpy(&b, &d, sizeof b);
      return b;
    };
    uint64_t h = bits(p.x) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits(p.y)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 31) ^ bits(p.z)) * 0x94D049BB133111EBull;
    return static_cast<size_t>(h ^ (h >> 32));
  }
};

}  // namespace cover::detail
