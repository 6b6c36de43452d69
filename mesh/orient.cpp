// Repeated loops and consistent orientation of closed leaves (orient.h).
// Notation: a side is one present half-edge (u, v), u != v, of a face's loop; its undirected
// edge is key(u, v) = min·2³² + max and its direction +1 when u < v, else −1. An edge is
// balanced when its sides' directions sum to 0.

#include "cover/mesh/orient.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

uint64_t edge_key(uint32_t u, uint32_t v) {
  return u < v ? (uint64_t{u} << 32 | v) : (uint64_t{v} << 32 | u);
}

struct Side {
  uint64_t key;
  uint32_t face;
  int8_t dir;
};

/// Calls visit(face, u, v) for every side (u, v), u != v, of every face.
template <typename Visit>
void for_each_side(const PolygonMesh& mesh, Visit visit) {
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    for (size_t i = 0; i < loop.size(); ++i) {
      const uint32_t u = loop[i], v = loop[(i + 1) % loop.size()];
      if (u != v) visit(f, u, v);
    }
  }
}

/// Every side of every face, sorted by (edge, face).
std::vector<Side> sorted_sides(const PolygonMesh& mesh) {
  std::vector<Side> sides;
  sides.reserve(mesh.face_vertices.size());
  for_each_side(mesh, [&](uint32_t f, uint32_t u, uint32_t v) {
    sides.push_back({edge_key(u, v), f, static_cast<int8_t>(u < v ? 1 : -1)});
  });
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
    return a.key != b.key ? a.key < b.key : a.face < b.face;
  });
  return sides;
}

/// True when every edge is balanced: the multiset of edges traversed low→high equals the one
/// traversed high→low (two parallel sorts of 64-bit keys; the common, already valid case).
bool all_balanced(const PolygonMesh& mesh) {
  std::vector<uint64_t> up, down;
  up.reserve(mesh.face_vertices.size() / 2 + 1);
  down.reserve(mesh.face_vertices.size() / 2 + 1);
  for_each_side(mesh, [&](uint32_t, uint32_t u, uint32_t v) {
    (u < v ? up : down).push_back(edge_key(u, v));
  });
  if (up.size() != down.size()) return false;
  parallel_sort(up);
  parallel_sort(down);
  return up == down;
}

std::string edge_name(uint64_t key) {
  return std::to_string(key >> 32) + "-" + std::to_string(key & 0xFFFFFFFFu);
}

/// Sides grouped by edge: [group[i], group[i+1]) index `sides`.
std::vector<size_t> edge_groups(const std::vector<Side>& sides) {
  std::vector<size_t> group;
  for (size_t s = 0; s < sides.size(); ++s)
    if (s == 0 || sides[s].key != sides[s - 1].key) group.push_back(s);
  group.push_back(sides.size());
  return group;
}

double face_area(const PolygonMesh& mesh, size_t f) {
  const auto loop = mesh.face(f);
  Vec3 n{};
  for (size_t i = 0; i < loop.size(); ++i)
    n = n + cross(mesh.vertices[loop[i]], mesh.vertices[loop[(i + 1) % loop.size()]]);
  return 0.5 * std::sqrt(dot(n, n));
}

/// Patches (components through two-sided edges) meeting an unbalanced edge get a coefficient
/// keep (1), flip (−1) or drop (0); the cheapest assignment that balances every edge they touch
/// wins (least dropped area, then least flipped area, then the first in enumeration order). With
/// at most kMaxPatches candidates the 3^k search is at most 59049 assignments.
constexpr size_t kMaxPatches = 10;

}  // namespace

size_t collapse_repeated_loops(PolygonMesh& mesh, size_t* first) {
  size_t changed = 0;
  PolygonMesh out;
  out.vertices = std::move(mesh.vertices);
  out.face_start.reserve(mesh.face_start.size());
  out.face_vertices.reserve(mesh.face_vertices.size());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    const size_t n = loop.size();
    size_t period = n;
    // The smallest period p dividing n with loop[i] == loop[i − p] for all i ≥ p.
    for (size_t p = 1; p < n && period == n; ++p)
      if (n % p == 0 && std::equal(loop.begin() + p, loop.end(), loop.begin())) period = p;
    if (period < n) {
      if (changed++ == 0 && first) *first = f;
    }
    out.add_face(loop.subspan(0, period));
  }
  if (changed == 0) {
    mesh.vertices = std::move(out.vertices);
    return 0;
  }
  mesh = std::move(out);
  return changed;
}

