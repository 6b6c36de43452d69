// Warp leaves along rays (covering/detail/implicit.h warp_crossings): certified bisection on the
// child's box states.
//
// The ray's piece [a, b] lies in piece_box(a, b); the child's three-valued state on the
// enclosure of that box's preimage (implicit_box_state) is the warped leaf's state on the whole
// piece. A decided piece holds no crossing. An undecided piece is halved, down to 2^-kDepth of
// the ray's run through the leaf's box; consecutive undecided finest pieces form a run, bounded
// by decided pieces (or the run's ends, outside: the leaf's box bounds it). A run between
// different states holds an odd number of crossings: one is reported at its midpoint, within
// half the run of a true crossing. A run between equal states holds an even number, perhaps
// none (a tangency, a sliver thinner than a piece, or only an enclosure's overestimate): it is
// counted in the uncertain pieces and reports nothing. Crossings alternate, as field_crossings'.

#include <cmath>
#include <vector>

#include "cover/covering/box_states.h"
#include "cover/covering/detail/implicit.h"

namespace cover::detail {
namespace {

constexpr int kDepth = 20;

struct RunWalker {
  const Prepared& prepared;
  const Ray& ray;
  uint32_t leaf;
  double finest;
  std::vector<RayHit>& hits;
  uint32_t& uncertain;
  int state = -1;          ///< +1 inside, −1 outside: the last decided piece's
  double run_start = NAN;  ///< the current undecided run's start; NaN: none

  void decided(double a, int s) {
    if (!std::isnan(run_start)) {
      if (s != state) {
        const double t = 0.5 * (run_start + a);
        // Leaving the leaf (inside → outside) counts +1, entering −1, as for triangles.
        hits.push_back({t, Span::kNone, leaf, Span::kNone, static_cast<int8_t>(s < 0 ? 1 : -1)});
      } else {
        ++uncertain;
      }
      run_start = NAN;
    } else if (s != state) {  // two decided pieces meeting with different states: cannot be
      hits.push_back({a, Span::kNone, leaf, Span::kNone, static_cast<int8_t>(s < 0 ? 1 : -1)});
      ++uncertain;
    }
    state = s;
  }

  void piece(double a, double b) {
    const uint8_t st = implicit_box_state(prepared, leaf, piece_box(ray, a, b));
    if (st != kBoxUndecided) {
      decided(a, st == kBoxInside ? 1 : -1);
      return;
    }
    const double m = 0.5 * (a + b);
    if (b - a <= finest || !(m > a && m < b)) {
      if (std::isnan(run_start)) run_start = a;
      return;
    }
    piece(a, m);
    piece(m, b);
  }
};

}  // namespace

uint32_t warp_crossings(const Prepared& prepared, uint32_t leaf, const Ray& ray,
                        std::vector<RayHit>& hits) {
  const Leaf& l = prepared.solid().leaves[leaf];
  const auto [t0, t1] = clip(ray, l.bbox);
  if (!(t0 < t1)) return 0;
  uint32_t uncertain = 0;
  RunWalker w{prepared, ray, leaf, (t1 - t0) * std::ldexp(1.0, -kDepth), hits, uncertain};
  // Outside the leaf's box is outside; an origin inside the box starts from its own membership.
  if (t0 == 0) {
    std::atomic<size_t> u{0};
    w.state = implicit_member(prepared, leaf, ray.origin, &u) == field::Sign::kInside ? 1 : -1;
    uncertain += static_cast<uint32_t>(u.load());
  }
  w.piece(t0, t1);
  w.decided(t1, -1);  // the box's exit: outside
  return uncertain;
}

}  // namespace cover::detail
