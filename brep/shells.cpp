// Shells of a closed triangle mesh (detail/shells.h).
//
// Notation: at an undirected edge {a, b} (a < b), a "forward" triangle holds a → b and a
// "backward" one b → a. Around the axis d = b − a, angles θ grow by the right-hand rule; a
// forward triangle (a, b, w) has its outward normal d × (w − a) towards growing θ, so its solid
// lies towards decreasing θ (clockwise), and the first triangle met clockwise from w bounds the
// same solid: a backward one on a valid input. orient3d(a, b, x, y) > 0 iff y is less than half
// a turn counter-clockwise from x.
#include "cover/brep/detail/shells.h"

#include <algorithm>
#include <array>
#include <string>
#include <tuple>

#include "cover/brep/halfedge.h"
#include "cover/solid/errors.h"
#include "cover/solid/predicates.h"
#include "cover/solid/union_find.h"

namespace cover::brep::detail {
namespace {

struct Side {
  uint32_t lo, hi;  ///< the undirected edge
  uint32_t face;
  uint32_t third;  ///< the triangle's vertex off the edge
  bool forward;    ///< holds lo → hi
};

/// Rank of x by its clockwise angle from w around a → b: 0 in (0, π), 1 at π, 2 in (π, 2π),
/// 3 at 0 (x on w's ray: overlapping triangles, never on valid input).
int half_turn(const Vec3& a, const Vec3& b, const Vec3& w, const Vec3& x) {
  const int s = orient3d(a, b, w, x);
  if (s != 0) return s < 0 ? 0 : 2;
  for (int axis = 0; axis < 3; ++axis)
    if (const int sw = orient2d(a, b, w, axis)) return orient2d(a, b, x, axis) == sw ? 3 : 1;
  return 1;  // w on the line ab (a zero-area triangle): no side
}

}  // namespace

std::vector<PolygonMesh> split_shells(const PolygonMesh& t) {
  const size_t nf = t.face_count();
  std::vector<Side> sides;
  sides.reserve(3 * nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const auto v = t.face(f);
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = v[k], b = v[(k + 1) % 3], w = v[(k + 2) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), f, w, a < b});
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return std::tie(x.lo, x.hi, x.forward, x.face) < std::tie(y.lo, y.hi, y.forward, y.face);
  });
  UnionFind uf(nf);
  const auto& P = t.vertices;
  for (size_t i = 0; i < sides.size();) {
    size_t j = i;
    while (j < sides.size() && sides[j].lo == sides[i].lo && sides[j].hi == sides[i].hi) ++j;
    // [i, m): backward, [m, j): forward (false sorts first).
    size_t m = i;
    while (m < j && !sides[m].forward) ++m;
    if (m - i != j - m)
      throw InputError("edge " + std::to_string(sides[i].lo) + "-" + std::to_string(sides[i].hi) +
                       " is held by " + std::to_string(j - m) + " faces one way and " +
                       std::to_string(m - i) + " the other (not a closed oriented surface)");
    if (j - m == 1) {
      uf.unite(sides[i].face, sides[m].face);
    } else {
      const Vec3 &a = P[sides[i].lo], &b = P[sides[i].hi];
      for (size_t f = m; f < j; ++f) {
        const Vec3& w = P[sides[f].third];
        size_t best = i;
        int best_rank = half_turn(a, b, w, P[sides[i].third]);
        for (size_t g = i + 1; g < m; ++g) {
          const Vec3& x = P[sides[g].third];
          const int rank = half_turn(a, b, w, x);
          // Within one half turn, x comes first (smaller clockwise angle) iff the best so far
          // is less than half a turn clockwise from it.
          if (rank < best_rank || (rank == best_rank && (rank == 0 || rank == 2) &&
                                   orient3d(a, b, P[sides[best].third], x) > 0)) {
            best = g;
            best_rank = rank;
          }
        }
        uf.unite(sides[f].face, sides[best].face);
      }
    }
    i = j;
  }
  // One mesh per class, in the order of the classes' first triangles.
  std::vector<uint32_t> shell_of(nf, kNone);
  std::vector<std::vector<uint32_t>> faces;
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t root = uf.find(f);
    if (shell_of[root] == kNone) {
      shell_of[root] = static_cast<uint32_t>(faces.size());
      faces.emplace_back();
    }
    faces[shell_of[root]].push_back(f);
  }
  std::vector<uint32_t> local(P.size(), kNone), owner(P.size(), kNone);
  std::vector<PolygonMesh> out(faces.size());
  for (uint32_t s = 0; s < faces.size(); ++s) {
    PolygonMesh& m = out[s];
    for (const uint32_t f : faces[s]) {
      std::array<uint32_t, 3> ids{};
      const auto v = t.face(f);
      for (int k = 0; k < 3; ++k) {
        if (owner[v[k]] != s) {
          owner[v[k]] = s;
          local[v[k]] = static_cast<uint32_t>(m.vertices.size());
          m.vertices.push_back(P[v[k]]);
        }
        ids[k] = local[v[k]];
      }
      m.add_face({ids[0], ids[1], ids[2]});
    }
  }
  return out;
}

}  // namespace cover::brep::detail
