// SubdivideOptions::exact_rounding: the masks of detail/stencils.h evaluated in exact rationals
// (CGAL::Gmpq) over the previous level's doubles, each coordinate rounded to the nearest double
// (ties to even). The only translation unit of cover_subdivision that includes CGAL.
#include <CGAL/Gmpq.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cover/solid/errors.h"
#include "cover/subdivision/detail/evaluate.h"

namespace cover::subdivision_detail {

namespace {

using Q = CGAL::Gmpq;

/// The double nearest to q (ties to even). to_interval gives the two doubles around q; the
/// exact midpoint decides between them.
double round_nearest(const Q& q) {
  const auto [lo, hi] = CGAL::to_interval(q);
  if (lo == hi) return lo;
  if (hi != std::nextafter(lo, std::numeric_limits<double>::infinity()))
    throw InternalError("exact_points: interval of a rational is not one ulp wide");
  const Q mid = (Q(lo) + Q(hi)) / Q(2.0);
  if (q < mid) return lo;
  if (q > mid) return hi;
  return (std::bit_cast<uint64_t>(lo) & 1) == 0 ? lo : hi;  // the last significand bit
}

}  // namespace

void exact_points(const Topology& t, const Layout& l, std::vector<Vec3>& out) {
  evaluate_points<Q>(t, l, out, [](const P3<Q>& p) {
    return Vec3{round_nearest(p.x), round_nearest(p.y), round_nearest(p.z)};
  });
}

}  // namespace cover::subdivision_detail
