// Step 6 of evaluate() (boolean/evaluate.h): a 2-manifold mesh from the kept triangles.
//
// Notation
//   half-edge h = 3·f + e   edge e of kept triangle f, from v[e] to v[e+1]
//   corner 3·f + i          vertex v[i] of triangle f
//   edge p–q                undirected, p < q (point ids); θ is the angle of a triangle's
//                           half-plane around the axis p → q (right-hand rule)
//
// Around an edge with 2k > 2 triangles (e.g. two cubes sharing an edge), a triangle using p → q
// has its normal towards increasing θ (its inside at θ−), one using q → p its inside at θ+.
// Sorted by exact θ, the solid sectors are those between a "q → p" triangle and the next
// triangle, which must use p → q: each such pair becomes one manifold edge. Corners are then
// merged across paired edges; each class of corners (one fan) becomes an output vertex, so
// non-manifold edges and vertices (touching at an edge or a point) get topologically
// duplicated vertices at the same position. Where a touching curve is a single edge whose two
// ends are each one fan (the solids merge beyond both ends, e.g. a region wound −1 meeting a
// sphere's inside across a plane), both copies of the edge join the same two vertices; the
// copies are then split at their midpoint (a new vertex per copy, at one position, its two
// faces halved), so that no two edges join the same vertices.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "cover/boolean/detail/arrangement.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::boolean_detail {
namespace {

/// The exact value rounded to the nearest double (ties to the even neighbour).
template <class ET>
double nearest_exact(const ET& e) {
  const std::pair<double, double> i = CGAL::to_interval(e);
  if (i.first == i.second) return i.first;
  const ET mid = (ET(i.first) + ET(i.second)) / 2;
  if (e < mid) return i.first;
  if (e > mid) return i.second;
  uint64_t bits;  // a tie: the neighbour with the even mantissa
  std::memcpy(&bits, &i.first, sizeof bits);
  return (bits & 1) == 0 ? i.first : i.second;
}
double nearest(const K::FT& x) { return nearest_exact(CGAL::exact(x)); }

/// Angular class of r around p → q relative to r0: 0 at θ = 0, 1 in (0, π), 2 at π, 3 in (π, 2π).
int quadrant(const Point& p, const Point& q, const Point& r0, const Point& r) {
  const CGAL::Orientation s = CGAL::orientation(p, q, r0, r);
  if (s == CGAL::POSITIVE) return 1;
  if (s == CGAL::NEGATIVE) return 3;
  const K::Vector_3 a = q - p;
  return CGAL::sign(CGAL::cross_product(a, r0 - p) * CGAL::cross_product(a, r - p)) ==
                 CGAL::POSITIVE
             ? 0
             : 2;
}

}  // namespace

double exact_volume(const Arrangement& arr, const std::vector<std::array<uint32_t, 3>>& tris) {
  using ET = K::Exact_kernel::FT;  // GMP rationals
  constexpr size_t kChunk = 4096;
  std::vector<ET> partial((tris.size() + kChunk - 1) / kChunk);
  parallel_for(tris.size(), kChunk, [&](size_t begin, size_t end) {
    ET sum = 0;
    for (size_t t = begin; t < end; ++t) {
      const auto& a = CGAL::exact(arr.points[tris[t][0]]);
      const auto& b = CGAL::exact(arr.points[tris[t][1]]);
      const auto& c = CGAL::exact(arr.points[tris[t][2]]);
      sum += a.x() * (b.y() * c.z() - b.z() * c.y()) + a.y() * (b.z() * c.x() - b.x() * c.z()) +
             a.z() * (b.x() * c.y() - b.y() * c.x());
    }
    partial[begin / kChunk] = sum;
  });
  ET total = 0;
  for (const ET& x : partial) total += x;
  const ET volume = total / 6;
  const double rounded = nearest(K::FT(volume));
  if (CGAL::sign(volume) != CGAL::ZERO && !(std::abs(rounded) >= DBL_MIN)) {
    // Below the normal doubles (a solid of side < ~1e-103): 0 or a subnormal with few digits
    // would claim an exact volume it is not. Its decimal exponent, for the message: the volume
    // scaled by 2^1000 per step (exact) until it is a normal double.
    ET scaled = volume < 0 ? -volume : volume;
    int steps = 0;
    while (CGAL::to_double(scaled) < DBL_MIN) scaled = scaled * ET(0x1p1000), ++steps;
    const double log10 = std::log10(CGAL::to_double(scaled)) - 1000.0 * steps * std::log10(2.0);
    const double exponent = std::floor(log10);
    char text[64];
    std::snprintf(text, sizeof text, "%.3ge%+.0f", std::pow(10.0, log10 - exponent), exponent);
    throw NotComputable(std::string("evaluate: the exact volume, about ") + text +
                        ", is below the normal doubles (2.2e-308): not representable");
  }
  return rounded;
}

