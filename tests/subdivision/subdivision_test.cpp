// subdivision/subdivide.h against CGAL 5.5's Subdivision_method_3 (one step: the same doubles
// after matching vertices by position, identical faces), against textbook stencils in exact
// rationals (the documented output order), the per-level counts, thread-count independence and
// errors.
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <string>
#include <unordered_map>
#include <vector>

#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/subdivision/subdivide.h"
#include "helpers.h"

namespace cover {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Q = CGAL::Gmpq;

#ifdef COVER_SANITIZED
constexpr int kMaxLevel = 2;
#else
constexpr int kMaxLevel = 3;
#endif

// ---- Test meshes -------------------------------------------------------------------------------

PolygonMesh cube() {
  PolygonMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({double(i & 1), double(i >> 1 & 1), double(i >> 2)});
  m.add_face({0, 2, 3, 1});
  m.add_face({4, 5, 7, 6});
  m.add_face({0, 1, 5, 4});
  m.add_face({2, 6, 7, 3});
  m.add_face({0, 4, 6, 2});
  m.add_face({1, 3, 7, 5});
  return m;
}

/// The cube without its top face (a border of four edges).
PolygonMesh open_cube() {
  PolygonMesh c = cube(), m;
  m.vertices = c.vertices;
  for (size_t f = 0; f < c.face_count(); ++f)
    if (f != 1) m.add_face(c.face(f));
  return m;
}

/// A torus of n × k quads (radii 3 and 1).
PolygonMesh torus(uint32_t n, uint32_t k) {
  PolygonMesh m;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < k; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / k;
      m.vertices.push_back(
          {(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < k; ++j) {
      const uint32_t i1 = (i + 1) % n, j1 = (j + 1) % k;
      m.add_face({i * k + j, i1 * k + j, i1 * k + j1, i * k + j1});
    }
  return m;
}

/// An open n × n grid of quads over a bumpy height field.
PolygonMesh grid(uint32_t n) {
  PolygonMesh m;
  for (uint32_t i = 0; i <= n; ++i)
    for (uint32_t j = 0; j <= n; ++j)
      m.vertices.push_back({0.3 * i, 0.3 * j, 0.1 * std::sin(1.7 * i + 0.9 * j)});
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j)
      m.add_face(
          {i * (n + 1) + j, (i + 1) * (n + 1) + j, (i + 1) * (n + 1) + j + 1, i * (n + 1) + j + 1});
  return m;
}

/// A triangulated grid with alternating diagonals: interior valence 6 everywhere.
PolygonMesh regular_triangles(uint32_t n, bool closed) {
  PolygonMesh m = closed ? torus(n, n) : grid(n), t;
  t.vertices = m.vertices;
  for (size_t f = 0; f < m.face_count(); ++f) {
    const auto q = m.face(f);
    t.add_face({q[0], q[1], q[2]});
    t.add_face({q[0], q[2], q[3]});
  }
  return t;
}

// ---- CGAL ---------------------------------------------------------------------------------------

SurfaceMesh to_cgal(const PolygonMesh& m) {
  SurfaceMesh s;
  for (const Vec3& p : m.vertices) s.add_vertex(Kernel::Point_3(p.x, p.y, p.z));
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<SurfaceMesh::Vertex_index> loop;
    for (uint32_t v : m.face(f)) loop.push_back(SurfaceMesh::Vertex_index(v));
    if (s.add_face(loop) == SurfaceMesh::null_face()) ADD_FAILURE() << "CGAL refused face " << f;
  }
  return s;
}

PolygonMesh from_cgal(const SurfaceMesh& s) {
  PolygonMesh m;
  std::unordered_map<uint32_t, uint32_t> index;
  for (auto v : s.vertices()) {
    index[uint32_t(v)] = static_cast<uint32_t>(m.vertices.size());
    const auto& p = s.point(v);
    m.vertices.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : s.faces()) {
    std::vector<uint32_t> loop;
    for (auto v : CGAL::vertices_around_face(s.halfedge(f), s))
      loop.push_back(index.at(uint32_t(v)));
    m.add_face(loop);
  }
  return m;
}

PolygonMesh cgal_subdivide(const PolygonMesh& m, Scheme scheme, int levels) {
  SurfaceMesh s = to_cgal(m);
  const auto np = CGAL::parameters::number_of_iterations(levels);
  namespace SM = CGAL::Subdivision_method_3;
  switch (scheme) {
    case Scheme::kCatmullClark:
      SM::CatmullClark_subdivision(s, np);
      break;
    case Scheme::kLoop:
      SM::Loop_subdivision(s, np);
      break;
    case Scheme::kDooSabin:
      SM::DooSabin_subdivision(s, np);
      break;
    case Scheme::kSqrt3:
      SM::Sqrt3_subdivision(s, np);
      break;
  }
  return from_cgal(s);
}

// ---- Matching and comparison ------------------------------------------------------------------

uint64_t ulps(double a, double b) {
  const auto ordered = [](double d) {
    const auto i = std::bit_cast<int64_t>(d);
    return i < 0 ? std::numeric_limits<int64_t>::min() - i : i;
  };
  const int64_t x = ordered(a), y = ordered(b);
  return x > y ? uint64_t(x) - uint64_t(y) : uint64_t(y) - uint64_t(x);
}

/// match[i]: the vertex of `ref` at the position of vertex i of `m`. Unambiguous: exactly one
/// vertex of `ref` lies within 1e-9 of the bounding box's size, and cells are 1e-6 of it.
std::vector<uint32_t> match_vertices(const PolygonMesh& m, const PolygonMesh& ref) {
  const Bbox box = face_bbox(ref);
  double size = 0;
  for (int k = 0; k < 3; ++k) size = std::max(size, box.max[k] - box.min[k]);
  const double cell = 1e-6 * size, radius = 1e-9 * size;
  const auto key = [&](const Vec3& p, int dx, int dy, int dz) {
    const auto c = [&](double x, int d) {
      return uint64_t(int64_t(std::floor(x / cell)) + d) & 0x1fffff;
    };
    return c(p.x, dx) << 42 | c(p.y, dy) << 21 | c(p.z, dz);
  };
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
  for (uint32_t i = 0; i < ref.vertices.size(); ++i)
    cells[key(ref.vertices[i], 0, 0, 0)].push_back(i);
  std::vector<uint32_t> match(m.vertices.size(), UINT32_MAX);
  std::vector<uint8_t> used(ref.vertices.size(), 0);
  for (uint32_t i = 0; i < m.vertices.size(); ++i) {
    const Vec3 p = m.vertices[i];
    int found = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(key(p, dx, dy, dz));
          if (it == cells.end()) continue;
          for (uint32_t j : it->second) {
            const Vec3 d = ref.vertices[j] - p;
            if (std::sqrt(dot(d, d)) <= radius) match[i] = j, ++found;
          }
        }
    EXPECT_EQ(found, 1) << "vertex " << i << " matches " << found << " reference vertices";
    if (found == 1) {
      EXPECT_FALSE(used[match[i]]) << "reference vertex " << match[i] << " matched twice";
      used[match[i]] = 1;
    }
  }
  return match;
}

