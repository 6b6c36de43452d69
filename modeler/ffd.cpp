// Free-form deformation (ffd.h has the conventions).

#include "cover/modeler/ffd.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "cover/mesh/triangulate.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

constexpr int kMaxDegree = 16;

size_t point_count(const FfdLattice& f) {
  return static_cast<size_t>(f.degree[0] + 1) * static_cast<size_t>(f.degree[1] + 1) *
         static_cast<size_t>(f.degree[2] + 1);
}

size_t index(const FfdLattice& f, int i, int j, int k) {
  return (static_cast<size_t>(i) * static_cast<size_t>(f.degree[1] + 1) + static_cast<size_t>(j)) *
             static_cast<size_t>(f.degree[2] + 1) +
         static_cast<size_t>(k);
}

double coord(const Vec3& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

Vec3 undeformed(const FfdLattice& f, int i, int j, int k) {
  const int ijk[3] = {i, j, k};
  double c[3];
  for (int a = 0; a < 3; ++a) {
    const double lo = coord(f.min, a), hi = coord(f.max, a);
    c[a] = ijk[a] == f.degree[a] ? hi : lo + (hi - lo) * ijk[a] / f.degree[a];
  }
  return {c[0], c[1], c[2]};
}

/// B_0..B_n of degree n at s (de Casteljau-free: the binomial form, n ≤ 16).
void bernstein(int n, double s, double* out) {
  out[0] = 1;
  for (int d = 1; d <= n; ++d) {  // raise the degree: B_i^d = (1−s)·B_i^{d−1} + s·B_{i−1}^{d−1}
    out[d] = s * out[d - 1];
    for (int i = d - 1; i > 0; --i) out[i] = (1 - s) * out[i] + s * out[i - 1];
    out[0] *= 1 - s;
  }
}

double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }

}  // namespace

FfdLattice identity_lattice(const Vec3& min, const Vec3& max, std::array<int, 3> degree) {
  FfdLattice f{min, max, degree, {}};
  f.points.resize(point_count(f));
  for (int i = 0; i <= degree[0]; ++i)
    for (int j = 0; j <= degree[1]; ++j)
      for (int k = 0; k <= degree[2]; ++k) f.points[index(f, i, j, k)] = undeformed(f, i, j, k);
  return f;
}

std::string validate(const FfdLattice& f) {
  for (int a = 0; a < 3; ++a)
    if (f.degree[a] < 1 || f.degree[a] > kMaxDegree)
      return "degree: expected 1 to " + std::to_string(kMaxDegree) + " per axis";
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(coord(f.min, a)) || !std::isfinite(coord(f.max, a)) ||
        !(coord(f.min, a) < coord(f.max, a)))
      return "min and max: expected finite numbers, min below max on every axis";
  if (f.points.size() != point_count(f))
    return "points: expected " + std::to_string(point_count(f)) +
           " control points (degree + 1 "
           "per axis, multiplied), got " +
           std::to_string(f.points.size());
  for (const Vec3& p : f.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "points: expected finite coordinates";
  return {};
}

Vec3 ffd_map(const FfdLattice& f, const Vec3& p) {
  double b[3][kMaxDegree + 1];
  for (int a = 0; a < 3; ++a) {
    const double lo = coord(f.min, a), hi = coord(f.max, a);
    bernstein(f.degree[a], (coord(p, a) - lo) / (hi - lo), b[a]);
  }
  Vec3 d{0, 0, 0};
  for (int i = 0; i <= f.degree[0]; ++i)
    for (int j = 0; j <= f.degree[1]; ++j) {
      const double bij = b[0][i] * b[1][j];
      for (int k = 0; k <= f.degree[2]; ++k) {
        const Vec3 disp = f.points[index(f, i, j, k)] - undeformed(f, i, j, k);
        if (disp.x != 0 || disp.y != 0 || disp.z != 0) d = d + (bij * b[2][k]) * disp;
      }
    }
  return p + d;
}

