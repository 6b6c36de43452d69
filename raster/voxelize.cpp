#include "raster/voxelize.h"

#include <algorithm>
#include <cmath>

#include "covering/bounds.h"
#include "covering/bvh.h"
#include "covering/predicates.h"
#include "solid/parallel.h"

namespace cover {
namespace {

/// One crossing of a column's centre line by a covering triangle.
struct Crossing {
  uint32_t column;  ///< i·N + j
  uint32_t below;   ///< number of voxel centres of the column below the triangle (0..N)
  uint32_t leaf;
  int32_t sign;  ///< n_z: winding contribution to the centres below
};

/// Sign of the projected (x, y) orientation of (a, b, q) with q → q + (ε, ε²) (as in classify).
int perturbed_orient_xy(const Vec3& a, const Vec3& b, const Vec3& q) {
  const int o = orient2d(a, b, q, 2);
  if (o != 0) return o;
  if (a.y != b.y) return a.y > b.y ? 1 : -1;
  if (a.x != b.x) return b.x > a.x ? 1 : -1;
  return 0;
}

/// Side of c + (ε, ε², ε³) relative to the plane of abc: sign of n·(c' − a).
int perturbed_side(const Bvh::Tri& t, const Vec3& c) {
  if (const int s = orient3d(t.a, t.b, t.c, c)) return s;
  if (const int s = orient2d(t.a, t.b, t.c, 0)) return s;
  if (const int s = orient2d(t.a, t.b, t.c, 1)) return s;
  return orient2d(t.a, t.b, t.c, 2);
}

/// Coordinates of the voxel centres along one axis (the doubles voxel_centre() computes).
std::vector<double> centres(double min, double h, int n) {
  std::vector<double> c(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) c[i] = min + (i + 0.5) * h;
  return c;
}

/// Indices [first, last] of the centres inside [lo, hi], or first > last: a floating-point
/// guess, then exact comparisons with the centre coordinates.
std::pair<int, int> centre_range(const std::vector<double>& c, double lo, double hi) {
  const int n = static_cast<int>(c.size());
  const double inv_h = n > 1 ? 1 / (c[1] - c[0]) : 1;
  auto guess = [&](double v) {
    const double g = std::floor((v - c[0]) * inv_h);
    return std::isfinite(g) ? static_cast<int>(std::clamp(g, -1.0, static_cast<double>(n))) : -1;
  };
  int first = std::max(0, guess(lo));
  while (first > 0 && c[first - 1] >= lo) --first;
  while (first < n && c[first] < lo) ++first;
  int last = std::min(n - 1, guess(hi) + 1);
  while (last >= 0 && c[last] > hi) --last;
  while (last + 1 < n && c[last + 1] <= hi) ++last;
  return {first, last};
}

/// Appends the crossings of triangle t with the grid's column lines.
void crossings_of(const Bvh::Tri& t, const std::vector<double>& xs, const std::vector<double>& ys,
                  const std::vector<double>& zs, std::vector<Crossing>& out) {
  const int nz = orient2d(t.a, t.b, t.c, 2);
  if (nz == 0) return;  // parallel to z: no perturbed column line crosses it
  const int n = static_cast<int>(xs.size());
  const auto [i0, i1] =
      centre_range(xs, std::min({t.a.x, t.b.x, t.c.x}), std::max({t.a.x, t.b.x, t.c.x}));
  const auto [j0, j1] =
      centre_range(ys, std::min({t.a.y, t.b.y, t.c.y}), std::max({t.a.y, t.b.y, t.c.y}));
  // Plane z(x, y) for the starting guess of `below` (exactness comes from the checks after it).
  const Vec3 nrm = cross(t.b - t.a, t.c - t.a);
  const double h = zs.size() > 1 ? zs[1] - zs[0] : 1;
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) {
      const Vec3 q{xs[i], ys[j], 0};
      if (perturbed_orient_xy(t.a, t.b, q) != nz || perturbed_orient_xy(t.b, t.c, q) != nz ||
          perturbed_orient_xy(t.c, t.a, q) != nz)
        continue;
      const double z = t.a.z - (nrm.x * (q.x - t.a.x) + nrm.y * (q.y - t.a.y)) / nrm.z;
      double guess = std::ceil((z - zs[0]) / h);
      guess = std::isfinite(guess) ? std::clamp(guess, 0.0, static_cast<double>(n)) : 0.0;
      int below = static_cast<int>(guess);
      // Centre k is below the triangle iff its perturbed side is opposite to n_z.
      auto is_below = [&](int k) { return perturbed_side(t, {q.x, q.y, zs[k]}) == -nz; };
      while (below > 0 && !is_below(below - 1)) --below;
      while (below < n && is_below(below)) ++below;
      out.push_back({static_cast<uint32_t>(i * n + j), static_cast<uint32_t>(below), t.leaf, nz});
    }
}

/// Sets bits [k0, k1) of one column.
void fill(uint64_t* column, int k0, int k1) {
  while (k0 < k1) {
    const int word = k0 / 64, bit = k0 % 64;
    const int count = std::min(64 - bit, k1 - k0);
    const uint64_t mask = count == 64 ? ~uint64_t{0} : ((uint64_t{1} << count) - 1) << bit;
    column[word] |= mask;
    k0 += count;
  }
}

}  // namespace