ExactCrossing exact_crossing(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q,
                             const Vec3& r) {
  using F = CGAL::Mpzf;
  auto diff = [](const Vec3& x, const Vec3& y) {
    return std::array<F, 3>{F(x.x) - F(y.x), F(x.y) - F(y.y), F(x.z) - F(y.z)};
  };
  const std::array<F, 3> u = diff(q, p), v = diff(r, p), ap = diff(a, p), bp = diff(b, p);
  const std::array<F, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                           u[0] * v[1] - u[1] * v[0]};
  const F da = n[0] * ap[0] + n[1] * ap[1] + n[2] * ap[2];
  const F db = n[0] * bp[0] + n[1] * bp[1] + n[2] * bp[2];
  return {{F(b.x) * da - F(a.x) * db, F(b.y) * da - F(a.y) * db, F(b.z) * da - F(a.z) * db},
          da - db};
}

/// Each coordinate's nearest double lies among the doubles of the lazy point's interval `box`
/// (which contains the exact value); starting from the quotient of the Mpzf approximations of
/// x and w (a few ulps off), it is found by exact comparisons with the midpoints between
/// neighbours, sign(2·x − (x₀ + x₁)·w). Rounding through the lazy exact value (GMP over the
/// construction DAG) would be the largest share of assembly.
bool round_crossing(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r,
                    const K::Approximate_kernel::Point_3& box, Vec3& out) {
  using F = CGAL::Mpzf;
  const ExactCrossing e = exact_crossing(a, b, p, q, r);
  const F& d = e.w;
  const int sd = d.sign();
  if (sd == 0) return false;  // not a crossing (precondition): leave it to the exact path
  double xyz[3];
  for (int c = 0; c < 3; ++c) {
    const double lo = box[c].inf(), hi = box[c].sup();
    if (!std::isfinite(lo) || !std::isfinite(hi)) return false;
    if (lo == hi) {
      xyz[c] = lo;
      continue;
    }
    const F twice_n = e.x[c] * F(2.0);
    // sign(X − (x0 + x1)/2) for neighbours x0 < x1
    auto above_mid = [&](double x0, double x1) {
      return (twice_n - (F(x0) + F(x1)) * d).sign() * sd;
    };
    auto even = [](double x0, double x1) {
      uint64_t bits;
      std::memcpy(&bits, &x0, sizeof bits);
      return (bits & 1) == 0 ? x0 : x1;
    };
    // Start from the quotient of the two Mpzf approximations (a few ulps off), then step.
    double x = twice_n.to_double() / (2 * d.to_double());
    x = std::isfinite(x) ? std::clamp(x, lo, hi) : lo;
    for (int step = 0;; ++step) {
      if (step == 8) return false;  // far from the estimate: the exact path
      if (x < hi) {
        const double up = std::nextafter(x, hi);
        const int s = above_mid(x, up);
        if (s > 0) {
          x = up;
          continue;
        }
        if (s == 0) {
          x = even(x, up);
          break;
        }
      }
      if (x > lo) {
        const double down = std::nextafter(x, lo);
        const int s = above_mid(down, x);
        if (s < 0) {
          x = down;
          continue;
        }
        if (s == 0) x = even(down, x);
      }
      break;
    }
    xyz[c] = x;
  }
  out = {xyz[0], xyz[1], xyz[2]};
  return true;
}

