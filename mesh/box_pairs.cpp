// box_pairs() (mesh/box_pairs.h). Notation:
//   h             the cell side; cell (i, j, k) holds [lo + i·h, lo + (i+1)·h) per axis (the last
//                 cell of an axis also everything above), lo the lower corner of all boxes
//   cell(v, a)    min(n_a − 1, floor((v − lo_a) · (1/h))): monotone in v, so a box [p, q] covers
//                 exactly the cells cell(p, a) … cell(q, a) on each axis a
//   entry         (cell index << bits) | box, sorted: the boxes of each cell are contiguous
#include "cover/mesh/box_pairs.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <type_traits>
#include <vector>

#include "cover/solid/parallel.h"

namespace cover {
namespace {

struct Grid {
  Vec3 lo;
  double inv_h = 1;
  std::array<uint64_t, 3> n{1, 1, 1};

  uint64_t cell(double v, int a) const {
    const double c = std::floor((v - lo[a]) * inv_h);
    return c <= 0 ? 0 : std::min(n[a] - 1, static_cast<uint64_t>(c));
  }
  uint64_t index(uint64_t i, uint64_t j, uint64_t k) const { return (i * n[1] + j) * n[2] + k; }
  /// Cells box b covers.
  uint64_t covered(const Bbox& b) const {
    uint64_t c = 1;
    for (int a = 0; a < 3; ++a) c *= cell(b.max[a], a) - cell(b.min[a], a) + 1;
    return c;
  }
};

bool meet(const Bbox& a, const Bbox& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

constexpr size_t kGroupGrain = 256;  // cells per parallel chunk

/// A box of one grid cell: its bounds, its index, and per axis (bit a) whether its lower corner
/// lies in this cell's layer of the axis; with corners (box_pairs_between's filter), its colour
/// and corners.
struct Member {
  Bbox box;
  uint32_t id;
  uint8_t lower;
};
struct CornerMember : Member {
  uint32_t colour;
  BoxCorners corners;
};

/// True when a and b have one colour and share a corner id marked in a (marks belong to ids).
bool same_marked(const CornerMember& a, const CornerMember& b) {
  if (a.colour != b.colour || a.corners.marked == 0) return false;
  for (int i = 0; i < 3; ++i) {
    const uint32_t c = a.corners.id[i];
    if ((a.corners.marked >> i & 1) &&
        (c == b.corners.id[0] || c == b.corners.id[1] || c == b.corners.id[2]))
      return true;
  }
  return false;
}

/// The scan behind box_pairs() and box_pairs_between(): chunks(c) is told the number of
/// parallel chunks first, then pair(chunk, a, b) gets the pairs (of different colours when
/// `color` is given), a < b; it returns true to stop. With `corners` (and `colours`), pairs of
/// one colour sharing a marked corner are dropped (M = CornerMember).
/// A template on `pair`: it runs once per reported pair.
template <class M = Member, class Chunks, class Pair>
void scan(std::span<const Bbox> boxes, std::span<const uint32_t> color, Chunks&& chunks,
          Pair&& pair, std::span<const uint32_t> colours = {},
          std::span<const BoxCorners> corners = {}) {
  auto differ = [&](uint32_t a, uint32_t b) { return color.empty() || color[a] != color[b]; };
  Bbox all;
  double mean = 0;
  size_t count = 0;
  for (const Bbox& b : boxes)
    if (!b.empty()) {
      all.add(b);
      mean += std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
      ++count;
    }
  if (count < 2) {
    chunks(0);
    return;
  }
  mean /= static_cast<double>(count);
  const double extent =
      std::max({all.max.x - all.min.x, all.max.y - all.min.y, all.max.z - all.min.z});
  if (!(extent > 0)) {  // all boxes are one point: every pair meets
    chunks(1);
    auto dropped = [&](uint32_t a, uint32_t b) {
      if constexpr (std::is_same_v<M, CornerMember>)
        return same_marked({{}, colours[a], corners[a]}, {{}, colours[b], corners[b]});
      return false;
    };
    for (uint32_t a = 0; a < boxes.size(); ++a)
      for (uint32_t b = a + 1; b < boxes.size(); ++b)
        if (!boxes[a].empty() && !boxes[b].empty() && differ(a, b) && !dropped(a, b) &&
            pair(0, a, b))
          return;
    return;
  }
  const int bits = std::max(1, static_cast<int>(std::bit_width(boxes.size())));
  // The cell side: the mean box size, at least 2^-20 of the extent, doubled while the boxes
  // would cover more than 4 cells each on average or the cell indices would not fit the key.
  double h = std::max(mean, extent * 0x1p-20);
  Grid grid;
  grid.lo = all.min;
  for (;;) {
    grid.inv_h = 1 / h;
    for (int a = 0; a < 3; ++a)
      grid.n[a] = static_cast<uint64_t>(std::floor((all.max[a] - all.min[a]) * grid.inv_h)) + 1;
    const double cells = static_cast<double>(grid.n[0]) * static_cast<double>(grid.n[1]) *
                         static_cast<double>(grid.n[2]);
    if (cells < std::ldexp(1.0, 63 - bits)) {
      constexpr size_t kCountGrain = 8192;
      std::vector<uint64_t> part((boxes.size() + kCountGrain - 1) / kCountGrain, 0);
      parallel_for(boxes.size(), kCountGrain, [&](size_t begin, size_t end) {
        uint64_t sum = 0;
        for (size_t b = begin; b < end; ++b)
          if (!boxes[b].empty()) sum += grid.covered(boxes[b]);
        part[begin / kCountGrain] = sum;
      });
      uint64_t entries = 0;
      for (uint64_t x : part) entries += x;
      if (entries <= 4 * count || h >= extent) break;
    }
    h *= 2;
  }
  // Entries, in box order then cell order; then sorted by cell.
  std::vector<uint64_t> start(boxes.size() + 1, 0);
  for (size_t b = 0; b < boxes.size(); ++b)
    start[b + 1] = start[b] + (boxes[b].empty() ? 0 : grid.covered(boxes[b]));
  std::vector<uint64_t> entries(start.back());
  parallel_for(boxes.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b) {
      if (boxes[b].empty()) continue;
      uint64_t* out = entries.data() + start[b];
      const Bbox& x = boxes[b];
      const uint64_t i0 = grid.cell(x.min.x, 0), i1 = grid.cell(x.max.x, 0);
      const uint64_t j0 = grid.cell(x.min.y, 1), j1 = grid.cell(x.max.y, 1);
      const uint64_t k0 = grid.cell(x.min.z, 2), k1 = grid.cell(x.max.z, 2);
      for (uint64_t i = i0; i <= i1; ++i)
        for (uint64_t j = j0; j <= j1; ++j)
          for (uint64_t k = k0; k <= k1; ++k) *out++ = (grid.index(i, j, k) << bits) | b;
    }
  });
  start = {};
  parallel_sort(entries);
  const uint64_t mask = (uint64_t{1} << bits) - 1;
  std::vector<size_t> groups;  // starts of the cells holding two boxes or more
  for (size_t e = 0; e < entries.size();) {
    size_t f = e + 1;
    while (f < entries.size() && (entries[f] >> bits) == (entries[e] >> bits)) ++f;
    if (f - e > 1) groups.push_back(e);
    e = f;
  }
  groups.push_back(entries.size());
  chunks((groups.size() - 1 + kGroupGrain - 1) / kGroupGrain);
  // Per box, the cell of its lower corner: the intersection of two boxes has its lower corner
  // in the cell whose coordinates are the larger of the two per axis (cell() is monotone).
  std::vector<std::array<uint32_t, 3>> low(boxes.size());
  parallel_for(boxes.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b)
      if (!boxes[b].empty())
        for (int a = 0; a < 3; ++a)
          low[b][a] = static_cast<uint32_t>(grid.cell(boxes[b].min[a], a));
  });
  std::atomic<bool> stop{false};
  parallel_for(groups.size() - 1, kGroupGrain, [&](size_t g0, size_t g1) {
    const size_t chunk = g0 / kGroupGrain;
    // The cell's boxes copied side by side, so that the quadratic pair loop reads one small
    // array instead of scattered boxes (this loop is a hot spot of evaluation, and scattered
    // loads would dominate it).
    std::vector<M> cell_boxes;
    for (size_t g = g0; g < g1 && !stop.load(std::memory_order_relaxed); ++g) {
      const uint64_t cell = entries[groups[g]] >> bits;
      const uint32_t at[3] = {static_cast<uint32_t>(cell / (grid.n[1] * grid.n[2])),
                              static_cast<uint32_t>(cell / grid.n[2] % grid.n[1]),
                              static_cast<uint32_t>(cell % grid.n[2])};
      cell_boxes.clear();
      bool one_colour = !color.empty();
      for (size_t e = groups[g]; e < entries.size() && (entries[e] >> bits) == cell; ++e) {
        const uint32_t id = static_cast<uint32_t>(entries[e] & mask);
        uint8_t lower = 0;
        for (int a = 0; a < 3; ++a) lower |= static_cast<uint8_t>((low[id][a] == at[a]) << a);
        if constexpr (std::is_same_v<M, CornerMember>)
          cell_boxes.push_back({{boxes[id], id, lower}, colours[id], corners[id]});
        else
          cell_boxes.push_back({boxes[id], id, lower});
        one_colour = one_colour && color[id] == color[cell_boxes[0].id];
      }
      if (one_colour) continue;
      // The pair is this cell's when the lower corner of the intersection lies in it: both
      // boxes reach the cell, so per axis the larger lower cell is this one iff either is.
      auto report = [&](const M& a, const M& b) {
        if ((a.lower | b.lower) != 7 || !meet(a.box, b.box) || !differ(a.id, b.id)) return false;
        if constexpr (std::is_same_v<M, CornerMember>)
          if (same_marked(a, b)) return false;
        if (pair(chunk, std::min(a.id, b.id), std::max(a.id, b.id))) {
          stop = true;
          return true;
        }
        return false;
      };
      const size_t n = cell_boxes.size();
      if (n <= 32) {
        for (size_t p = 0; p < n; ++p)
          for (size_t q = p + 1; q < n; ++q)
            if (report(cell_boxes[p], cell_boxes[q])) return;
        continue;
      }
      std::sort(cell_boxes.begin(), cell_boxes.end(),
                [](const M& a, const M& b) { return a.box.min.x < b.box.min.x; });
      for (size_t p = 0; p < n; ++p)
        for (size_t q = p + 1; q < n && cell_boxes[q].box.min.x <= cell_boxes[p].box.max.x; ++q)
          if (report(cell_boxes[p], cell_boxes[q])) return;
    }
  });
}

