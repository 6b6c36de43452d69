// Ray-integrated volume with a proven error bound (detail/ray_volume.h has the notation).

#include "cover/covering/detail/ray_volume.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cover/covering/ray.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"

namespace cover::detail {
namespace {

constexpr double kMargin = 1e-9;  // relative margin of the conservative geometric tests

/// A covering triangle in the scaled frame (u, v, depth): vertices, depth plane, bounds.
struct Tri {
  double u[3], v[3];
  double t0 = 0, a = 0, b = 0;  ///< depth(u, v) = t0 + a·(u − u[0]) + b·(v − v[0])
  double g = INFINITY;          ///< |∇ depth|; infinite when the triangle is parallel to d
  double tmin = 0, tmax = 0;
  double orient = 0;  ///< sign of the projected area (0: degenerate in projection)
  double depth(double pu, double pv) const { return t0 + a * (pu - u[0]) + b * (pv - v[0]); }
};

struct Frame {
  Vec3 d, e1, e2, centre;
  double scale = 1;  ///< a power of two: scaled = (p − centre)·scale
};

Vec3 unit(Vec3 a) { return (1.0 / std::sqrt(dot(a, a))) * a; }

/// The candidate direction farthest from being parallel to any face (largest min |n̂·d|).
Vec3 pick_direction(const Solid& s) {
  static const Vec3 kCandidates[] = {{0.3141592653589793, 0.2718281828459045, 1.0},
                                     {-0.5772156649015329, 1.0, 0.4142135623730951},
                                     {1.0, -0.3819660112501051, 0.6931471805599453},
                                     {0.7071067811865476, 0.5772156649015329, -1.0}};
  Vec3 best = unit(kCandidates[0]);
  double best_min = -1;
  for (const Vec3& c : kCandidates) {
    const Vec3 d = unit(c);
    double worst = 1;
    for (size_t f = 0; f < s.face_count() && worst > best_min; ++f) {
      const auto face = s.face(f);
      Vec3 n{};
      for (size_t i = 0; i < face.size(); ++i)
        n = n + cross(s.vertices[face[i]], s.vertices[face[(i + 1) % face.size()]]);
      const double len = std::sqrt(dot(n, n));
      if (len > 0) worst = std::min(worst, std::abs(dot(n, d)) / len);
    }
    if (worst > best_min) {
      best_min = worst;
      best = d;
    }
  }
  return best;
}

Frame make_frame(const Solid& s, const Bbox& box) {
  Frame f;
  f.d = pick_direction(s);
  f.e1 = unit(cross(f.d, std::abs(f.d.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  f.e2 = cross(f.d, f.e1);
  f.centre = 0.5 * (box.min + box.max);
  const Vec3 ext = box.max - box.min;
  const double extent = std::max(
      {ext.x, ext.y, ext.z, std::abs(f.centre.x), std::abs(f.centre.y), std::abs(f.centre.z)});
  int exponent = 0;
  std::frexp(extent > 0 ? extent : 1, &exponent);
  f.scale = std::ldexp(1.0, -exponent);
  return f;
}

std::vector<Tri> project_triangles(const Solid& s, const Frame& fr) {
  std::vector<Tri> tris;
  for (size_t f = 0; f < s.face_count(); ++f) {
    const auto face = s.face(f);
    for (size_t j = 1; j + 1 < face.size(); ++j) {
      Tri t;
      const uint32_t idx[3] = {face[0], face[j], face[j + 1]};
      double depth[3];
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = fr.scale * (s.vertices[idx[k]] - fr.centre);
        t.u[k] = dot(p, fr.e1);
        t.v[k] = dot(p, fr.e2);
        depth[k] = dot(p, fr.d);
      }
      t.tmin = std::min({depth[0], depth[1], depth[2]});
      t.tmax = std::max({depth[0], depth[1], depth[2]});
      const double du1 = t.u[1] - t.u[0], dv1 = t.v[1] - t.v[0];
      const double du2 = t.u[2] - t.u[0], dv2 = t.v[2] - t.v[0];
      const double det = du1 * dv2 - du2 * dv1;
      const double size = std::max({std::abs(du1), std::abs(dv1), std::abs(du2), std::abs(dv2)});
      t.t0 = depth[0];
      if (std::abs(det) > kMargin * size * size) {
        const double dt1 = depth[1] - depth[0], dt2 = depth[2] - depth[0];
        t.a = (dt1 * dv2 - dt2 * dv1) / det;
        t.b = (du1 * dt2 - du2 * dt1) / det;
        t.g = std::sqrt(t.a * t.a + t.b * t.b) * (1 + 1e-6);  // rounding of a, b
        t.orient = det > 0 ? 1 : -1;
      }
      if (t.tmax - t.tmin > 0 || t.orient != 0) tris.push_back(t);
    }
  }
  return tris;
}

/// A quadtree cell [u0, u0 + side] × [v0, v0 + side] and its triangles list[first, first+count).
struct Cell {
  double u0, v0, side;
  size_t first, count;
};

enum class Overlap { kOutside, kMeets, kContains };

/// Where the closed square lies relative to triangle t (conservative: kOutside and kContains
/// only with a margin).
Overlap overlap(const Tri& t, double u0, double v0, double side) {
  const double m = kMargin * side;
  const double umin = std::min({t.u[0], t.u[1], t.u[2]}), umax = std::max({t.u[0], t.u[1], t.u[2]});
  const double vmin = std::min({t.v[0], t.v[1], t.v[2]}), vmax = std::max({t.v[0], t.v[1], t.v[2]});
  if (umax < u0 - m || umin > u0 + side + m || vmax < v0 - m || vmin > v0 + side + m)
    return Overlap::kOutside;
  if (t.orient == 0) return Overlap::kMeets;
  bool inside = true;
  for (int e = 0; e < 3; ++e) {
    const int n = (e + 1) % 3;
    const double eu = t.u[n] - t.u[e], ev = t.v[n] - t.v[e];
    const double tol = kMargin * (std::abs(eu) + std::abs(ev)) * side + 1e-300;
    double lo = INFINITY, hi = -INFINITY;
    for (int c = 0; c < 4; ++c) {
      const double pu = u0 + ((c & 1) ? side : 0), pv = v0 + ((c & 2) ? side : 0);
      const double f = t.orient * (eu * (pv - t.v[e]) - ev * (pu - t.u[e]));
      lo = std::min(lo, f);
      hi = std::max(hi, f);
    }
    if (hi < -tol) return Overlap::kOutside;  // every corner beyond this edge
    inside = inside && lo > tol;
  }
  return inside ? Overlap::kContains : Overlap::kMeets;
}

struct CellReport {
  bool certified = false;
  double bound = 0;  ///< area·min(r·G, T) for uncertified cells
};

/// Certifies a cell whose list holds exactly the triangles meeting it.
CellReport examine(const std::vector<Tri>& tris, const uint32_t* list, size_t count,
                   const Cell& c) {
  CellReport r;
  if (count == 0) {
    r.certified = true;
    return r;
  }
  double g = 0, tmin = INFINITY, tmax = -INFINITY;
  bool all_contain = true;
  for (size_t k = 0; k < count; ++k) {
    const Tri& t = tris[list[k]];
    g += t.g;
    tmin = std::min(tmin, t.tmin);
    tmax = std::max(tmax, t.tmax);
    all_contain = all_contain && overlap(t, c.u0, c.v0, c.side) == Overlap::kContains;
  }
  const double area = c.side * c.side;
  r.bound = area * std::min(c.side * std::sqrt(0.5) * g, tmax - tmin);
  if (!all_contain) return r;
  // Depth order constant over the cell: each pair's (affine) depth difference keeps its sign at
  // the four corners, with a margin. A pair within the margin at all four corners (coplanar
  // faces, common in CSG of aligned boxes) is a tie that cast() breaks the same way on every
  // line; were it a near-crossing, L would differ from an affine function by at most the pair's
  // largest corner difference δ, so such pairs add 2·area·Σδ to the bound instead.
  const double tol = kMargin * (1 + std::abs(tmin) + std::abs(tmax));
  double ties = 0;
  for (size_t i = 0; i < count; ++i)
    for (size_t j = 0; j < i; ++j) {
      const Tri &a = tris[list[i]], &b = tris[list[j]];
      double largest = 0;
      bool tied = true, above = true, below = true;
      for (int k = 0; k < 4; ++k) {
        const double pu = c.u0 + ((k & 1) ? c.side : 0), pv = c.v0 + ((k & 2) ? c.side : 0);
        const double diff = a.depth(pu, pv) - b.depth(pu, pv);
        largest = std::max(largest, std::abs(diff));
        tied = tied && std::abs(diff) <= tol;
        above = above && diff > tol;
        below = below && diff < -tol;
      }
      if (tied)
        ties += largest + tol;
      else if (!above && !below)
        return r;  // the pair may cross inside the cell
    }
  r.certified = true;
  r.bound = 2 * area * ties;
  return r;
}

}  // namespace

RayVolume ray_volume(const Prepared& prepared, const Bbox& box, const RayVolumeOptions& options) {
  const Solid& s = prepared.solid();
  RayVolume out;
  const Frame fr = make_frame(s, box);
  const std::vector<Tri> tris = project_triangles(s, fr);
  // Root square: the projection of the scaled box's corners.
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY, tlo = INFINITY;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p =
        fr.scale * (Vec3{(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                         (c & 4) ? box.max.z : box.min.z} -
                    fr.centre);
    umin = std::min(umin, dot(p, fr.e1));
    umax = std::max(umax, dot(p, fr.e1));
    vmin = std::min(vmin, dot(p, fr.e2));
    vmax = std::max(vmax, dot(p, fr.e2));
    tlo = std::min(tlo, dot(p, fr.d));
  }
  const double side0 = std::max(umax - umin, vmax - vmin) * (1 + 1e-6) + 1e-300;
  const double unscale = 1 / fr.scale;  // exact: a power of two
  const double area_unit = unscale * unscale;
  // Ray origins start before the box (scaled depth tlo − 1).
  auto ray_at = [&](double pu, double pv) {
    const Vec3 p = pu * fr.e1 + pv * fr.e2 + (tlo - 1) * fr.d;
    return Ray{fr.centre + unscale * p, fr.d};
  };

  std::vector<Cell> cells{{umin, vmin, side0, 0, 0}};
  std::vector<uint32_t> lists(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) lists[i] = static_cast<uint32_t>(i);
  cells[0].count = tris.size();
  NeumaierSum exact;      // certified cells' integrals
  NeumaierSum tie_bound;  // certified cells' bounds from tied pairs
  double rounding = 0;
  const int max_level = options.fixed_level >= 0 ? options.fixed_level : 62;
  for (int level = 0; level <= max_level && !cells.empty(); ++level) {
    // Children of every open cell, with their triangle lists (chunks concatenated in order);
    // level 0 is the root itself.
    const size_t parents = level == 0 ? 1 : cells.size();
    constexpr size_t kGrain = 256;
    const size_t chunks = (parents + kGrain - 1) / kGrain;
    std::vector<std::vector<Cell>> chunk_cells(chunks);
    std::vector<std::vector<uint32_t>> chunk_lists(chunks);
    std::vector<std::vector<CellReport>> chunk_reports(chunks);
    parallel_for(parents, kGrain, [&](size_t begin, size_t end) {
      const size_t k = begin / kGrain;
      for (size_t p = begin; p < end; ++p) {
        const Cell& parent = cells[p];
        const double half = level == 0 ? parent.side : 0.5 * parent.side;
        for (int q = 0; q < (level == 0 ? 1 : 4); ++q) {
          Cell child{parent.u0 + ((q & 1) ? half : 0), parent.v0 + ((q & 2) ? half : 0), half,
                     chunk_lists[k].size(), 0};
          for (size_t i = parent.first; i < parent.first + parent.count; ++i)
            if (overlap(tris[lists[i]], child.u0, child.v0, half) != Overlap::kOutside)
              chunk_lists[k].push_back(lists[i]);
          child.count = chunk_lists[k].size() - child.first;
          chunk_reports[k].push_back(
              examine(tris, chunk_lists[k].data() + child.first, child.count, child));
          chunk_cells[k].push_back(child);
        }
      }
    });
    std::vector<Cell> next;
    std::vector<uint32_t> next_lists;
    std::vector<CellReport> reports;
    for (size_t k = 0; k < chunks; ++k) {
      for (Cell c : chunk_cells[k]) {
        c.first += next_lists.size();
        next.push_back(c);
      }
      next_lists.insert(next_lists.end(), chunk_lists[k].begin(), chunk_lists[k].end());
      reports.insert(reports.end(), chunk_reports[k].begin(), chunk_reports[k].end());
    }
    // One ray per child with triangles (a cell without any has L ≡ 0).
    std::vector<Ray> rays;
    std::vector<size_t> ray_cell;
    for (size_t i = 0; i < next.size(); ++i)
      if (next[i].count > 0) {
        rays.push_back(ray_at(next[i].u0 + 0.5 * next[i].side, next[i].v0 + 0.5 * next[i].side));
        ray_cell.push_back(i);
      }
    const std::vector<RayResult> results = cast(prepared, rays);
    out.rays += rays.size();
    std::vector<double> value(next.size(), 0);
    for (size_t r = 0; r < results.size(); ++r) {
      NeumaierSum length;
      for (const Span& span : results[r].spans) {
        if (span.t1 == INFINITY || span.enter == Span::kNone)
          throw NotComputable("the solid is unbounded");  // precondition broken
        length.add(span.t1 - span.t0);
      }
      const Cell& c = next[ray_cell[r]];
      value[ray_cell[r]] = length.value() * (c.side * c.side * area_unit);
    }
    // Certified cells leave; the others carry their value and bound to the next level.
    NeumaierSum open_value, open_bound;
    std::vector<Cell> open;
    std::vector<uint32_t> open_lists;
    const double volume_unit = area_unit * unscale;
    for (size_t i = 0; i < next.size(); ++i) {
      rounding += std::abs(value[i]);
      if (reports[i].certified) {
        exact.add(value[i]);
        tie_bound.add(reports[i].bound * volume_unit);
        continue;
      }
      open_value.add(value[i]);
      open_bound.add(reports[i].bound * volume_unit);
      Cell c = next[i];
      c.first = open_lists.size();
      open_lists.insert(
          open_lists.end(), next_lists.begin() + static_cast<std::ptrdiff_t>(next[i].first),
          next_lists.begin() + static_cast<std::ptrdiff_t>(next[i].first + next[i].count));
      open.push_back(c);
    }
    NeumaierSum total = exact;
    total.add(open_value);
    out.volume = total.value();
    out.error_bound = open_bound.value() + tie_bound.value() + 0x1p-40 * rounding;
    out.level = level;
    const bool fixed = options.fixed_level >= 0;
    out.target_met = out.error_bound <= options.target_relative_error * std::abs(out.volume);
    if (options.progress)
      options.progress(fixed ? double(level) / max_level
                             : std::min(1.0, double(out.rays) / double(options.max_rays)));
    if (open.empty() || (!fixed && out.target_met)) break;
    if (!fixed) {
      // The bound shrinks about 4× per level while the open cells (along curves) about double:
      // stop as soon as the levels still needed would overrun the budget.
      const double goal = options.target_relative_error * std::abs(out.volume);
      const double levels =
          goal > 0 ? std::ceil(std::log(out.error_bound / goal) / std::log(4.0)) : 1;
      const double needed = 4.0 * open.size() * (std::exp2(std::max(levels, 1.0)) - 1);
      if (static_cast<double>(out.rays) + needed > static_cast<double>(options.max_rays)) break;
    }
    cells = std::move(open);
    lists = std::move(open_lists);
  }
  return out;
}

}  // namespace cover::detail
