// evaluate(): the driver of boolean/evaluate.h (no CGAL here; the exact steps live in
// arrangement.cpp, select.cpp and assemble.cpp).
#include "boolean/evaluate.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "boolean/detail/arrangement.h"
#include "brep/halfedge.h"
#include "covering/bounds.h"
#include "solid/errors.h"
#include "solid/measure.h"
#include "solid/parallel.h"
#include "solid/validate.h"

namespace cover {

namespace {

/// Shells of a mesh: connected components of its faces through shared vertices, each with its
/// own compact vertex array (in first-use order).
std::vector<PolygonMesh> shells(const PolygonMesh& m) {
  std::vector<uint32_t> parent(m.vertices.size());
  for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (size_t f = 0; f < m.face_count(); ++f)
    for (uint32_t v : m.face(f)) parent[find(v)] = find(m.face(f)[0]);
  // A vertex belongs to the shell of its component; its local index is set on first use.
  std::vector<uint32_t> shell_of(m.vertices.size(), UINT32_MAX), local(m.vertices.size(), UINT32_MAX);
  std::vector<PolygonMesh> out;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < m.face_count(); ++f) {
    const uint32_t root = find(m.face(f)[0]);
    if (shell_of[root] == UINT32_MAX) {
      shell_of[root] = static_cast<uint32_t>(out.size());
      out.emplace_back();
    }
    PolygonMesh& shell = out[shell_of[root]];
    loop.clear();
    for (uint32_t v : m.face(f)) {
      if (local[v] == UINT32_MAX) {
        local[v] = static_cast<uint32_t>(shell.vertices.size());
        shell.vertices.push_back(m.vertices[v]);
      }
      loop.push_back(local[v]);
    }
    shell.add_face(loop);
  }
  return out;
}

/// A self-intersecting leaf whose shells are each free of self-intersections and outward is the
/// union of its shells: its winding number is the sum of theirs, each 0 or 1, so it is nonzero
/// exactly inside some shell (nonzero rule, CONTRACT.md). Empty when that does not hold.
std::optional<Solid> shell_union(const Solid& solid, uint32_t l) {
  std::vector<PolygonMesh> parts = shells(leaf_mesh(solid, l));
  if (parts.size() < 2) return std::nullopt;
  std::vector<Solid> leaves;
  for (PolygonMesh& part : parts) {
    if (signed_volume(part) <= 0 || self_intersects(part)) return std::nullopt;
    leaves.push_back(make_leaf(std::move(part), solid.leaves[l].name, solid.leaves[l].origin));
    leaves.back().leaves[0].flipped = solid.leaves[l].flipped;
  }
  return unite(std::move(leaves));
}

/// The solid with each leaf l for which split[l] is set replaced by that solid (same tree).
Solid rebuild(const Solid& s, uint32_t node, std::vector<std::optional<Solid>>& split) {
  const CsgNode& n = s.tree.nodes[node];
  if (n.op == CsgOp::kLeaf) {
    if (split[n.leaf]) return *split[n.leaf];
    Solid leaf = make_leaf(leaf_mesh(s, n.leaf), s.leaves[n.leaf].name, s.leaves[n.leaf].origin);
    leaf.leaves[0].flipped = s.leaves[n.leaf].flipped;
    return leaf;
  }
  std::vector<Solid> parts;
  for (uint32_t c : n.children) parts.push_back(rebuild(s, c, split));
  switch (n.op) {
    case CsgOp::kComplement:
      return complement(std::move(parts[0]));
    case CsgOp::kUnion:
      return unite(std::move(parts));
    case CsgOp::kIntersection:
      return intersect(std::move(parts));
    default:
      return subtract(std::move(parts));
  }
}

}  // namespace

EvaluateResult evaluate(const Solid& solid, const EvaluateOptions& options) {
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  EvaluateResult r;
  if (!is_bounded(solid))
    throw NotComputable("evaluate: the result is unbounded (a complement at the root); a B-rep "
                        "needs a bounded solid");
  auto t = Clock::now();
  if (options.check_leaves) {
    // One leaf per task (the test itself is serial); the first bad leaf by index is reported.
    std::vector<uint8_t> bad(solid.leaves.size(), 0);
    parallel_for(solid.leaves.size(), 1, [&](size_t begin, size_t end) {
      for (size_t l = begin; l < end; ++l)
        bad[l] = self_intersects(leaf_mesh(solid, static_cast<uint32_t>(l)));
    });
    std::vector<std::optional<Solid>> split(solid.leaves.size());
    bool any = false;
    for (uint32_t l = 0; l < solid.leaves.size(); ++l)
      if (bad[l]) {
        split[l] = shell_union(solid, l);
        any = true;
        if (split[l]) continue;
        const Leaf& leaf = solid.leaves[l];
        throw InputError((leaf.origin.empty() ? leaf.name : leaf.origin + " (" + leaf.name + ")") +
                         ": leaf is self-intersecting (beyond overlapping outward shells); "
                         "evaluate needs its shells free of self-intersections");
      }
    if (any) {
      EvaluateOptions again = options;
      again.check_leaves = false;  // the shells were checked
      return evaluate(rebuild(solid, solid.tree.root, split), again);
    }
  }
  r.seconds.check = since(t);
  const size_t grain = options.grain == 0 ? 1 : options.grain;
  const boolean_detail::Arrangement arr =
      boolean_detail::build_arrangement(solid, grain, r.seconds);
  r.candidate_pairs = arr.candidate_pairs;
  r.intersecting_pairs = arr.intersecting_pairs;
  t = Clock::now();
  const auto kept = boolean_detail::select_pieces(solid, arr, grain, r.patches);
  r.seconds.select = since(t);
  t = Clock::now();
  r.mesh = boolean_detail::assemble(arr, kept);
  for (size_t f = 0; f < r.mesh.face_count(); ++f) {
    auto t = r.mesh.face(f);
    const Vec3 a = r.mesh.vertices[t[0]], b = r.mesh.vertices[t[1]], c = r.mesh.vertices[t[2]];
    r.volume += dot(a, cross(b, c)) / 6;
    const Vec3 n = cross(b - a, c - a);
    r.area += 0.5 * std::sqrt(dot(n, n));
  }
  if (r.mesh.face_count() > 0) {
    const brep::BrepReport report = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(r.mesh));
    r.components = report.components;
    r.genus = report.genus;
  }
  r.seconds.assemble = since(t);
  return r;
}

}  // namespace cover