/// Faces as index cycles rotated to start at their smallest index, sorted.
std::vector<std::vector<uint32_t>> canonical_faces(const PolygonMesh& m,
                                                   const std::vector<uint32_t>* map) {
  std::vector<std::vector<uint32_t>> faces;
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t v : m.face(f)) loop.push_back(map ? (*map)[v] : v);
    std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    faces.push_back(loop);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

/// Distances between matched coordinates: `own` in ulps of the coordinates themselves (over
/// coordinates of at least 1/64 of the mesh's largest |coordinate| M, since near zero cancellation
/// makes any ulp count meaningless), `scaled` in ulps of M (every coordinate).
struct Agreement {
  uint64_t own = 0, scaled = 0;
};

/// Agreement of vertex i of `mine` with vertex match[i] of `ref`.
Agreement agreement(const std::vector<Vec3>& mine, const std::vector<Vec3>& ref,
                    const std::vector<uint32_t>& match) {
  double big = 0;
  for (const Vec3& p : ref)
    for (int k = 0; k < 3; ++k) big = std::max(big, std::abs(p[k]));
  const double ulp_big = std::nextafter(big, 2 * big) - big;
  Agreement a;
  for (size_t i = 0; i < match.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double x = mine[i][k], y = ref[match[i]][k];
      a.scaled = std::max(a.scaled, static_cast<uint64_t>(std::ceil(std::abs(x - y) / ulp_big)));
      if (std::abs(y) >= big / 64) a.own = std::max(a.own, ulps(x, y));
    }
  return a;
}

Agreement compare_with_cgal(const PolygonMesh& mine, const PolygonMesh& ref) {
  EXPECT_EQ(mine.vertices.size(), ref.vertices.size());
  EXPECT_EQ(mine.face_count(), ref.face_count());
  const std::vector<uint32_t> match = match_vertices(mine, ref);
  if (std::count(match.begin(), match.end(), UINT32_MAX) > 0 ||
      mine.vertices.size() != ref.vertices.size())
    return {UINT64_MAX, UINT64_MAX};
  EXPECT_EQ(canonical_faces(mine, &match), canonical_faces(ref, nullptr));
  return agreement(mine.vertices, ref.vertices, match);
}

const char* name(Scheme s) {
  switch (s) {
    case Scheme::kCatmullClark:
      return "CatmullClark";
    case Scheme::kLoop:
      return "Loop";
    case Scheme::kDooSabin:
      return "DooSabin";
    case Scheme::kSqrt3:
      return "Sqrt3";
  }
  return "";
}

