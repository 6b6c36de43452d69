// Point-set leaves (point_set.h has the conventions).

#include "cover/points/point_set.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>
#include <queue>
#include <string>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

/// nanoflann's dataset adaptor over a span of points.
struct Cloud {
  std::span<const Vec3> p;
  size_t kdtree_get_point_count() const { return p.size(); }
  double kdtree_get_pt(size_t i, size_t dim) const {
    return dim == 0 ? p[i].x : dim == 1 ? p[i].y : p[i].z;
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                   Cloud, 3, uint32_t>;

/// The k nearest other points of every point, row-major (k per point), and their squared
/// distances. Parallel; the same for any thread count.
void neighbours(std::span<const Vec3> points, int k, std::vector<uint32_t>& index,
                std::vector<double>& dist2) {
  const Cloud cloud{points};
  KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const size_t n = points.size(), kk = static_cast<size_t>(k);
  index.resize(n * kk);
  dist2.resize(n * kk);
  parallel_for(n, 1024, [&](size_t begin, size_t end) {
    std::vector<uint32_t> idx(kk + 1);
    std::vector<double> d(kk + 1);
    for (size_t i = begin; i < end; ++i) {
      const double q[3] = {points[i].x, points[i].y, points[i].z};
      const size_t found = tree.knnSearch(q, kk + 1, idx.data(), d.data());
      size_t out = 0;
      for (size_t j = 0; j < found && out < kk; ++j) {
        if (idx[j] == i) continue;  // the point itself (or a duplicate: kept as a neighbour)
        index[i * kk + out] = idx[j];
        dist2[i * kk + out] = d[j];
        ++out;
      }
      for (; out < kk; ++out) {  // fewer distinct results (duplicates): repeat the last
        index[i * kk + out] = index[i * kk + out - 1];
        dist2[i * kk + out] = dist2[i * kk + out - 1];
      }
    }
  });
}

/// A right-handed orthonormal frame (u, v, n) of the tangent plane of the unit normal n.
void tangent_frame(const Vec3& n, Vec3& u, Vec3& v) {
  const Vec3 t = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  u = cross(n, t);
  u = (1 / std::sqrt(dot(u, u))) * u;
  v = cross(n, u);
}

void check_options(const PointSetOptions& o, size_t n) {
  if (o.neighbours < 3 || o.neighbours > 64)
    throw InputError("points: neighbours: expected 3 to 64, got " + std::to_string(o.neighbours));
  if (n < static_cast<size_t>(o.neighbours) + 1)
    throw InputError("points: expected at least " + std::to_string(o.neighbours + 1) +
                     " points (neighbours + 1), got " + std::to_string(n));
}

}  // namespace

std::vector<Vec3> estimate_normals(std::span<const Vec3> points, const PointSetOptions& o) {
  check_options(o, points.size());
  const size_t n = points.size(), k = static_cast<size_t>(o.neighbours);
  std::vector<uint32_t> nb;
  std::vector<double> d2;
  neighbours(points, o.neighbours, nb, d2);
  std::vector<Vec3> normal(n);
  parallel_for(n, 1024, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      Eigen::Vector3d mean = Eigen::Vector3d(points[i].x, points[i].y, points[i].z);
      for (size_t j = 0; j < k; ++j) {
        const Vec3& q = points[nb[i * k + j]];
        mean += Eigen::Vector3d(q.x, q.y, q.z);
      }
      mean /= static_cast<double>(k + 1);
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      auto add = [&](const Vec3& q) {
        const Eigen::Vector3d d = Eigen::Vector3d(q.x, q.y, q.z) - mean;
        cov += d * d.transpose();
      };
      add(points[i]);
      for (size_t j = 0; j < k; ++j) add(points[nb[i * k + j]]);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
      const Eigen::Vector3d v = eig.eigenvectors().col(0);  // smallest eigenvalue first
      normal[i] = {v.x(), v.y(), v.z()};
    }
  });
  // Orientation: Prim's minimum spanning tree over the symmetric kNN graph, weight 1 − |ni·nj|,
  // each component from its point of largest x (normal turned to +x), serial and deterministic.
  std::vector<std::vector<uint32_t>> adj(n);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < k; ++j) {
      const uint32_t b = nb[i * k + j];
      if (b == i) continue;
      adj[i].push_back(b);
      adj[b].push_back(static_cast<uint32_t>(i));
    }
  std::vector<uint8_t> done(n, 0);
  std::vector<uint32_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(i);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return points[a].x != points[b].x ? points[a].x > points[b].x : a < b;
  });
  using Item = std::tuple<double, uint32_t, uint32_t>;  // weight, to, from
  for (uint32_t seed : order) {
    if (done[seed]) continue;
    if (normal[seed].x < 0) normal[seed] = -1.0 * normal[seed];
    done[seed] = 1;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    auto push_from = [&](uint32_t a) {
      for (uint32_t b : adj[a])
        if (!done[b]) heap.emplace(1 - std::abs(dot(normal[a], normal[b])), b, a);
    };
    push_from(seed);
    while (!heap.empty()) {
      const auto [w, b, a] = heap.top();
      heap.pop();
      if (done[b]) continue;
      if (dot(normal[a], normal[b]) < 0) normal[b] = -1.0 * normal[b];
      done[b] = 1;
      push_from(b);
    }
  }
  return normal;
}

