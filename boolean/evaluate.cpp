// evaluate(): the driver of boolean/evaluate.h (no CGAL here; the exact steps live in
// arrangement.cpp, select.cpp and assemble.cpp).
#include "cover/boolean/evaluate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "cover/boolean/detail/arrangement.h"
#include "cover/covering/bounds.h"
#include "cover/mesh/rounding_repair.h"
#include "cover/solid/errors.h"
#include "cover/solid/union_find.h"

namespace cover {

EvaluateResult evaluate(const Solid& solid, const EvaluateOptions& options) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  EvaluateResult r;
  EvaluatePhases seconds;
  if (!is_bounded(solid))
    throw NotComputable(
        "evaluate: the result is unbounded (a complement at the root); a B-rep "
        "needs a bounded solid");
  // Leaf self-intersection test (with check_leaves) inside build_arrangement: it shares the grid
  // pass of the candidate pairs. Self-intersecting leaves get their own tri pairs intersected
  // too; the others need only pairs of different leaves.
  std::vector<uint8_t> self;
  const size_t grain = options.grain == 0 ? 1 : options.grain;
  const boolean_detail::Arrangement arr =
      boolean_detail::build_arrangement(solid, options.check_leaves, grain, seconds, self);
  r.candidate_pairs = arr.candidate_pairs;
  r.intersecting_pairs = arr.intersecting_pairs;
  auto t = Clock::now();
  std::vector<uint32_t> grouped;
  const auto kept =
      boolean_detail::select_pieces(solid, arr, grain, r.face_leaf, r.patches, grouped);
  seconds.select = since(t);
  t = Clock::now();
  if (options.exact_volume) r.exact_volume = boolean_detail::exact_volume(arr, kept);
  std::vector<uint8_t> rounded;
  r.mesh = boolean_detail::assemble(arr, kept, &r.face_leaf, &rounded, &grouped);
  seconds.assemble = since(t);
  // Contacts made by rounding the constructed points independently (mesh/rounding_repair.h).
  t = Clock::now();
  const RoundingRepair repair = repair_rounding(r.mesh, rounded);
  if (repair.changed()) {
    std::vector<uint32_t> leaf;
    leaf.reserve(repair.face_origin.size());
    for (uint32_t f : repair.face_origin) leaf.push_back(r.face_leaf[f]);
    r.face_leaf = std::move(leaf);
  }
  r.collapsed_edges = repair.collapsed_edges;
  r.rounding_contacts = repair.remaining_pairs;
  seconds.repair = since(t);
  t = Clock::now();
  // Volume and area in doubles, relative to the centre o of the mesh's box and scaled by a power
  // of two s (exact) so that |s·(v − o)| ≤ 1: summed about the origin, a solid far from it
  // (a unit box at 1e15) loses every digit to cancellation, and a tiny one (side 1e-150)
  // underflows in the products.
  {
    Bbox box;
    for (const Vec3& p : r.mesh.vertices) box.add(p);
    const Vec3 o = box.empty() ? Vec3{} : 0.5 * box.min + 0.5 * box.max;
    double reach = 0;
    for (const Vec3& p : r.mesh.vertices)
      reach = std::max({reach, std::abs(p.x - o.x), std::abs(p.y - o.y), std::abs(p.z - o.z)});
    const int e = reach > 0 ? std::ilogb(reach) + 1 : 0;
    auto local = [&](const Vec3& p) {
      return Vec3{std::ldexp(p.x - o.x, -e), std::ldexp(p.y - o.y, -e), std::ldexp(p.z - o.z, -e)};
    };
    double volume = 0, area = 0;
    for (size_t f = 0; f < r.mesh.face_count(); ++f) {
      auto t = r.mesh.face(f);
      const Vec3 a = local(r.mesh.vertices[t[0]]), b = local(r.mesh.vertices[t[1]]),
                 c = local(r.mesh.vertices[t[2]]);
      volume += dot(a, cross(b, c)) / 6;
      const Vec3 n = cross(b - a, c - a);
      area += 0.5 * std::sqrt(dot(n, n));
    }
    r.volume = std::ldexp(volume, 3 * e);
    r.area = std::ldexp(area, 2 * e);
  }
  // The result is closed and 2-manifold with its vertices split per fan (assemble() throws
  // otherwise), so E = 3F/2, components through edges are those through vertices, and
  // genus = (2·components − χ)/2 with χ = V − E + F (as brep::validate reports it).
  if (r.mesh.face_count() > 0) {
    UnionFind sets(r.mesh.vertices.size());
    for (size_t f = 0; f < r.mesh.face_count(); ++f) {
      auto t = r.mesh.face(f);
      sets.unite(t[0], t[1]);
      sets.unite(t[0], t[2]);
    }
    for (uint32_t v = 0; v < r.mesh.vertices.size(); ++v) r.components += sets.find(v) == v;
    const int64_t chi = static_cast<int64_t>(r.mesh.vertices.size()) -
                        static_cast<int64_t>(r.mesh.face_count()) / 2;
    r.genus = (2 * r.components - chi) / 2;
  }
  seconds.assemble += since(t);
  if (options.phases != nullptr) *options.phases = seconds;
  return r;
}

}  // namespace cover