OrientResult orient_consistently(PolygonMesh& mesh, const std::string& where) {
  OrientResult result;
  if (all_balanced(mesh)) return result;
  const std::vector<Side> sides = sorted_sides(mesh);
  const std::vector<size_t> group = edge_groups(sides);
  // Constraints from edges with exactly two sides in different faces: flip[f] ^ flip[g] must be
  // (dir_f == dir_g). adjacent[degree[f] .. degree[f+1]) lists (g, must_differ).
  const size_t faces = mesh.face_count();
  std::vector<uint32_t> degree(faces + 1, 0);
  struct Link {
    uint32_t a, b;
    bool differ;
  };
  std::vector<Link> links;
  for (size_t g = 0; g + 1 < group.size(); ++g) {
    const size_t s = group[g];
    if (group[g + 1] - s == 2 && sides[s].face != sides[s + 1].face) {
      links.push_back({sides[s].face, sides[s + 1].face, sides[s].dir == sides[s + 1].dir});
      ++degree[sides[s].face + 1];
      ++degree[sides[s + 1].face + 1];
    }
  }
  for (size_t f = 0; f < faces; ++f) degree[f + 1] += degree[f];
  std::vector<std::pair<uint32_t, bool>> adjacent(degree.back());
  {
    std::vector<uint32_t> fill(degree.begin(), degree.end() - 1);
    for (const Link& l : links) {
      adjacent[fill[l.a]++] = {l.b, l.differ};
      adjacent[fill[l.b]++] = {l.a, l.differ};
    }
  }
  constexpr uint32_t kUnset = UINT32_MAX;
  std::vector<uint8_t> flip(faces, 0);
  std::vector<uint32_t> patch(faces, kUnset), component, queue;
  std::vector<size_t> patch_flips;
  for (uint32_t root = 0; root < faces; ++root) {
    if (patch[root] != kUnset) continue;
    const auto id = static_cast<uint32_t>(patch_flips.size());
    patch[root] = id;
    component.assign(1, root);
    queue.assign(1, root);
    while (!queue.empty()) {
      const uint32_t f = queue.back();
      queue.pop_back();
      for (uint32_t k = degree[f]; k < degree[f + 1]; ++k) {
        const auto [g, differ] = adjacent[k];
        const uint8_t want = static_cast<uint8_t>(flip[f] ^ (differ ? 1 : 0));
        if (patch[g] == kUnset) {
          patch[g] = id;
          flip[g] = want;
          component.push_back(g);
          queue.push_back(g);
        } else if (flip[g] != want) {
          throw InputError(where + ": non-orientable surface: faces " + std::to_string(f) +
                           " and " + std::to_string(g) +
                           " (counting from 0) admit no consistent orientation");
        }
      }
    }
    size_t flips = 0;
    for (uint32_t f : component) flips += flip[f];
    if (2 * flips > component.size()) {  // keep the majority's orientation
      for (uint32_t f : component) flip[f] ^= 1;
      flips = component.size() - flips;
    }
    patch_flips.push_back(flips);
  }
  // Oriented direction of a side, and the edges still unbalanced.
  auto dir = [&](const Side& side) { return flip[side.face] ? -side.dir : side.dir; };
  std::vector<size_t> unbalanced;
  for (size_t g = 0; g + 1 < group.size(); ++g) {
    int net = 0;
    for (size_t s = group[g]; s < group[g + 1]; ++s) net += dir(sides[s]);
    if (net != 0) unbalanced.push_back(g);
  }
  std::vector<int8_t> coefficient(patch_flips.size(), 1);  // 1 keep, −1 flip, 0 drop
  if (!unbalanced.empty()) {
    // Candidate patches: those with a side on an unbalanced edge.
    std::vector<uint32_t> candidates;
    for (size_t g : unbalanced)
      for (size_t s = group[g]; s < group[g + 1]; ++s) candidates.push_back(patch[sides[s].face]);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    const auto fail = [&](size_t g) {
      int net = 0;
      for (size_t s = group[g]; s < group[g + 1]; ++s) net += dir(sides[s]);
      throw InputError(where + ": face " + std::to_string(sides[group[g]].face) +
                       " (counting from 0): edge " + edge_name(sides[group[g]].key) +
                       " is traversed " + std::to_string(std::abs(net)) +
                       " more time(s) in one direction than in the other (not a closed, "
                       "orientable surface)");
    };
    if (candidates.size() > kMaxPatches) fail(unbalanced[0]);
    std::vector<int> slot(patch_flips.size(), -1);
    for (size_t i = 0; i < candidates.size(); ++i) slot[candidates[i]] = static_cast<int>(i);
    // Edges to balance: every edge with a side in a candidate patch that is not interior to one
    // patch (interior edges stay balanced under any coefficient of their patch).
    std::vector<size_t> junctions;
    for (size_t g = 0; g + 1 < group.size(); ++g) {
      bool touches = false, mixed = group[g + 1] - group[g] != 2;
      for (size_t s = group[g]; s < group[g + 1]; ++s) {
        touches = touches || slot[patch[sides[s].face]] >= 0;
        mixed = mixed || patch[sides[s].face] != patch[sides[group[g]].face];
      }
      if (touches && mixed) junctions.push_back(g);
    }
    std::vector<double> area(candidates.size(), 0);
    for (size_t f = 0; f < faces; ++f)
      if (slot[patch[f]] >= 0) area[static_cast<size_t>(slot[patch[f]])] += face_area(mesh, f);
    size_t total = 1;
    for (size_t i = 0; i < candidates.size(); ++i) total *= 3;
    std::vector<int8_t> c(candidates.size()), best;
    double best_drop = INFINITY, best_flip = INFINITY;
    for (size_t code = 0; code < total; ++code) {
      double drop = 0, flipped = 0;
      for (size_t i = 0, k = code; i < c.size(); ++i, k /= 3) {
        c[i] = static_cast<int8_t>(k % 3 == 0 ? 1 : (k % 3 == 1 ? 0 : -1));
        (c[i] == 0 ? drop : flipped) += c[i] == 1 ? 0 : area[i];
      }
      if (drop > best_drop || (drop == best_drop && flipped >= best_flip)) continue;
      bool ok = true;
      for (size_t j = 0; j < junctions.size() && ok; ++j) {
        int net = 0;
        for (size_t s = group[junctions[j]]; s < group[junctions[j] + 1]; ++s) {
          const int at = slot[patch[sides[s].face]];
          net += (at >= 0 ? c[static_cast<size_t>(at)] : 1) * dir(sides[s]);
        }
        ok = net == 0;
      }
      if (ok) {
        best = c;
        best_drop = drop;
        best_flip = flipped;
      }
    }
    if (best.empty() || best_drop == INFINITY) fail(unbalanced[0]);
    for (size_t i = 0; i < candidates.size(); ++i) coefficient[candidates[i]] = best[i];
  }
  // Apply: flip faces, drop the dropped patches' faces.
  PolygonMesh out;
  out.vertices = std::move(mesh.vertices);
  out.face_start.reserve(faces + 1);
  out.face_vertices.reserve(mesh.face_vertices.size());
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < faces; ++f) {
    const int8_t k = coefficient[patch[f]];
    if (k == 0) {
      ++result.dropped_faces;
      continue;
    }
    const auto in = mesh.face(f);
    loop.assign(in.begin(), in.end());
    if ((flip[f] != 0) != (k < 0)) {
      std::reverse(loop.begin(), loop.end());
      ++result.flipped_faces;
    }
    out.add_face(loop);
  }
  for (size_t p = 0; p < patch_flips.size(); ++p)
    if ((coefficient[p] == 1 && patch_flips[p] > 0) || coefficient[p] == -1) ++result.components;
  mesh = std::move(out);
  return result;
}

}  // namespace cover
