#pragma once
// Outward rounding of doubles to floats, exact: the BVH's float node boxes contain the double
// boxes (covering/bvh.cpp), and a double point compared with a float box gives the same answers
// as the float bounds of the point (covering/classify.cpp's four-lane half-line test).

#include <cstdint>

namespace cover::detail {

/// The neighbour of float f toward +∞ (up) or −∞ (down), by its bits, ±∞ stepping back to
/// ±FLT_MAX (nextafterf is a library call, and this is on the per-query setup path).
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