PolygonMesh assemble(const Arrangement& arr, const std::vector<std::array<uint32_t, 3>>& tris,
                     std::vector<uint32_t>* labels, std::vector<uint8_t>* rounded_vertex,
                     const std::vector<uint32_t>* grouped) {
  const size_t m = tris.size();
  auto from = [&](uint32_t h) { return tris[h / 3][h % 3]; };
  auto to = [&](uint32_t h) { return tris[h / 3][(h % 3 + 1) % 3]; };
  auto third = [&](uint32_t h) { return tris[h / 3][(h % 3 + 2) % 3]; };
  std::vector<uint32_t> own, bucket;  // the grouping, when the caller has none
  if (grouped == nullptr) group_half_edges(m, arr.points.size(), from, to, own, bucket);
  const std::vector<uint32_t>& hs = grouped != nullptr ? *grouped : own;

  UnionFind corners(3 * m);
  std::vector<uint32_t> mate(3 * m, kNone);
  auto pair_up = [&](uint32_t h, uint32_t g) {  // h: a → b, g: b → a
    corners.unite(h, 3 * (g / 3) + (g % 3 + 1) % 3);
    corners.unite(3 * (h / 3) + (h % 3 + 1) % 3, g);
    mate[h] = g;
    mate[g] = h;
  };
  std::vector<uint32_t> group;
  std::vector<uint32_t> crowded;  // the half-edges of groups of more than two
  for (size_t i = 0; i < hs.size();) {
    const uint64_t key = edge_key(from(hs[i]), to(hs[i]));
    size_t j = i;
    group.clear();
    while (j < hs.size() && edge_key(from(hs[j]), to(hs[j])) == key) group.push_back(hs[j++]);
    i = j;
    const uint32_t p = static_cast<uint32_t>(key >> 32);
    auto forward = [&](uint32_t h) { return from(h) == p; };
    if (group.size() % 2 != 0)
      throw InternalError("evaluate: an edge of the result has an odd number of faces");
    if (group.size() == 2) {
      if (forward(group[0]) == forward(group[1]))
        throw InternalError("evaluate: inconsistent orientation at an edge of the result");
      pair_up(group[0], group[1]);
      continue;
    }
    crowded.insert(crowded.end(), group.begin(), group.end());
    const Point& pp = arr.points[p];
    const Point& qq = arr.points[static_cast<uint32_t>(key & 0xffffffffu)];
    const Point& r0 = arr.points[third(group[0])];
    std::vector<std::pair<int, uint32_t>> order;
    for (uint32_t h : group) order.emplace_back(quadrant(pp, qq, r0, arr.points[third(h)]), h);
    std::stable_sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
      if (x.first != y.first) return x.first < y.first;
      if (x.first == 0 || x.first == 2) return false;
      return CGAL::orientation(pp, qq, arr.points[third(x.second)], arr.points[third(y.second)]) ==
             CGAL::POSITIVE;
    });
    const size_t k = order.size();
    for (size_t x = 0; x < k; ++x) {
      const uint32_t h = order[x].second;
      if (forward(h)) continue;
      const uint32_t g = order[(x + 1) % k].second;
      if (!forward(g))
        throw InternalError("evaluate: faces around a non-manifold edge do not alternate");
      pair_up(h, g);
    }
  }

  // Rounding needs each constructed point's exact value (rationals): the dominant cost of this
  // step, so it runs in parallel over the distinct constructed points used.
  // slot[id − originals]: the index in `constructed` (increasing id) of each one used.
  const size_t first = arr.originals.size();
  std::vector<uint32_t> slot(arr.points.size() - first, kNone);
  for (const auto& t : tris)
    for (uint32_t id : t)
      if (id >= first) slot[id - first] = 0;
  std::vector<uint32_t> constructed;
  for (size_t x = 0; x < slot.size(); ++x)
    if (slot[x] == 0) {
      slot[x] = static_cast<uint32_t>(constructed.size());
      constructed.push_back(static_cast<uint32_t>(first + x));
    }
  std::vector<Vec3> rounded(constructed.size());
  parallel_for(constructed.size(), 64, [&](size_t begin, size_t end) {
    for (size_t x = begin; x < end; ++x) {
      const uint32_t id = constructed[x];
      const Point& p = arr.points[id];
      if (id >= arr.first_crossing && id - arr.first_crossing < arr.crossings.size()) {
        const auto& [a, b, t] = arr.crossings[id - arr.first_crossing];
        const auto& w = arr.tris[t].v;
        const std::vector<Vec3>& o = arr.originals;
        if (round_crossing(o[a], o[b], o[w[0]], o[w[1]], o[w[2]], CGAL::approx(p), rounded[x]))
          continue;
      }
      const auto& e = CGAL::exact(p);
      rounded[x] = {nearest_exact(e.x()), nearest_exact(e.y()), nearest_exact(e.z())};
    }
  });
  PolygonMesh mesh;
  std::vector<uint32_t> vertex(3 * m, kNone);
  for (uint32_t c = 0; c < 3 * m; ++c) {
    const uint32_t root = corners.find(c);
    if (vertex[root] == kNone) {
      const uint32_t id = tris[c / 3][c % 3];
      vertex[root] = static_cast<uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(id < first ? arr.originals[id] : rounded[slot[id - first]]);
      if (rounded_vertex) rounded_vertex->push_back(id >= arr.originals.size());
    }
    vertex[c] = vertex[root];
  }
  // Second copies of an output edge (same two vertices, same direction): split at the midpoint.
  // Both copies join the same two points, so they are in one group of the pairing above, and a
  // group of two is one copy each way: only the crowded groups' half-edges can be copies.
  std::vector<std::array<uint32_t, 3>> faces(m);
  for (uint32_t f = 0; f < m; ++f) faces[f] = {vertex[3 * f], vertex[3 * f + 1], vertex[3 * f + 2]};
  std::vector<std::pair<uint64_t, uint32_t>> directed(crowded.size());
  for (size_t x = 0; x < crowded.size(); ++x) {
    const uint32_t h = crowded[x];
    directed[x] = {(uint64_t{vertex[h]} << 32) | vertex[3 * (h / 3) + (h % 3 + 1) % 3], h};
  }
  std::sort(directed.begin(), directed.end());
  std::vector<uint8_t> split(m, 0);
  std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> extra;  // (face, split-from face)
  for (size_t i = 0, j; i < directed.size(); i = j) {
    for (j = i + 1; j < directed.size() && directed[j].first == directed[i].first;) ++j;
    if (j - i < 2) continue;
    // Every copy gets its own midpoint vertex (all at one position, like the ends).
    for (size_t x = i; x < j; ++x) {
      const uint32_t h = directed[x].second, g = mate[h];
      if (g == kNone) continue;
      const uint32_t f = h / 3, f2 = g / 3;
      if (f == f2 || split[f] || split[f2]) continue;  // (not seen in practice)
      split[f] = split[f2] = 1;
      const uint32_t a = vertex[h], b = vertex[g];
      const uint32_t c1 = faces[f][(h % 3 + 2) % 3], c2 = faces[f2][(g % 3 + 2) % 3];
      const uint32_t mid = static_cast<uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(0.5 * (mesh.vertices[a] + mesh.vertices[b]));
      if (rounded_vertex) rounded_vertex->push_back(1);
      faces[f] = {a, mid, c1};
      extra.push_back({{mid, b, c1}, f});
      faces[f2] = {b, mid, c2};
      extra.push_back({{mid, a, c2}, f2});
    }
  }
  for (const auto& t : faces) mesh.add_face({t[0], t[1], t[2]});
  for (const auto& [t, from] : extra) {
    mesh.add_face({t[0], t[1], t[2]});
    if (labels) labels->push_back((*labels)[from]);
  }
  return mesh;
}

}  // namespace cover::boolean_detail
