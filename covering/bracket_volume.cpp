// The bracket volume of solids with field leaves (covering/volume.h volume(), method "bracket").
//
// Cells of an octree over the result's box are settled three-valued (covering/box_states.h: each
// field by interval bounds, each mesh leaf by triangle boxes and its exact winding number, the
// tree in Kleene's logic): full, empty or unknown; full cells add to both ends of the bracket,
// unknown ones to its upper end only, and unknown cells are split in eight until (V_out − V_in)/2 ≤
// target·V or the next level would hold more cells than the budget (so all levels together settle
// at most about 8/7 of it). Sums are outward-rounded intervals (CGAL::Interval_nt), so the bracket
// holds in doubles.

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <cmath>

#include "cover/covering/bounds.h"
#include "cover/covering/box_states.h"
#include "cover/covering/volume.h"
#include "cover/solid/errors.h"

namespace cover::detail {

VolumeResult bracket_volume(const Prepared& prepared, const VolumeOptions& options) {
  using I = CGAL::Interval_nt<false>;
  const Solid& s = prepared.solid();
  const std::optional<Bbox> bounds = result_bounds(s);
  if (!bounds) throw NotComputable("the result is unbounded: it has no volume");
  VolumeResult r;
  r.method = "bracket";
  if (bounds->empty()) return r;
  std::vector<Bbox> level{*bounds}, next;
  I inside_sum(0);
  const size_t budget = std::max<size_t>(options.max_rays, 4096);  // cells of a level, at most
  size_t settled = 0;
  for (int depth = 0; !level.empty(); ++depth) {
    const std::vector<uint8_t> state = box_states(prepared, level);
    settled += level.size();
    // In cell order: the sums (hence the bracket) do not depend on the threads.
    I unknown_here(0);
    for (size_t c = 0; c < level.size(); ++c) {
      if (state[c] == kBoxOutside) continue;
      const Bbox& b = level[c];
      const I v = (I(b.max.x) - b.min.x) * (I(b.max.y) - b.min.y) * (I(b.max.z) - b.min.z);
      if (state[c] == kBoxInside)
        inside_sum += v;
      else
        unknown_here += v;
    }
    const double lo = inside_sum.inf(), hi = (inside_sum + unknown_here).sup();
    const double half = (hi - lo) / 2, mid = lo + half;
    if (options.progress)
      options.progress(std::min(1.0, static_cast<double>(settled) / (budget + budget / 7)));
    const size_t unknown_cells =
        static_cast<size_t>(std::count(state.begin(), state.end(), uint8_t{kBoxUndecided}));
    if (half <= options.bracket_relative_error * std::abs(mid) || unknown_cells == 0 ||
        8 * unknown_cells > budget) {
      r.volume = mid;
      r.error_bound = std::nextafter(hi - mid > mid - lo ? hi - mid : mid - lo, INFINITY);
      r.target_met = half <= options.bracket_relative_error * std::abs(mid);
      r.rays = settled;
      return r;
    }
    next.clear();
    for (size_t c = 0; c < level.size(); ++c) {
      if (state[c] != kBoxUndecided) continue;
      const Bbox& b = level[c];
      const Vec3 m = 0.5 * (b.min + b.max);
      for (int o = 0; o < 8; ++o) {
        Bbox child;
        child.min = {o & 1 ? m.x : b.min.x, o & 2 ? m.y : b.min.y, o & 4 ? m.z : b.min.z};
        child.max = {o & 1 ? b.max.x : m.x, o & 2 ? b.max.y : m.y, o & 4 ? b.max.z : m.z};
        next.push_back(child);
      }
    }
    level.swap(next);
  }
  return r;
}

}  // namespace cover::detail