bool has_border(const PolygonMesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> count;
  for (size_t f = 0; f < m.face_count(); ++f) {
    const auto loop = m.face(f);
    for (size_t i = 0; i < loop.size(); ++i) {
      const uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  }
  return std::any_of(count.begin(), count.end(), [](const auto& c) { return c.second == 1; });
}

/// Levels 1..max_level of `scheme` on `m` against CGAL: identical faces after matching vertices
/// by position; per step (both refine the same previous level, ours) the same doubles
/// (kStepUlps = 0: the same operands summed in the same order, detail/stencils.h); over all
/// levels (each side refining its own previous level) within kScaleUlps of the mesh's largest
/// coordinate: from level 2 on, CGAL circulates from the half-edges its in-place refinement
/// leaves, so the rounding of the two diverges (≤ 3 observed).
constexpr uint64_t kStepUlps = 0, kScaleUlps = 4;

void check_against_cgal(const std::string& label, const PolygonMesh& m, Scheme scheme,
                        int max_level) {
  PolygonMesh previous = m;
  const bool border = has_border(m);
  for (int level = 1; level <= max_level; ++level) {
    SCOPED_TRACE(label + " " + name(scheme) + " level " + std::to_string(level));
    const PolygonMesh mine = subdivide(m, {scheme, level});
    const Agreement all = compare_with_cgal(mine, cgal_subdivide(m, scheme, level));
    EXPECT_LE(all.scaled, kScaleUlps);
    // A fresh CGAL run does not split the border: compare √3 steps that do not either.
    Agreement step;
    if (scheme != Scheme::kSqrt3 || !border || level % 2 == 1) {
      step =
          compare_with_cgal(subdivide(previous, {scheme, 1}), cgal_subdivide(previous, scheme, 1));
      EXPECT_LE(step.own, kStepUlps);
    }
    std::printf(
        "[ ulp      ] %s %s L%d: %zu vertices; step %llu ulp; levels %llu ulp own, %llu scale\n",
        label.c_str(), name(scheme), level, mine.vertices.size(),
        static_cast<unsigned long long>(step.own), static_cast<unsigned long long>(all.own),
        static_cast<unsigned long long>(all.scaled));
    previous = mine;
  }
}

TEST(Subdivision, CatmullClarkMatchesCgal) {
  check_against_cgal("cube", cube(), Scheme::kCatmullClark, kMaxLevel);
  check_against_cgal("torus", torus(8, 6), Scheme::kCatmullClark, kMaxLevel);
  check_against_cgal("open cube", open_cube(), Scheme::kCatmullClark, kMaxLevel);
  check_against_cgal("grid", grid(4), Scheme::kCatmullClark, kMaxLevel);
  check_against_cgal("cross.off", read_mesh(test::cgal_mesh("cross.off")), Scheme::kCatmullClark,
                     kMaxLevel);
  check_against_cgal("pig.off", read_mesh(test::cgal_mesh("pig.off")), Scheme::kCatmullClark, 2);
}

TEST(Subdivision, LoopMatchesCgal) {
  check_against_cgal("cube", test::triangulate(cube()), Scheme::kLoop, kMaxLevel);
  check_against_cgal("torus", regular_triangles(6, true), Scheme::kLoop, kMaxLevel);
  check_against_cgal("open cube", test::triangulate(open_cube()), Scheme::kLoop, kMaxLevel);
  check_against_cgal("grid", regular_triangles(4, false), Scheme::kLoop, kMaxLevel);
  check_against_cgal("cross.off", read_mesh(test::cgal_mesh("cross.off")), Scheme::kLoop,
                     kMaxLevel);
  check_against_cgal("pig.off", read_mesh(test::cgal_mesh("pig.off")), Scheme::kLoop, 2);
}

TEST(Subdivision, DooSabinMatchesCgal) {
  check_against_cgal("cube", cube(), Scheme::kDooSabin, kMaxLevel);
  check_against_cgal("torus", torus(8, 6), Scheme::kDooSabin, kMaxLevel);
  check_against_cgal("open cube", open_cube(), Scheme::kDooSabin, kMaxLevel);
  check_against_cgal("grid", grid(4), Scheme::kDooSabin, kMaxLevel);
  check_against_cgal("cross.off", read_mesh(test::cgal_mesh("cross.off")), Scheme::kDooSabin,
                     kMaxLevel);
  check_against_cgal("pig.off", read_mesh(test::cgal_mesh("pig.off")), Scheme::kDooSabin, 2);
}

TEST(Subdivision, Sqrt3MatchesCgal) {
  check_against_cgal("cube", test::triangulate(cube()), Scheme::kSqrt3, kMaxLevel);
  check_against_cgal("torus", regular_triangles(6, true), Scheme::kSqrt3, kMaxLevel);
  check_against_cgal("open cube", test::triangulate(open_cube()), Scheme::kSqrt3, kMaxLevel);
  check_against_cgal("cross.off", read_mesh(test::cgal_mesh("cross.off")), Scheme::kSqrt3,
                     kMaxLevel);
}

TEST(Subdivision, ElephantMatchesCgal) {
  const PolygonMesh m = read_mesh(test::cgal_mesh("elephant.off"));
  for (Scheme s : {Scheme::kCatmullClark, Scheme::kLoop, Scheme::kDooSabin, Scheme::kSqrt3})
    check_against_cgal("elephant.off", m, s, 1);
}

// ---- Exact textbook stencils ------------------------------------------------------------------

struct QPoint {
  Q x, y, z;
};
QPoint operator+(const QPoint& a, const QPoint& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
QPoint operator*(const Q& s, const QPoint& a) { return {s * a.x, s * a.y, s * a.z}; }
QPoint q_of(const Vec3& p) { return {Q(p.x), Q(p.y), Q(p.z)}; }

/// The double nearest to q (ties to even), from the two doubles around it.
double nearest(const Q& q) {
  double lo = CGAL::to_double(q);
  while (Q(lo) > q) lo = std::nextafter(lo, -INFINITY);
  while (Q(std::nextafter(lo, INFINITY)) <= q) lo = std::nextafter(lo, INFINITY);
  if (Q(lo) == q) return lo;
  const double hi = std::nextafter(lo, INFINITY);
  const Q mid = (Q(lo) + Q(hi)) / Q(2);
  if (q != mid) return q < mid ? lo : hi;
  return (std::bit_cast<uint64_t>(lo) & 1) == 0 ? lo : hi;
}
Vec3 nearest(const QPoint& p) { return {nearest(p.x), nearest(p.y), nearest(p.z)}; }

/// Edges in order of first appearance (the documented order), their faces, vertex neighbours.
struct Adjacency {
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edge;
  std::vector<std::pair<uint32_t, uint32_t>> ends;
  std::vector<std::vector<uint32_t>> edge_faces, vertex_faces, neighbours, border_neighbours;
  explicit Adjacency(const PolygonMesh& m)
      : vertex_faces(m.vertices.size()),
        neighbours(m.vertices.size()),
        border_neighbours(m.vertices.size()) {
    for (uint32_t f = 0; f < m.face_count(); ++f) {
      const auto loop = m.face(f);
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
        const auto key = std::make_pair(std::min(a, b), std::max(a, b));
        auto [it, fresh] = edge.emplace(key, static_cast<uint32_t>(ends.size()));
        if (fresh) ends.push_back({a, b}), edge_faces.emplace_back();
        edge_faces[it->second].push_back(f);
        vertex_faces[a].push_back(f);
      }
    }
    for (size_t e = 0; e < ends.size(); ++e) {
      const auto [a, b] = ends[e];
      neighbours[a].push_back(b), neighbours[b].push_back(a);
      if (edge_faces[e].size() == 1)
        border_neighbours[a].push_back(b), border_neighbours[b].push_back(a);
    }
  }
};

QPoint face_point(const PolygonMesh& m, uint32_t f) {
  QPoint s{0, 0, 0};
  for (uint32_t v : m.face(f)) s = s + q_of(m.vertices[v]);
  return Q(1, int(m.face(f).size())) * s;
}

/// Textbook Catmull–Clark [V | E | F] with the border rules (1/2, 1/2) and (1/8, 6/8, 1/8).
std::vector<QPoint> textbook_catmull_clark(const PolygonMesh& m) {
  const Adjacency a(m);
  std::vector<QPoint> out(m.vertices.size() + a.ends.size() + m.face_count());
  for (uint32_t f = 0; f < m.face_count(); ++f)
    out[m.vertices.size() + a.ends.size() + f] = face_point(m, f);
  for (size_t e = 0; e < a.ends.size(); ++e) {
    const QPoint p = q_of(m.vertices[a.ends[e].first]) + q_of(m.vertices[a.ends[e].second]);
    out[m.vertices.size() + e] =
        a.edge_faces[e].size() == 1
            ? Q(1, 2) * p
            : Q(1, 4) * (p + face_point(m, a.edge_faces[e][0]) + face_point(m, a.edge_faces[e][1]));
  }
  for (uint32_t v = 0; v < m.vertices.size(); ++v) {
    const QPoint s = q_of(m.vertices[v]);
    if (!a.border_neighbours[v].empty()) {
      out[v] = Q(1, 8) * (q_of(m.vertices[a.border_neighbours[v][0]]) +
                          q_of(m.vertices[a.border_neighbours[v][1]])) +
               Q(3, 4) * s;
      continue;
    }
    const int n = int(a.neighbours[v].size());
    QPoint fq{0, 0, 0}, r{0, 0, 0};
    for (uint32_t f : a.vertex_faces[v]) fq = fq + face_point(m, f);
    for (uint32_t u : a.neighbours[v]) r = r + Q(1, 2) * (s + q_of(m.vertices[u]));
    out[v] = Q(1, n * n) * fq + Q(2, n * n) * r + Q(n - 3, n) * s;
  }
  return out;
}

/// Textbook Loop [V | E] for meshes whose interior vertices have valence 6.
std::vector<QPoint> textbook_loop(const PolygonMesh& m) {
  const Adjacency a(m);
  std::vector<QPoint> out(m.vertices.size() + a.ends.size());
  const auto opposite = [&](uint32_t f, uint32_t x, uint32_t y) {
    for (uint32_t v : m.face(f))
      if (v != x && v != y) return v;
    return UINT32_MAX;
  };
  for (size_t e = 0; e < a.ends.size(); ++e) {
    const auto [x, y] = a.ends[e];
    const QPoint p = q_of(m.vertices[x]) + q_of(m.vertices[y]);
    if (a.edge_faces[e].size() == 1) {
      out[m.vertices.size() + e] = Q(1, 2) * p;
      continue;
    }
    out[m.vertices.size() + e] =
        Q(3, 8) * p + Q(1, 8) * (q_of(m.vertices[opposite(a.edge_faces[e][0], x, y)]) +
                                 q_of(m.vertices[opposite(a.edge_faces[e][1], x, y)]));
  }
  for (uint32_t v = 0; v < m.vertices.size(); ++v) {
    const QPoint s = q_of(m.vertices[v]);
    if (!a.border_neighbours[v].empty()) {
      out[v] = Q(1, 8) * (q_of(m.vertices[a.border_neighbours[v][0]]) +
                          q_of(m.vertices[a.border_neighbours[v][1]])) +
               Q(3, 4) * s;
      continue;
    }
    EXPECT_EQ(a.neighbours[v].size(), 6u);
    QPoint r{0, 0, 0};
    for (uint32_t u : a.neighbours[v]) r = r + q_of(m.vertices[u]);
    out[v] = Q(5, 8) * s + Q(1, 16) * r;
  }
  return out;
}

/// Textbook Doo–Sabin corners of a quad mesh: (9, 3, 1, 3)/16.
std::vector<QPoint> textbook_doo_sabin(const PolygonMesh& m) {
  std::vector<QPoint> out;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const auto q = m.face(f);
    for (size_t k = 0; k < 4; ++k)
      out.push_back(Q(9, 16) * q_of(m.vertices[q[k]]) +
                    Q(3, 16) * q_of(m.vertices[q[(k + 1) % 4]]) +
                    Q(1, 16) * q_of(m.vertices[q[(k + 2) % 4]]) +
                    Q(3, 16) * q_of(m.vertices[q[(k + 3) % 4]]));
  }
  return out;
}

