#pragma once
// Two doubles in one SSE2 register (GCC/Clang vector extension, so not MSVC): element-wise IEEE
// operations with the same results as the scalar ones (the build has -ffp-contract=off). Used by
// the hot loops of the voxelizer (raster/voxelize.cpp) and the ray slab test (covering/ray.cpp);
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

/// The neighbour of a finite float f toward +∞ (up) or −∞ (down), by its bits (nextafterf is a
/// library call on the query setup path).
inline float next_float(float f, bool up) {
  if (f == 0) return up ? __FLT_DENORM_MIN__ : -__FLT_DENORM_MIN__;
  uint32_t bits;
  __builtin_memcpy(&bits, &f, sizeof bits);
  bits += (f > 0) == up ? 1 : -1;  // away from zero when moving with the sign, else toward it
  __builtin_memcpy(&f, &bits, sizeof f);
  return f;
}

/// The largest float <= x and the smallest float >= x (±∞ beyond the float range): for a float
/// f, f <= x ⟺ f <= float_down(x) and f >= x ⟺ f >= float_up(x), so a float box compared with
/// a double point gives the same answers in single precision.
inline float float_down(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? next_float(f, false) : f;
}
inline float float_up(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? next_float(f, true) : f;
}

}  // namespace cover::detail
