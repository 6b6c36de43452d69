// Voxel boundary surface (voxel_surface.h): one sweep over the x-slabs with word operations.
// Notation:
//   corner (i, j, k)  the grid point min + (i, j, k)·h, i, j, k in 0..N.
//   plane i           the corners with x index i.
//   octant o          one of the 8 voxels around a corner: bit 0 set = the voxel on the +x side
//                     of the corner (voxel i, not i − 1), bit 1 likewise for y, bit 2 for z.
//   mask              occupancy of the 8 octants (bit o).
//   quarter face q    a·8 + o with bit a of o clear: the part, at the corner, of the face normal
//                     to axis a between octants o and o | 1<<a (12 of the 24 codes are used).
//   half-edge         2·b + s: the segment from the corner along axis b, towards + if s = 1.
//   ext column        a voxel column padded with one empty voxel at each end: bit t is voxel
//                     k = t − 1 (t = 0..N+1); slab s (voxels x = s, s = −1..N, −1 and N empty)
//                     holds N + 2 ext columns, index j + 1 for j = −1..N (−1 and N empty).
// A corner's fans depend only on its mask: a table (256 masks) gives each boundary quarter face
// its fan and flags the half-edges whose 4 boundary faces all lie in one fan ("pinched"). An edge
// pinched at both ends cannot be told apart by its end vertices; the faces of one of its two
// occupied voxels then take the edge midpoint as an extra vertex (voxel_surface.h).
// Sweep: for plane i, the corners of plane i get their vertex copies (a base index per corner;
// copy = base + fan), then the y- and z-faces of slab i − 1 (corners in planes i − 1 and i) and
// the x-faces of plane i are emitted. Per-corner data is kept for two planes and written only at
// boundary corners (the only ones faces read), so nothing O(N²) is cleared per plane.

#include "cover/voxel/voxel_surface.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "cover/solid/errors.h"

namespace cover {
namespace {

struct CornerTable {
  std::array<std::array<int8_t, 24>, 256> fan{};  ///< fan of quarter face q, −1 if not boundary
  std::array<uint8_t, 256> fans{};                ///< number of fans (vertex copies)
  std::array<uint8_t, 256> pinched{};             ///< bit 2·b + s: pinched half-edge
};

CornerTable make_corner_table() {
  CornerTable table;
  for (int mask = 0; mask < 256; ++mask) {
    auto occupied = [&](int o) { return (mask >> o) & 1; };
    auto boundary = [&](int q) {
      const int a = q / 8, o = q % 8;
      return !((o >> a) & 1) && occupied(o) != occupied(o | 1 << a);
    };
    auto owner = [&](int q) { return occupied(q % 8) ? q % 8 : (q % 8) | 1 << (q / 8); };
    std::array<int, 24> parent;
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int q) {
      while (parent[q] != q) q = parent[q] = parent[parent[q]];
      return q;
    };
    // The 4 quarter faces around each half-edge; join them per the (6, 26) rule.
    std::array<std::array<int, 4>, 6> around{};
    std::array<int, 6> count{};
    for (int b = 0; b < 3; ++b)
      for (int s = 0; s < 2; ++s) {
        const int he = 2 * b + s;
        for (int a = 0; a < 3; ++a) {
          if (a == b) continue;
          const int c = 3 - a - b;
          for (int cbit = 0; cbit < 2; ++cbit) {
            const int q = a * 8 + (s << b | cbit << c);
            if (boundary(q)) around[he][count[he]++] = q;
          }
        }
        if (count[he] == 2) parent[find(around[he][0])] = find(around[he][1]);
        if (count[he] == 4)
          for (int x = 0; x < 4; ++x)
            for (int y = x + 1; y < 4; ++y)
              if (owner(around[he][x]) == owner(around[he][y]))
                parent[find(around[he][x])] = find(around[he][y]);
      }
    std::array<int8_t, 24> root_fan;
    root_fan.fill(-1);
    int fans = 0;
    for (int q = 0; q < 24; ++q) {
      table.fan[mask][q] = -1;
      if (!boundary(q)) continue;
      int8_t& f = root_fan[find(q)];
      if (f < 0) f = static_cast<int8_t>(fans++);
      table.fan[mask][q] = f;
    }
    table.fans[mask] = static_cast<uint8_t>(fans);
    for (int he = 0; he < 6; ++he) {
      if (count[he] != 4) continue;
      const int r = find(around[he][0]);
      bool one = true;
      for (int x = 1; x < 4; ++x) one = one && find(around[he][x]) == r;
      if (one) table.pinched[mask] |= static_cast<uint8_t>(1 << he);
    }
  }
  return table;
}

const CornerTable& corner_table() {
  static const CornerTable table = make_corner_table();
  return table;
}

struct Corner {
  int i, j, k;
  int q;  ///< quarter face of the emitted face at this corner
};

class SurfaceBuilder {
 public:
  explicit SurfaceBuilder(const VoxelGrid& grid)
      : grid_(grid),
        n_(grid.nx()),
        row_(static_cast<size_t>(n_) + 1),
        cw_((static_cast<size_t>(n_) + 2 + 63) / 64),
        h_(grid.voxel_size()),
        table_(corner_table()) {
    for (auto& e : ext_) e.assign((static_cast<size_t>(n_) + 2) * cw_, 0);
    for (int p = 0; p < 2; ++p) {
      base_[p].resize(row_ * row_);
      mask_[p].resize(row_ * row_);
    }
  }

