#pragma once
// Two doubles in one SSE2 register (GCC/Clang vector extension, so not MSVC): element-wise IEEE
// operations with the same results as the scalar ones (the build has -ffp-contract=off). Used by
// the hot loops of the voxelizer (voxel/voxelize.cpp) and the ray slab test (covering/ray.cpp);
// four floats in one register for the classification half-line's node test (classify.cpp).

#include <cstdint>

namespace cover::detail {

using v2d = double __attribute__((vector_size(16)));
using v2u = uint64_t __attribute__((vector_size(16)));
using v4f = float __attribute__((vector_size(16)));
using v4i = int32_t __attribute__((vector_size(16)));

/// |v| element-wise by clearing the sign bits (as std::abs).
inline v2d vabs(v2d v) {
  return reinterpret_cast<v2d>(reinterpret_cast<v2u>(v) & (~uint64_t{0} >> 1));
}

/// True when every lane of a comparison mask is set (all-ones).
inline bool all_lanes(v4i m) {
  unsigned __int128 bits;
  __builtin_memcpy(&bits, &m, sizeof bits);
  return bits == ~static_cast<unsigned __int128>(0);
}

}  // namespace cover::detail