double ffd_curvature_bound(const FfdLattice& f) {
  const Vec3 size = f.max - f.min;
  const int* n = f.degree.data();
  double total = 0;
  for (int a = 0; a < 3; ++a)
    for (int c = a; c < 3; ++c) {
      if (a == c && n[a] < 2) continue;
      double worst = 0;
      for (int i = 0; i <= n[0]; ++i)
        for (int j = 0; j <= n[1]; ++j)
          for (int k = 0; k <= n[2]; ++k) {
            int at[3] = {i, j, k};
            auto P = [&](int da, int dc) {
              int q[3] = {at[0], at[1], at[2]};
              q[a] += da;
              q[c] += dc;
              // The displacement: the undeformed lattice is linear, so it adds nothing to the
              // second derivatives, and its rounded points must not either.
              return f.points[index(f, q[0], q[1], q[2])] - undeformed(f, q[0], q[1], q[2]);
            };
            if (a == c) {
              if (at[a] + 2 > n[a]) continue;
              worst = std::max(worst, norm(P(2, 0) - 2 * P(1, 0) + P(0, 0)));
            } else {
              if (at[a] + 1 > n[a] || at[c] + 1 > n[c]) continue;
              worst = std::max(worst, norm(P(1, 1) - P(1, 0) - P(0, 1) + P(0, 0)));
            }
          }
      const double factor =
          a == c ? static_cast<double>(n[a]) * (n[a] - 1) : static_cast<double>(n[a]) * n[c];
      // Off-diagonal pairs appear twice in D²_v X = Σ_pq v_p v_q ∂p∂q X.
      total += (a == c ? 1 : 2) * factor * worst / (coord(size, a) * coord(size, c));
    }
  return total * (1 + 1e-12);  // the differences' rounding, generously
}

FfdResult ffd(const PolygonMesh& mesh, const FfdLattice& f, const FfdOptions& options) {
  if (const std::string problem = validate(f); !problem.empty())
    throw InputError("ffd: lattice: " + problem);
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a)
      if (!(coord(mesh.vertices[v], a) >= coord(f.min, a) &&
            coord(mesh.vertices[v], a) <= coord(f.max, a)))
        throw InputError("ffd: vertex " + std::to_string(v) +
                         " lies outside the lattice box (the lattice must contain the child)");
  const double diagonal = norm(f.max - f.min);
  const double tolerance = options.tolerance == 0 ? 1e-3 * diagonal : options.tolerance;
  if (!(tolerance > 0) || !std::isfinite(tolerance))
    throw InputError("ffd: tolerance: expected a finite number > 0");
  FfdResult r;
  // Triangulate.
  std::vector<std::array<uint32_t, 3>> tris;
  for (size_t face = 0; face < mesh.face_count(); ++face)
    if (triangulate_face(mesh.vertices, mesh.face(face), tris) == FaceTiling::kCrossing)
      throw InputError("ffd: face " + std::to_string(face) +
                       " cannot be triangulated (its boundary crosses itself)");
  std::vector<Vec3> points = mesh.vertices;
  const double m = ffd_curvature_bound(f);
  auto longest_edge = [&] {
    double e = 0;
    for (const auto& t : tris)
      for (int c = 0; c < 3; ++c) e = std::max(e, norm(points[t[(c + 1) % 3]] - points[t[c]]));
    return e;
  };
  double e = longest_edge();
  while (0.5 * m * e * e > tolerance) {
    if (tris.size() * 4 > options.max_triangles)
      throw InputError("ffd: the chord bound " + std::to_string(tolerance) + " needs more than " +
                       std::to_string(options.max_triangles) +
                       " triangles; use a larger tolerance");
    // 1→4 at shared edge midpoints.
    std::unordered_map<uint64_t, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const uint64_t key = a < b ? (uint64_t{a} << 32) | b : (uint64_t{b} << 32) | a;
      auto [it, fresh] = mid.try_emplace(key, static_cast<uint32_t>(points.size()));
      if (fresh) points.push_back(0.5 * (points[a] + points[b]));
      return it->second;
    };
    std::vector<std::array<uint32_t, 3>> next;
    next.reserve(tris.size() * 4);
    for (const auto& t : tris) {
      const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                     ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    tris.swap(next);
    ++r.levels;
    e = longest_edge();
  }
  r.chord_bound = 0.5 * m * e * e;
  r.mesh.vertices.resize(points.size());
  for (size_t v = 0; v < points.size(); ++v) r.mesh.vertices[v] = ffd_map(f, points[v]);
  for (const auto& t : tris) r.mesh.add_face({t[0], t[1], t[2]});
  return r;
}

}  // namespace cover
