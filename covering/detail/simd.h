#pragma once
// Two doubles in one SSE2 register (GCC/Clang vector extension, so not MSVC): element-wise IEEE
// operations with the same results as the scalar ones (the build has -ffp-contract=off). Used by
// the hot loops of the voxelizer (raster/voxelize.cpp) and the ray slab test (covering/ray.cpp).

#include <cstdint>

namespace cover::detail {

using v2d = double __attribute__((vector_size(16)));
using v2u = uint64_t __attribute__((vector_size(16)));

/// |v| element-wise by clearing the sign bits (as std::abs).
inline v2d vabs(v2d v) {
  return reinterpret_cast<v2d>(reinterpret_cast<v2u>(v) & (~uint64_t{0} >> 1));
}

}  // namespace cover::detail
