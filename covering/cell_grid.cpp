#include "cover/covering/detail/cell_grid.h"

#include <algorithm>

#include "cover/solid/parallel.h"

namespace cover::detail {
namespace {

/// Cells i with planes[i] <= hi and planes[i+1] >= lo, as [first, last] (exact comparisons).
std::pair<int, int> cell_range(const std::vector<double>& planes, double lo, double hi) {
  const int n = static_cast<int>(planes.size()) - 1;
  const int first =
      static_cast<int>(std::lower_bound(planes.begin(), planes.end(), lo) - planes.begin()) - 1;
  const int last =
      static_cast<int>(std::upper_bound(planes.begin(), planes.end(), hi) - planes.begin()) - 1;
  return {std::max(first, 0), std::min(last, n - 1)};
}

}  // namespace

CellGrid::CellGrid(const Bvh& bvh, int resolution, const std::function<bool(const Vec3&)>& member,
                   const std::function<bool(const Bbox&)>& settled) {
  if (bvh.nodes().empty() || resolution < 1) return;
  n_ = resolution;
  const Bbox& box = bvh.bounds();
  for (int a = 0; a < 3; ++a) {
    planes_[a].resize(n_ + 1);
    for (int i = 0; i <= n_; ++i) planes_[a][i] = box.min[a] + (box.max[a] - box.min[a]) * i / n_;
    planes_[a][n_] = box.max[a];
    scale_[a] = box.max[a] > box.min[a] ? n_ / (box.max[a] - box.min[a]) : 0;
  }
  state_.assign(static_cast<size_t>(n_) * n_ * n_, 2);  // 2: empty, not yet labelled
  for (uint32_t i = 0; i < bvh.triangle_count(); ++i) {
    const Bvh::Tri t = bvh.triangle(i);
    std::array<std::pair<int, int>, 3> r;
    for (int a = 0; a < 3; ++a)
      r[a] = cell_range(planes_[a], std::min({t.a[a], t.b[a], t.c[a]}),
                        std::max({t.a[a], t.b[a], t.c[a]}));
    for (int k = r[2].first; k <= r[2].second; ++k)
      for (int j = r[1].first; j <= r[1].second; ++j)
        for (int i = r[0].first; i <= r[0].second; ++i) state_[index(i, j, k)] = -1;
  }
  if (settled) {
    // Blocks of kBlock³ cells (each owned by one task), refined into octants where unsettled.
    constexpr int kBlock = 8;
    const int nb = (n_ + kBlock - 1) / kBlock;
    const std::function<void(int, int, int, int)> refine = [&](int i0, int j0, int k0, int s) {
      const int i1 = std::min(i0 + s, n_), j1 = std::min(j0 + s, n_), k1 = std::min(k0 + s, n_);
      if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
      bool any_empty = false;
      for (int k = k0; k < k1 && !any_empty; ++k)
        for (int j = j0; j < j1 && !any_empty; ++j)
          for (int i = i0; i < i1 && !any_empty; ++i) any_empty = state_[index(i, j, k)] == 2;
      if (!any_empty) return;
      Bbox box;
      box.min = {planes_[0][i0], planes_[1][j0], planes_[2][k0]};
      box.max = {planes_[0][i1], planes_[1][j1], planes_[2][k1]};
      if (settled(box)) return;
      if (s == 1) {
        state_[index(i0, j0, k0)] = -1;
        return;
      }
      const int h = s / 2;
      for (int dk : {0, h})
        for (int dj : {0, h})
          for (int di : {0, h}) refine(i0 + di, j0 + dj, k0 + dk, h);
    };
    parallel_for(static_cast<size_t>(nb) * nb * nb, 1, [&](size_t begin, size_t end) {
      for (size_t b = begin; b < end; ++b) {
        const int bi = static_cast<int>(b % nb), bj = static_cast<int>(b / nb % nb),
                  bk = static_cast<int>(b / nb / nb);
        refine(bi * kBlock, bj * kBlock, bk * kBlock, kBlock);
      }
    });
  }
  // Flood fill each component of empty cells from one exactly classified centre.
  std::vector<std::array<int, 3>> queue;
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i) {
        if (state_[index(i, j, k)] != 2) continue;
        const Vec3 c{0.5 * (planes_[0][i] + planes_[0][i + 1]),
                     0.5 * (planes_[1][j] + planes_[1][j + 1]),
                     0.5 * (planes_[2][k] + planes_[2][k + 1])};
        const int8_t label = member(c) ? 1 : 0;
        state_[index(i, j, k)] = label;
        queue.assign(1, {i, j, k});
        while (!queue.empty()) {
          const auto [x, y, z] = queue.back();
          queue.pop_back();
          const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z},
                                {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
          for (const auto& q : nb) {
            if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n_ || q[1] >= n_ || q[2] >= n_)
              continue;
            int8_t& s = state_[index(q[0], q[1], q[2])];
            if (s != 2) continue;
            s = label;
            queue.push_back({q[0], q[1], q[2]});
          }
        }
      }
}

int CellGrid::lookup(const Vec3& p) const {
  if (n_ == 0) return -1;
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const auto& pl = planes_[a];
    if (p[a] < pl.front() || p[a] > pl.back()) return -1;
    // A floating guess, then exact steps: any cell whose closed extent holds p is valid.
    int i = std::clamp(static_cast<int>((p[a] - pl.front()) * scale_[a]), 0, n_ - 1);
    while (i > 0 && p[a] < pl[i]) --i;
    while (i < n_ - 1 && p[a] > pl[i + 1]) ++i;
    c[a] = i;
  }
  return state_[index(c[0], c[1], c[2])];
}

}  // namespace cover::detail