std::vector<double> voronoi_areas(std::span<const Vec3> points, std::span<const Vec3> normals,
                                  const PointSetOptions& o) {
  check_options(o, points.size());
  const size_t n = points.size(), k = static_cast<size_t>(o.neighbours);
  std::vector<uint32_t> nb;
  std::vector<double> d2;
  neighbours(points, o.neighbours, nb, d2);
  std::vector<double> area(n);
  parallel_for(n, 1024, [&](size_t begin, size_t end) {
    std::vector<std::array<double, 2>> poly, next;
    for (size_t i = begin; i < end; ++i) {
      Vec3 u, v;
      tangent_frame(normals[i], u, v);
      const double r = std::sqrt(d2[i * k + k - 1]);
      if (!(r > 0)) {  // k coincident neighbours: no extent of its own
        area[i] = 0;
        continue;
      }
      poly = {{-r, -r}, {r, -r}, {r, r}, {-r, r}};
      for (size_t j = 0; j < k && !poly.empty(); ++j) {
        const Vec3 d = points[nb[i * k + j]] - points[i];
        const double a = dot(d, u), b = dot(d, v), c = 0.5 * (a * a + b * b);
        if (c == 0) continue;
        // Keep the half-plane a·x + b·y ≤ c (closer to the point than to the neighbour).
        next.clear();
        for (size_t e = 0; e < poly.size(); ++e) {
          const auto& p = poly[e];
          const auto& q = poly[(e + 1) % poly.size()];
          const double fp = a * p[0] + b * p[1] - c, fq = a * q[0] + b * q[1] - c;
          if (fp <= 0) next.push_back(p);
          if ((fp < 0) != (fq < 0) && fp != fq) {
            const double s = fp / (fp - fq);
            next.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])});
          }
        }
        poly.swap(next);
      }
      double twice = 0;
      for (size_t e = 0; e < poly.size(); ++e) {
        const auto& p = poly[e];
        const auto& q = poly[(e + 1) % poly.size()];
        twice += p[0] * q[1] - q[0] * p[1];
      }
      area[i] = 0.5 * std::abs(twice);
    }
  });
  return area;
}

PolygonMesh dipole_triangles(std::span<const Vec3> points, std::span<const Vec3> normals,
                             std::span<const double> areas) {
  PolygonMesh m;
  m.vertices.reserve(3 * points.size());
  // An equilateral triangle of area A has circumradius R = sqrt(4A / (3·sqrt(3))).
  const double factor = 4 / (3 * std::sqrt(3.0));
  for (size_t i = 0; i < points.size(); ++i) {
    if (!(areas[i] > 0)) continue;
    Vec3 u, v;
    tangent_frame(normals[i], u, v);
    const double r = std::sqrt(factor * areas[i]);
    const auto first = static_cast<uint32_t>(m.vertices.size());
    for (int c = 0; c < 3; ++c) {
      const double angle = 2 * M_PI * c / 3;
      m.vertices.push_back(points[i] + (r * std::cos(angle)) * u + (r * std::sin(angle)) * v);
    }
    m.add_face({first, first + 1, first + 2});  // counter-clockwise about n = u × v
  }
  return m;
}

PolygonMesh point_set_mesh(std::span<const Vec3> points, std::span<const Vec3> normals,
                           const PointSetOptions& o) {
  check_options(o, points.size());
  for (size_t i = 0; i < points.size(); ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z))
      throw InputError("points: point " + std::to_string(i) + " is not finite");
  std::vector<Vec3> unit;
  if (normals.empty()) {
    unit = estimate_normals(points, o);
  } else {
    if (normals.size() != points.size())
      throw InputError("points: expected one normal per point (" + std::to_string(points.size()) +
                       "), got " + std::to_string(normals.size()));
    unit.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      const double len = std::sqrt(dot(normals[i], normals[i]));
      if (!(len > 0) || !std::isfinite(len))
        throw InputError("points: normal " + std::to_string(i) + " is zero or not finite");
      unit[i] = (1 / len) * normals[i];
    }
  }
  const std::vector<double> areas = voronoi_areas(points, unit, o);
  return dipole_triangles(points, unit, areas);
}

}  // namespace cover