/// The pairs between colours, sorted, and same(a, b) for those of one colour when given: with
/// `same` the scan sees every pair (no colour filter) and they are told apart here.
template <class M>
std::vector<std::pair<uint32_t, uint32_t>> between(
    std::span<const Bbox> boxes, std::span<const uint32_t> color,
    const std::function<void(uint32_t, uint32_t)>& same, std::span<const BoxCorners> corners) {
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found;
  scan<M>(
      boxes, same ? std::span<const uint32_t>{} : color, [&](size_t n) { found.resize(n); },
      [&](size_t chunk, uint32_t a, uint32_t b) {
        if (color[a] != color[b])
          found[chunk].emplace_back(a, b);
        else
          same(a, b);
        return false;
      },
      color, corners);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace

void box_pairs(std::span<const Bbox> boxes, const std::function<bool(uint32_t, uint32_t)>& pair) {
  scan(
      boxes, {}, [](size_t) {}, [&](size_t, uint32_t a, uint32_t b) { return pair(a, b); });
}

std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(std::span<const Bbox> boxes,
                                                             std::span<const uint32_t> color) {
  return box_pairs_between(boxes, color, nullptr);
}

std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(
    std::span<const Bbox> boxes, std::span<const uint32_t> color,
    std::span<const BoxCorners> corners, const std::function<void(uint32_t, uint32_t)>& same) {
  return between<CornerMember>(boxes, color, same, corners);
}

std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(
    std::span<const Bbox> boxes, std::span<const uint32_t> color,
    const std::function<void(uint32_t, uint32_t)>& same) {
  return between<Member>(boxes, color, same, {});
}

std::vector<BoxCorners> marked_corners(std::span<const std::array<uint32_t, 3>> tris,
                                       std::span<const uint8_t> flag) {
  std::vector<BoxCorners> out(tris.size());
  parallel_for(tris.size(), 8192, [&](size_t begin, size_t end) {
    for (size_t t = begin; t < end; ++t) {
      out[t].id = tris[t];
      for (int c = 0; c < 3; ++c) out[t].marked |= static_cast<uint8_t>(flag[tris[t][c]] << c);
    }
  });
  return out;
}

}  // namespace cover