  PolygonMesh build() {
    reserve();
    fill_slab(-1);
    for (int i = 0; i <= n_; ++i) {
      fill_slab(i);
      number_corners(i);
      if (i > 0) emit_slab_faces(i - 1);
      emit_x_faces(i);
    }
    return std::move(mesh_);
  }

 private:
  const uint64_t* column(int s, int j) const {
    return ext_[static_cast<size_t>(s + 2) & 1].data() + static_cast<size_t>(j + 1) * cw_;
  }
  /// Word w of the column shifted down by one bit (bit t becomes voxel t's occupancy).
  uint64_t shifted(const uint64_t* col, size_t w) const {
    return (col[w] >> 1) | (w + 1 < cw_ ? col[w + 1] << 63 : 0);
  }
  static int bit(const uint64_t* col, int t) {
    return static_cast<int>((col[t >> 6] >> (t & 63)) & 1);
  }
  size_t corner_index(int j, int k) const { return static_cast<size_t>(j) * row_ + k; }

  /// Counts the boundary faces (word operations) to reserve the result and refuse overflow.
  void reserve() {
    uint64_t faces = 0;
    fill_slab(-1);
    for (int i = 0; i <= n_; ++i) {
      fill_slab(i);
      for (int j = 0; j <= n_; ++j)
        for (size_t w = 0; w < cw_; ++w) {
          if (j < n_) {
            const uint64_t* e = column(i, j);
            faces += std::popcount(column(i - 1, j)[w] ^ e[w]);  // x = i
            faces += std::popcount(e[w] ^ shifted(e, w));        // z faces of column (i, j)
          }
          faces += std::popcount(column(i, j - 1)[w] ^ column(i, j)[w]);  // y = j
        }
    }
    if (faces * 4 > UINT32_MAX)
      throw NotComputable("voxel_surface: " + std::to_string(faces) +
                          " faces exceed 32-bit indices");
    mesh_.face_start.reserve(faces + 1);
    mesh_.face_vertices.reserve(faces * 4);
    mesh_.vertices.reserve(faces + 2);  // V = F + 2 per sphere-like component of quads
  }

  /// Loads slab s (voxels x = s) as padded columns; empty outside 0..N−1.
  void fill_slab(int s) {
    std::vector<uint64_t>& out = ext_[static_cast<size_t>(s + 2) & 1];
    std::fill(out.begin(), out.end(), 0);
    if (s < 0 || s >= n_) return;
    const size_t words = grid_.words_per_column();
    const unsigned tail = static_cast<unsigned>(n_ % 64);
    const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
    for (int j = 0; j < n_; ++j) {
      const uint64_t* in = grid_.bits.data() + grid_.column_word(s, j);
      uint64_t* col = out.data() + static_cast<size_t>(j + 1) * cw_;
      uint64_t carry = 0;
      for (size_t w = 0; w < cw_; ++w) {
        uint64_t v = w < words ? in[w] : 0;
        if (w + 1 == words) v &= last_mask;
        col[w] = v << 1 | carry;
        carry = v >> 63;
      }
    }
  }