void check_exact(const std::string& label, const PolygonMesh& m, Scheme scheme,
                 std::vector<QPoint> (*textbook)(const PolygonMesh&)) {
  for (int level = 0; level < kMaxLevel; ++level) {
    SCOPED_TRACE(label + " " + name(scheme) + " level " + std::to_string(level + 1));
    const PolygonMesh in = subdivide(m, {scheme, level, true});
    const std::vector<QPoint> expected = textbook(in);
    const PolygonMesh exact = subdivide(in, {scheme, 1, true});
    const PolygonMesh fast = subdivide(in, {scheme, 1, false});
    ASSERT_EQ(exact.vertices.size(), expected.size());
    EXPECT_EQ(subdivide(m, {scheme, level + 1, true}).vertices, exact.vertices);
    std::vector<Vec3> rounded;
    for (const QPoint& p : expected) rounded.push_back(nearest(p));
    std::vector<uint32_t> identity(rounded.size());
    for (size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<uint32_t>(i);
    for (size_t i = 0; i < rounded.size(); ++i)
      EXPECT_EQ(exact.vertices[i], rounded[i]) << "vertex " << i;
    // Without exact rounding: within 2 ulp of the mesh's largest coordinate (near zero, the
    // stencils' cancellation makes ulps of the coordinate itself meaningless).
    const Agreement a = agreement(fast.vertices, rounded, identity);
    EXPECT_LE(a.scaled, 2u);
    std::printf("[ exact    ] %s %s L%d: doubles within %llu ulp (own), %llu ulp (scale)\n",
                label.c_str(), name(scheme), level + 1, static_cast<unsigned long long>(a.own),
                static_cast<unsigned long long>(a.scaled));
  }
}

TEST(Subdivision, ExactRoundingMatchesTextbookRationals) {
  check_exact("cube", cube(), Scheme::kCatmullClark, textbook_catmull_clark);
  check_exact("open cube", open_cube(), Scheme::kCatmullClark, textbook_catmull_clark);
  check_exact("grid", grid(3), Scheme::kCatmullClark, textbook_catmull_clark);
  check_exact("torus", torus(5, 4), Scheme::kCatmullClark, textbook_catmull_clark);
  check_exact("torus", regular_triangles(4, true), Scheme::kLoop, textbook_loop);
  check_exact("grid", regular_triangles(3, false), Scheme::kLoop, textbook_loop);
  check_exact("torus", torus(5, 4), Scheme::kDooSabin, textbook_doo_sabin);
  check_exact("grid", grid(3), Scheme::kDooSabin, textbook_doo_sabin);
}

// ---- Corner attributes -------------------------------------------------------------------------

/// The corners' positions as 3 attribute values per corner.
CornerAttributes corner_positions(const PolygonMesh& m) {
  CornerAttributes a{3, {}};
  for (uint32_t v : m.face_vertices)
    a.values.insert(a.values.end(), {m.vertices[v].x, m.vertices[v].y, m.vertices[v].z});
  return a;
}

/// The mesh whose faces are `m`'s with every corner its own vertex at the attribute value
/// (a "polygon soup" of the attribute values), vertices merged when their values are equal.
PolygonMesh attribute_mesh(const PolygonMesh& m, const CornerAttributes& a) {
  PolygonMesh out;
  std::map<std::array<double, 3>, uint32_t> ids;
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t h = m.face_start[f]; h < m.face_start[f + 1]; ++h) {
      const std::array<double, 3> p{a.values[3 * h], a.values[3 * h + 1], a.values[3 * h + 2]};
      const auto [it, added] = ids.emplace(p, static_cast<uint32_t>(out.vertices.size()));
      if (added) out.vertices.push_back({p[0], p[1], p[2]});
      loop.push_back(it->second);
    }
    out.add_face(loop);
  }
  return out;
}