VoxelGrid voxelize(const Solid& solid, const VoxelizeOptions& options) {
  VoxelGrid g;
  voxelize(solid, options, g);
  return g;
}

void voxelize(const Solid& solid, const VoxelizeOptions& options, VoxelGrid& g) {
  g.n = options.resolution;
  if (options.bounds) {
    g.bounds = *options.bounds;
  } else {
    const std::optional<Bbox> box = result_bounds(solid);
    g.bounds = default_voxel_bounds(box && !box->empty() ? *box : solid.bbox(), std::max(g.n, 3));
  }
  const int n = g.n;
  const double h = g.voxel_size();
  const std::vector<double> xs = centres(g.bounds.min.x, h, n), ys = centres(g.bounds.min.y, h, n),
                            zs = centres(g.bounds.min.z, h, n);
  g.bits.assign(static_cast<size_t>(n) * n * g.words_per_column(), 0);

  // 1. Crossings, per fixed chunk of triangles (deterministic concatenation order).
  const std::vector<Bvh::Tri> tris = leaf_triangles(solid);
  constexpr size_t kChunk = 2048;
  std::vector<std::vector<Crossing>> parts((tris.size() + kChunk - 1) / kChunk);
  // Batches of whole chunks only give the progress callback a beat (80% of the work here, 20% in
  // step 3); chunk boundaries, hence the output, do not depend on them.
  const size_t batch = kChunk * std::max<size_t>(1, tris.size() / kChunk / 16);
  for (size_t b0 = 0; b0 < tris.size(); b0 += batch) {
    const size_t b1 = std::min(tris.size(), b0 + batch);
    parallel_for(b1 - b0, kChunk, [&](size_t begin, size_t end) {
      std::vector<Crossing>& out = parts[(b0 + begin) / kChunk];
      for (size_t t = b0 + begin; t < b0 + end; ++t) crossings_of(tris[t], xs, ys, zs, out);
    });
    if (options.progress) options.progress(0.8 * static_cast<double>(b1) / tris.size());
  }
  // 2. Group by column (counting sort), then order each column by (below, leaf).
  const size_t columns = static_cast<size_t>(n) * n;
  std::vector<uint32_t> start(columns + 1, 0);
  for (const auto& part : parts)
    for (const Crossing& c : part) ++start[c.column + 1];
  for (size_t c = 0; c < columns; ++c) start[c + 1] += start[c];
  std::vector<Crossing> sorted(start[columns]);
  {
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (auto& part : parts) {
      for (const Crossing& c : part) sorted[next[c.column]++] = c;
      std::vector<Crossing>().swap(part);
    }
  }
  // 3. Per column: sweep upwards with per-leaf windings; fill runs where the result is inside.
  const size_t leaves = solid.leaves.size();
  std::vector<uint8_t> none(leaves, 0);
  const bool outside_value = solid.tree.evaluate(none);  // membership with every winding 0
  constexpr size_t kColumns = 1024;
  const size_t column_batch = kColumns * std::max<size_t>(1, columns / kColumns / 8);
  for (size_t b0 = 0; b0 < columns; b0 += column_batch) {
    const size_t b1 = std::min(columns, b0 + column_batch);
    parallel_for(b1 - b0, kColumns, [&](size_t begin, size_t end) {
      std::vector<int> winding(leaves);
      std::vector<uint8_t> inside(leaves);
      for (size_t col = b0 + begin; col < b0 + end; ++col) {
        uint64_t* column = g.bits.data() + col * g.words_per_column();
        Crossing* first = sorted.data() + start[col];
        Crossing* last = sorted.data() + start[col + 1];
        if (first == last) {
          if (outside_value) fill(column, 0, n);
          continue;
        }
        std::sort(first, last, [](const Crossing& a, const Crossing& b) {
          return a.below < b.below || (a.below == b.below && a.leaf < b.leaf);
        });
        // Winding of centre k = Σ sign over crossings with below > k.
        std::fill(winding.begin(), winding.end(), 0);
        for (const Crossing* c = first; c != last; ++c) winding[c->leaf] += c->sign;
        int k = 0;
        for (const Crossing* c = first;;) {
          while (c != last && static_cast<int>(c->below) <= k) {
            winding[c->leaf] -= c->sign;
            ++c;
          }
          const int run_end = c == last ? n : static_cast<int>(c->below);
          for (size_t l = 0; l < leaves; ++l) inside[l] = winding[l] != 0;
          if (solid.tree.evaluate(inside)) fill(column, k, run_end);
          if (c == last || run_end >= n) break;
          k = run_end;
        }
      }
    });
    if (options.progress) options.progress(0.8 + 0.2 * static_cast<double>(b1) / columns);
  }
}

}  // namespace cover