  /// Gives each boundary corner of plane i one vertex per fan.
  void number_corners(int i) {
    const CornerTable& t = table_;
    const int p = i & 1;
    const double x = grid_.lattice.origin.x + i * h_;
    for (int j = 0; j <= n_; ++j) {
      const std::array<const uint64_t*, 4> c = {column(i - 1, j - 1), column(i, j - 1),
                                                column(i - 1, j), column(i, j)};
      const double y = grid_.lattice.origin.y + j * h_;
      for (size_t w = 0; w < cw_; ++w) {
        const uint64_t any = c[0][w] | c[1][w] | c[2][w] | c[3][w];
        const uint64_t all = c[0][w] & c[1][w] & c[2][w] & c[3][w];
        const uint64_t any_next =
            w + 1 < cw_ ? c[0][w + 1] | c[1][w + 1] | c[2][w + 1] | c[3][w + 1] : 0;
        const uint64_t all_next =
            w + 1 < cw_ ? c[0][w + 1] & c[1][w + 1] & c[2][w + 1] & c[3][w + 1] : 0;
        // Corner k sees ext bits k and k + 1 of the 4 columns.
        uint64_t corners = (any | any >> 1 | any_next << 63) & ~(all & (all >> 1 | all_next << 63));
        while (corners) {
          const int k = static_cast<int>(w * 64) + std::countr_zero(corners);
          corners &= corners - 1;
          int mask = 0;
          for (int o = 0; o < 8; ++o) mask |= bit(c[o & 3], k + (o >> 2)) << o;
          const size_t idx = corner_index(j, k);
          const size_t base = mesh_.vertices.size();
          if (base + t.fans[mask] > UINT32_MAX)
            throw NotComputable("voxel_surface: vertices exceed 32-bit indices");
          mask_[p][idx] = static_cast<uint8_t>(mask);
          base_[p][idx] = static_cast<uint32_t>(base);
          const Vec3 v{x, y, grid_.lattice.origin.z + k * h_};
          for (int f = 0; f < t.fans[mask]; ++f) mesh_.vertices.push_back(v);
        }
      }
    }
  }

  /// x-faces of plane i: between voxels (i − 1, j, k) and (i, j, k).
  void emit_x_faces(int i) {
    for (int j = 0; j < n_; ++j) {
      const uint64_t* lo = column(i - 1, j);
      const uint64_t* hi = column(i, j);
      for (size_t w = 0; w < cw_; ++w) {
        uint64_t faces = lo[w] ^ hi[w];
        while (faces) {
          const int t = static_cast<int>(w * 64) + std::countr_zero(faces);
          faces &= faces - 1;
          const int k = t - 1;
          const bool inside_hi = bit(hi, t);
          // Counter-clockwise seen from +x.
          emit({Corner{i, j, k, 6}, Corner{i, j + 1, k, 4}, Corner{i, j + 1, k + 1, 0},
                Corner{i, j, k + 1, 2}},
               inside_hi, {inside_hi ? i : i - 1, j, k});
        }
      }
    }
  }

  /// y- and z-faces of slab s (between planes s and s + 1).
  void emit_slab_faces(int s) {
    for (int j = 0; j <= n_; ++j) {
      const uint64_t* lo = column(s, j - 1);
      const uint64_t* hi = column(s, j);
      for (size_t w = 0; w < cw_; ++w) {
        uint64_t faces = lo[w] ^ hi[w];
        while (faces) {
          const int t = static_cast<int>(w * 64) + std::countr_zero(faces);
          faces &= faces - 1;
          const int k = t - 1;
          const bool inside_hi = bit(hi, t);
          // Counter-clockwise seen from −y.
          emit({Corner{s, j, k, 13}, Corner{s + 1, j, k, 12}, Corner{s + 1, j, k + 1, 8},
                Corner{s, j, k + 1, 9}},
               !inside_hi, {s, inside_hi ? j : j - 1, k});
        }
      }
      if (j == n_) continue;
      for (size_t w = 0; w < cw_; ++w) {
        uint64_t faces = hi[w] ^ shifted(hi, w);
        while (faces) {
          const int k = static_cast<int>(w * 64) + std::countr_zero(faces);
          faces &= faces - 1;
          const bool inside_below = bit(hi, k);
          // Counter-clockwise seen from +z.
          emit({Corner{s, j, k, 19}, Corner{s + 1, j, k, 18}, Corner{s + 1, j + 1, k, 16},
                Corner{s, j + 1, k, 17}},
               !inside_below, {s, j, inside_below ? k - 1 : k});
        }
      }
    }
  }