// Positions carried as attributes are refined linearly: the same as CGAL's linear masks
// (Linear_mask_3: face centroid, edge midpoint, vertex kept) through the same refinement,
// Catmull–Clark (PQQ) and Loop (PTQ) topology, over two levels. Closed meshes only: CGAL's
// Linear_mask_3::border_node leaves a border vertex's point unset; on an open cube the old
// vertices' corners are checked directly.
TEST(SubdivisionAttributes, CatmullClarkAndLoopCarryValuesLinearlyAsCgalLinearMasks) {
  namespace SM = CGAL::Subdivision_method_3;
  const std::pair<const char*, PolygonMesh> quads[] = {{"cube", cube()}, {"torus", torus(8, 6)}};
  const std::pair<const char*, PolygonMesh> triangles[] = {
      {"cube", test::triangulate(cube())},
      {"torus", regular_triangles(6, true)},
      {"cross.off", read_mesh(test::cgal_mesh("cross.off"))}};
  for (int levels : {1, 2}) {
    for (const auto& [label, m] : quads) {
      SCOPED_TRACE(std::string("CC ") + label + " L" + std::to_string(levels));
      CornerAttributes a = corner_positions(m);
      const PolygonMesh refined = subdivide(m, {Scheme::kCatmullClark, levels}, a);
      ASSERT_EQ(a.values.size(), 3 * refined.face_vertices.size());
      SurfaceMesh s = to_cgal(m);
      SM::PQQ(s, CGAL::Linear_mask_3<SurfaceMesh>(&s, get(CGAL::vertex_point, s)),
              CGAL::parameters::number_of_iterations(levels));
      const Agreement agree = compare_with_cgal(attribute_mesh(refined, a), from_cgal(s));
      EXPECT_LE(agree.scaled, 1u);
    }
    for (const auto& [label, m] : triangles) {
      SCOPED_TRACE(std::string("Loop ") + label + " L" + std::to_string(levels));
      CornerAttributes a = corner_positions(m);
      const PolygonMesh refined = subdivide(m, {Scheme::kLoop, levels}, a);
      SurfaceMesh s = to_cgal(m);
      SM::PTQ(s, CGAL::Linear_mask_3<SurfaceMesh>(&s, get(CGAL::vertex_point, s)),
              CGAL::parameters::number_of_iterations(levels));
      const Agreement agree = compare_with_cgal(attribute_mesh(refined, a), from_cgal(s));
      EXPECT_LE(agree.scaled, 1u);
    }
  }
  // Open cube, Catmull–Clark: corner 0 of the quad of old corner c is old vertex fv[c]'s.
  const PolygonMesh open = open_cube();
  CornerAttributes a = corner_positions(open);
  const PolygonMesh refined = subdivide(open, {Scheme::kCatmullClark, 1}, a);
  for (size_t c = 0; c < open.face_vertices.size(); ++c)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(a.values[3 * (4 * c) + k], open.vertices[open.face_vertices[c]][k]);
}

// Doo–Sabin's attribute rule is its own mask within the face: positions carried as attributes
// land on the refined vertices (one level, closed and open meshes, quads and other polygons).
TEST(SubdivisionAttributes, DooSabinCarriesPositionsOntoItsCornerPoints) {
  for (const PolygonMesh& m : {cube(), open_cube(), read_mesh(test::cgal_mesh("cross.off"))}) {
    CornerAttributes a = corner_positions(m);
    const PolygonMesh refined = subdivide(m, {Scheme::kDooSabin, 1}, a);
    double worst = 0;
    for (size_t h = 0; h < refined.face_vertices.size(); ++h) {
      const Vec3 p = refined.vertices[refined.face_vertices[h]];
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a.values[3 * h + k] - p[k]));
    }
    EXPECT_LE(worst, 1e-14);
  }
}

// √3: a corner at an old vertex keeps that vertex's value, a centre's value is its face's mean
// (read off the output's vertex numbering: old vertices first, then one centre per face).
TEST(SubdivisionAttributes, Sqrt3KeepsOldVerticesAndAveragesFaces) {
  for (const PolygonMesh& m : {test::triangulate(cube()), regular_triangles(4, true)}) {
    CornerAttributes a = corner_positions(m);
    const PolygonMesh refined = subdivide(m, {Scheme::kSqrt3, 1}, a);
    const size_t nv = m.vertices.size();
    for (size_t h = 0; h < refined.face_vertices.size(); ++h) {
      const uint32_t u = refined.face_vertices[h];
      Vec3 expected{0, 0, 0};
      if (u < nv) {
        expected = m.vertices[u];
      } else {
        const size_t f = u - nv;
        for (uint32_t v : m.face(f)) expected = expected + (1.0 / 3) * m.vertices[v];
      }
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.values[3 * h + k], expected[k], 1e-15) << h;
    }
  }
}