  /// Appends one face, its corners in counter-clockwise order (reversed if `reverse`); `voxel`
  /// is its occupied voxel.
  void emit(const std::array<Corner, 4>& corners, bool reverse, const std::array<int, 3>& voxel) {
    std::array<uint32_t, 4> v;
    std::array<uint8_t, 4> m;
    uint8_t pinched = 0;
    for (int x = 0; x < 4; ++x) {
      const Corner& c = corners[x];
      const size_t idx = corner_index(c.j, c.k);
      m[x] = mask_[c.i & 1][idx];
      v[x] = base_[c.i & 1][idx] + static_cast<uint32_t>(table_.fan[m[x]][c.q]);
      pinched |= table_.pinched[m[x]];
    }
    static constexpr std::array<int, 4> kForward = {0, 1, 2, 3}, kBackward = {0, 3, 2, 1};
    const std::array<int, 4>& order = reverse ? kBackward : kForward;
    for (int x = 0; x < 4; ++x) {
      mesh_.face_vertices.push_back(v[order[x]]);
      if (pinched)
        add_midpoint(corners[order[x]], m[order[x]], corners[order[(x + 1) % 4]],
                     m[order[(x + 1) % 4]], voxel);
    }
    if (mesh_.face_vertices.size() > UINT32_MAX)
      throw NotComputable("voxel_surface: face indices exceed 32 bits");
    mesh_.face_start.push_back(static_cast<uint32_t>(mesh_.face_vertices.size()));
  }

  /// Appends the midpoint of edge a–b if the edge is pinched at both ends and `voxel` is its
  /// occupied voxel on the low side of the first axis normal to the edge.
  void add_midpoint(const Corner& a, uint8_t mask_a, const Corner& b, uint8_t mask_b,
                    const std::array<int, 3>& voxel) {
    const int axis = a.i != b.i ? 0 : a.j != b.j ? 1 : 2;
    const std::array<int, 3> pa = {a.i, a.j, a.k}, pb = {b.i, b.j, b.k};
    const bool a_low = pa[axis] < pb[axis];
    const std::array<int, 3>& low = a_low ? pa : pb;
    const uint8_t mask_low = a_low ? mask_a : mask_b, mask_high = a_low ? mask_b : mask_a;
    if (!((table_.pinched[mask_low] >> (2 * axis + 1)) & 1) ||
        !((table_.pinched[mask_high] >> (2 * axis)) & 1))
      return;
    const int normal = axis == 0 ? 1 : 0;
    if (voxel[normal] >= low[normal]) return;
    const uint64_t key =
        ((static_cast<uint64_t>(low[0]) * row_ + low[1]) * row_ + low[2]) * 3 + axis;
    const auto found = midpoints_.find(key);
    if (found != midpoints_.end()) {
      mesh_.face_vertices.push_back(found->second);
      midpoints_.erase(found);  // both faces of the pair have it now
      return;
    }
    if (mesh_.vertices.size() >= UINT32_MAX)
      throw NotComputable("voxel_surface: vertices exceed 32-bit indices");
    const uint32_t index = static_cast<uint32_t>(mesh_.vertices.size());
    std::array<double, 3> c;
    const std::array<double, 3> min = {grid_.lattice.origin.x, grid_.lattice.origin.y,
                                       grid_.lattice.origin.z};
    for (int d = 0; d < 3; ++d) c[d] = min[d] + (d == axis ? low[d] + 0.5 : low[d]) * h_;
    mesh_.vertices.push_back({c[0], c[1], c[2]});
    mesh_.face_vertices.push_back(index);
    midpoints_.emplace(key, index);
  }

  const VoxelGrid& grid_;
  const int n_;
  const size_t row_;  ///< corners per axis, N + 1
  const size_t cw_;   ///< words per ext column
  const double h_;
  const CornerTable& table_;
  std::array<std::vector<uint64_t>, 2> ext_;          ///< slabs s with s + 2 even / odd
  std::array<std::vector<uint32_t>, 2> base_;         ///< planes i even / odd: first vertex copy
  std::array<std::vector<uint8_t>, 2> mask_;          ///< planes i even / odd: octant mask
  std::unordered_map<uint64_t, uint32_t> midpoints_;  ///< edges with one of two faces emitted
  PolygonMesh mesh_;
};

}  // namespace

PolygonMesh voxel_surface(const VoxelGrid& grid) {
  if (grid.nx() <= 0) return {};
  if (!grid.whole() || !grid.lattice.cubic())
    throw PreconditionError("voxel_surface: a whole cubic grid expected");
  return SurfaceBuilder(grid).build();
}

}  // namespace cover