// Seams survive: with one value per old face (every edge a seam), each new face of
// Catmull–Clark, Loop and Doo–Sabin's face-faces carries its old face's value only, and the
// values are identical for 1 and 2 threads.
TEST(SubdivisionAttributes, KeepsSeamsAndIsThreadIndependent) {
  const PolygonMesh elephant = read_mesh(test::cgal_mesh("elephant.off"));
  for (Scheme s : {Scheme::kCatmullClark, Scheme::kLoop, Scheme::kDooSabin, Scheme::kSqrt3}) {
    CornerAttributes a{1, {}};
    for (size_t f = 0; f < elephant.face_count(); ++f)
      a.values.insert(a.values.end(), elephant.face(f).size(), double(f));
    CornerAttributes one = a, two = a;
    PolygonMesh r1, r2;
    {
      ThreadLimit limit(1);
      r1 = subdivide(elephant, {s, 2}, one);
    }
    {
      ThreadLimit limit(2);
      r2 = subdivide(elephant, {s, 2}, two);
    }
    EXPECT_EQ(one.values, two.values) << name(s);
    if (s == Scheme::kSqrt3) continue;  // its triangles straddle two old faces
    const size_t faces = s == Scheme::kDooSabin ? elephant.face_count() : r1.face_count();
    for (size_t f = 0; f < faces; ++f) {
      const uint32_t b = r1.face_start[f], e = r1.face_start[f + 1];
      for (uint32_t h = b + 1; h < e; ++h) ASSERT_EQ(one.values[h], one.values[b]) << name(s);
    }
  }
}

TEST(SubdivisionAttributes, RefusesBadAttributes) {
  const PolygonMesh m = cube();
  CornerAttributes wrong_count{2, std::vector<double>(5, 0.0)};
  EXPECT_THROW(subdivide(m, {}, wrong_count), InputError);
  CornerAttributes no_dims{0, {}};
  EXPECT_THROW(subdivide(m, {}, no_dims), InputError);
  CornerAttributes nan{1, std::vector<double>(m.face_vertices.size(), 0.0)};
  nan.values[7] = std::nan("");
  EXPECT_THROW(subdivide(m, {}, nan), InputError);
}

// ---- Counts, threads, errors -------------------------------------------------------------------

size_t edge_count(const PolygonMesh& m) { return Adjacency(m).ends.size(); }

TEST(Subdivision, CountsPerLevel) {
  for (const PolygonMesh& base : {torus(6, 5), cube()}) {
    PolygonMesh m = base;
    for (int level = 1; level <= kMaxLevel; ++level) {
      const size_t v = m.vertices.size(), e = edge_count(m), f = m.face_count(),
                   h = m.face_vertices.size();
      const PolygonMesh cc = subdivide(m, {Scheme::kCatmullClark, 1});
      EXPECT_EQ(cc.vertices.size(), v + e + f);
      EXPECT_EQ(cc.face_count(), h);
      EXPECT_EQ(cc.face_vertices.size(), 4 * h);
      EXPECT_EQ(edge_count(cc), 2 * e + h);
      const PolygonMesh ds = subdivide(m, {Scheme::kDooSabin, 1});
      EXPECT_EQ(ds.vertices.size(), h);
      EXPECT_EQ(ds.face_count(), f + e + v);
      const PolygonMesh tri = test::triangulate(m);
      const size_t te = edge_count(tri), tf = tri.face_count();
      const PolygonMesh loop = subdivide(tri, {Scheme::kLoop, 1});
      EXPECT_EQ(loop.vertices.size(), v + te);
      EXPECT_EQ(loop.face_count(), 4 * tf);
      EXPECT_EQ(edge_count(loop), 2 * te + 3 * tf);
      const PolygonMesh s3 = subdivide(tri, {Scheme::kSqrt3, 1});
      EXPECT_EQ(s3.vertices.size(), v + tf);
      EXPECT_EQ(s3.face_count(), 3 * tf);
      EXPECT_EQ(edge_count(s3), te + 3 * tf);
      m = cc;
    }
  }
  // With a border: CC still V + E + F; Doo–Sabin drops border edge and vertex faces.
  const PolygonMesh g = grid(3);
  EXPECT_EQ(subdivide(g, {Scheme::kCatmullClark, 1}).vertices.size(), 16u + 24u + 9u);
  EXPECT_EQ(subdivide(g, {Scheme::kDooSabin, 1}).face_count(), 9u + 12u + 4u);
  EXPECT_EQ(subdivide(g, {Scheme::kCatmullClark, 0}).vertices, g.vertices);
  EXPECT_EQ(subdivide(PolygonMesh{}, {Scheme::kDooSabin, 1000000}).vertices.size(), 0u);
}

TEST(Subdivision, SameOutputForOneAndTwoThreads) {
  // Doubles on the elephant (two levels), exact rationals on the smaller cross.
  const PolygonMesh elephant = read_mesh(test::cgal_mesh("elephant.off"));
  const PolygonMesh cross = read_mesh(test::cgal_mesh("cross.off"));
  for (Scheme s : {Scheme::kCatmullClark, Scheme::kLoop, Scheme::kDooSabin, Scheme::kSqrt3})
    for (bool exact : {false, true}) {
      const PolygonMesh& m = exact ? cross : elephant;
      const SubdivideOptions o{s, exact ? kMaxLevel - 1 : 2, exact};
      PolygonMesh one, two;
      {
        ThreadLimit limit(1);
        one = subdivide(m, o);
      }
      {
        ThreadLimit limit(2);
        two = subdivide(m, o);
      }
      EXPECT_EQ(one.vertices, two.vertices) << name(s);
      EXPECT_EQ(one.face_start, two.face_start) << name(s);
      EXPECT_EQ(one.face_vertices, two.face_vertices) << name(s);
      if (exact) {  // the exact path and the doubles agree closely for every scheme
        const PolygonMesh fast = subdivide(m, {s, o.levels, false});
        std::vector<uint32_t> identity(fast.vertices.size());
        for (size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<uint32_t>(i);
        EXPECT_LE(agreement(fast.vertices, one.vertices, identity).scaled, 2u) << name(s);
      }
    }
}

void expect_input_error(const PolygonMesh& m, const SubdivideOptions& o, const std::string& part) {
  try {
    subdivide(m, o);
    ADD_FAILURE() << "no error, expected one naming '" << part << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
}

TEST(Subdivision, RefusesInvalidInput) {
  PolygonMesh two = cube();
  two.add_face({0, 1});
  expect_input_error(two, {}, "face 6 has 2 vertices");
  PolygonMesh fin = test::unit_tetrahedron();
  fin.vertices.push_back({1, 1, 1});
  fin.add_face({0, 1, 4});  // a third face on edge (0, 1)
  expect_input_error(fin, {}, "non-manifold");
  PolygonMesh bowtie;
  bowtie.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  bowtie.add_face({0, 1, 2});
  bowtie.add_face({0, 3, 4});
  expect_input_error(bowtie, {}, "vertex 0 is non-manifold");
  expect_input_error(cube(), {Scheme::kLoop, 1}, "face 0 has 4 vertices");
  expect_input_error(cube(), {Scheme::kSqrt3, 1}, "face 0 has 4 vertices");
  expect_input_error(cube(), {Scheme::kCatmullClark, -1}, "levels");
  expect_input_error(cube(), {Scheme::kCatmullClark, 40}, "levels");
  expect_input_error(cube(), {Scheme::kDooSabin, 1000000}, "levels");
  PolygonMesh out_of_range = cube();
  out_of_range.add_face({0, 1, 99});
  expect_input_error(out_of_range, {}, "out of range");
}

}  // namespace
}  // namespace cover
