#include "cover/voxel/voxelize.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "cover/covering/bounds.h"
#include "cover/covering/bvh_walk.h"
#include "cover/covering/classify.h"
#include "cover/solid/errors.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/simd.h"

namespace cover {
namespace {

/// Shortest decimal text that reads back as `value` ("1e-10", not std::to_string's "0.000000").
std::string shortest(double value) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

/// One crossing of a column's centre line by a covering triangle, as the triangle pass records it.
struct Crossing {
  uint32_t column;  ///< column within its band: (i − first row of the band)·N + j
  uint32_t leaf;
  uint32_t below;  ///< number of voxel centres of the column below the triangle (0..N)
  int32_t sign;    ///< n_z: winding contribution to the centres below
};

/// Per-column sort key of a crossing: (below, leaf, sign) packed so that integer order is
/// (below, leaf) order. below ≤ kMaxVoxelDims = 16384 needs 15 bits, leaf 32, sign 1: 48 bits.
uint64_t crossing_key(const Crossing& c) {
  return (uint64_t{c.below} << 33) | (uint64_t{c.leaf} << 1) | (c.sign > 0 ? 1u : 0u);
}
int key_below(uint64_t key) { return static_cast<int>(key >> 33); }
uint32_t key_leaf(uint64_t key) { return static_cast<uint32_t>(key >> 1); }
int key_sign(uint64_t key) { return (key & 1) ? 1 : -1; }

/// Sign of the projected (x, y) orientation of (a, b, q) with q → q + (ε, ε²) (as in classify).
int perturbed_orient_xy(const Vec3& a, const Vec3& b, const Vec3& q) {
  const int o = orient2d(a, b, q, 2);
  if (o != 0) return o;
  if (a.y != b.y) return a.y > b.y ? 1 : -1;
  if (a.x != b.x) return b.x > a.x ? 1 : -1;
  return 0;
}

/// Side of c + (ε, ε², ε³) relative to the plane of abc: sign of n·(c' − a).
int perturbed_side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  if (const int s = orient3d(a, b, c, p)) return s;
  if (const int s = orient2d(a, b, c, 0)) return s;
  if (const int s = orient2d(a, b, c, 1)) return s;
  return orient2d(a, b, c, 2);
}

/// Coordinates of the voxel centres first..first+count−1 along one axis: the doubles
/// VoxelLattice::centre() computes, from the GLOBAL index (never re-based on the brick).
std::vector<double> centres(double min, double h, int first, int count) {
  std::vector<double> c(static_cast<size_t>(count));
  for (int t = 0; t < count; ++t) c[t] = min + ((first + t) + 0.5) * h;
  return c;
}

/// Indices [first, last] of the centres inside [lo, hi], or first > last: a floating-point
/// guess, then exact comparisons with the centre coordinates.
/// inv_h: 1 / (c[1] − c[0]) (1 when N = 1), computed once by the caller. `c` may be any run of
/// consecutive centres (a brick's): the guess is relative to c[0], the answer exact.
std::pair<int, int> centre_range(const std::vector<double>& c, double inv_h, double lo, double hi) {
  const int n = static_cast<int>(c.size());
  // A guess only (the loops below make it exact): truncation instead of floor (std::floor is a
  // library call without SSE4.1), NaN and out-of-range values clamped before the conversion.
  auto guess = [&](double v) {
    double g = (v - c[0]) * inv_h;
    if (!(g > -1)) g = -1;
    if (g > n) g = n;
    return static_cast<int>(g);
  };
  int first = std::max(0, guess(lo));
  while (first > 0 && c[first - 1] >= lo) --first;
  while (first < n && c[first] < lo) ++first;
  int last = std::min(n - 1, guess(hi) + 1);
  while (last >= 0 && c[last] > hi) --last;
  while (last + 1 < n && c[last + 1] <= hi) ++last;
  return {first, last};
}

using detail::v2d;
using detail::vabs;

/// One covering triangle as a band needs it (computed once, before the bands).
struct BandTriangle {
  uint32_t v[3];  ///< vertex indices, leaf orientation
  uint32_t leaf;
  uint16_t i0, i1;  ///< rows whose centre x lies in the triangle's x range (≤ kMaxVoxelDims)
  uint16_t j0, j1;  ///< the same for columns and y
  int8_t nz;        ///< orient2d(a, b, c, 2) ≠ 0: winding contribution to the centres below
  bool moderate;    ///< every coordinate of a, b, c is moderate()
};

/// Whether v is 0 or of magnitude in [2^-100, 2^100]. When every coordinate a filter sees
/// (triangle vertices and voxel centres) is moderate, its range guard never rejects: see
/// crossings_of.
bool moderate(double v) {
  const double m = std::abs(v);
  return (m == 0) | ((m >= 0x1p-100) & (m <= 0x1p100));  // no branches: vectorizable loops
}
bool moderate(const Vec3& v) { return moderate(v.x) & moderate(v.y) & moderate(v.z); }

/// Sign of one projected edge test orient2d(p, q, centre), given its filter terms (see
/// crossings_of): the filter's sign when decided, else the exact perturbed predicate.
int edge_sign(double det, double sum, const Vec3& p, const Vec3& q, const Vec3& centre) {
  const int s = detail::filter_sign(det, sum, detail::kOrient2dErr);
  return s != 0 ? s : perturbed_orient_xy(p, q, centre);
}

/// Appends the crossings of covering triangle abc (leaf orientation, n_z = nz ≠ 0) with the
/// column lines of rows i0..i1 and columns j0..j1 (the triangle's bounding box, rows clipped to
/// one band); `column` is (i − band_first_row)·N + j.
///
/// Work at bunny00 512³: 95k triangle visits, 820k candidate columns, 324k crossings, and this
/// function is about half of a single-thread call. So a candidate does not make three branching
/// orient2d calls nor a crossing two orient3d calls: the terms are shared (below), the
/// classification is branch-free and a crossing takes one paired side test in the common case.
/// Candidates are kept in per-row blocks (one list across all rows is slower).
///
/// Every decision is still the one the exact predicates take. For a column point q = (x, y) the
/// three projected edge tests orient2d(b, c, q), orient2d(c, a, q), orient2d(a, b, q) compute
/// exactly the 2×2 minors M_a, M_b, M_c (and the sums P_a, P_b, P_c of their products'
/// magnitudes) that Shewchuk's orient3d(a, b, c, (x, y, z)) expands along its z column:
///   det(z) = (a.z − z)·M_a + (b.z − z)·M_b + (c.z − z)·M_c,
///   permanent(z) = P_a·|a.z − z| + P_b·|b.z − z| + P_c·|c.z − z|.
/// The code below evaluates these with the same floating-point operations on the same operands
/// in the same order as orient2d / orient3d (IEEE products and sums are commutative; the build
/// has -ffp-contract=off), so the filtered values are bit-identical to theirs and the filters'
/// error bounds (Shewchuk's, see predicates.h) apply unchanged; multiplying by nz = ±1 is exact.
/// Where a filter is undecided, the full perturbed predicate (exact fallback included) decides.
/// No new error analysis, no epsilon.
///
/// kModerate (every coordinate of a, b, c and of the voxel centres moderate()): the filters'
/// range guards (sum, permanent ∈ (kFilterMin, kFilterMax) = (1e-200, 1e200)) are dropped from
/// the hot loops, which decide exactly as with them (~7% of the call at 512³). Proof: every
/// coordinate is then an integer multiple of 2^-152 (a double of magnitude ≥ 2^-100 has an ulp
/// ≥ 2^-152), so a rounded coordinate difference is 0 (equal coordinates) or in
/// [2^-152, 2^101] (rounding is monotone and both ends are doubles); a rounded product of two
/// nonzero differences is in [2^-304, 2^202]; so a sum P = |l| + |r| is 0 or in
/// [2^-304, 2^204], and a permanent (three terms P·|dz|) is 0 or in [2^-456, 2^307] — inside
/// (1e-200, 1e200) whenever nonzero, so the guard passes. When it is 0, every product in it is 0,
/// hence the minor M = l − r (resp. det, whose terms dz·M vanish with P or dz) is 0 and the
/// bound is 0: neither "> bound" nor "< −bound" holds, undecided with or without the guard.
template <bool kModerate>
void crossings_of(const Vec3& a, const Vec3& b, const Vec3& c, uint32_t leaf, int nz, int i0,
                  int i1, int j0, int j1, int band_first_row, const std::vector<double>& xs,
                  const std::vector<double>& ys, const std::vector<double>& zs,
                  std::vector<Crossing>& out) {
  const int ny = static_cast<int>(ys.size()),
            nk = static_cast<int>(zs.size());  // columns per row, centres per column
  const double inv_h = zs.size() > 1 ? 1 / (zs[1] - zs[0]) : 1;
  const double snz = nz;
  // The plane's z in centre-index units, k(x, y) = k0 + kx·(x − a.x) + ky·(y − a.y): only the
  // starting guess of `below` (the side tests decide), so plain floating point; per triangle
  // rather than a division per crossing.
  const Vec3 nrm = cross(b - a, c - a);
  const double k0 = (a.z - zs[0]) * inv_h, kx = -nrm.x / nrm.z * inv_h, ky = -nrm.y / nrm.z * inv_h;
  constexpr double kEps2 = detail::kOrient2dErr;
  auto in_range = [](auto sum) { return (sum > detail::kFilterMin) & (sum < detail::kFilterMax); };
  constexpr int kBlock = 64;
  int inside[kBlock];
  // The block's minors M_a, M_b, M_c (signs as orient2d) and sums P_a, P_b, P_c, kept for the
  // side tests.
  double m[3][kBlock], p[3][kBlock];
  for (int i = i0; i <= i1; ++i) {
    const double x = xs[i];
    const double adx = a.x - x, bdx = b.x - x, cdx = c.x - x;
    for (int jb = j0; jb <= j1; jb += kBlock) {
      const int je = std::min(j1 + 1, jb + kBlock);
      // Classify the block's centres without branches on the (unpredictable) outcome: inside
      // when the three filters decide n_z, outside when one decides −n_z, else undecided
      // (rare: the exact predicates decide, in a branch).
      uint8_t status[kBlock];  // 1: inside, 2: undecided, 0: outside
      for (int j = jb; j < je; ++j) {
        const int t = j - jb;
        const double y = ys[j];
        const double ady = a.y - y, bdy = b.y - y, cdy = c.y - y;
        const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
        const double cdxady = cdx * ady, adxcdy = adx * cdy;
        const double adxbdy = adx * bdy, bdxady = bdx * ady;
        m[0][t] = bdxcdy - cdxbdy, p[0][t] = std::abs(bdxcdy) + std::abs(cdxbdy);
        m[1][t] = cdxady - adxcdy, p[1][t] = std::abs(cdxady) + std::abs(adxcdy);
        m[2][t] = adxbdy - bdxady, p[2][t] = std::abs(adxbdy) + std::abs(bdxady);
        const double sma = snz * m[0][t], smb = snz * m[1][t], smc = snz * m[2][t];
        const double ba = kEps2 * p[0][t], bb = kEps2 * p[1][t], bc = kEps2 * p[2][t];
        const bool ga = kModerate || in_range(p[0][t]), gb = kModerate || in_range(p[1][t]),
                   gc = kModerate || in_range(p[2][t]);
        const bool in = ga & gb & gc & (sma > ba) & (smb > bb) & (smc > bc);
        const bool outside = (ga & (sma < -ba)) | (gb & (smb < -bb)) | (gc & (smc < -bc));
        status[t] = static_cast<uint8_t>(in | ((!in & !outside) << 1));
      }
      int count = 0;
      for (int j = jb; j < je; ++j) {
        const int t = j - jb;
        inside[count] = j;
        count += status[t] & 1;
        if (status[t] & 2) [[unlikely]] {
          const Vec3 q{x, ys[j], 0};
          if (edge_sign(m[0][t], p[0][t], b, c, q) == nz &&
              edge_sign(m[1][t], p[1][t], c, a, q) == nz &&
              edge_sign(m[2][t], p[2][t], a, b, q) == nz)
            inside[count++] = j;
        }
      }
      for (int u = 0; u < count; ++u) {
        const int j = inside[u], t = j - jb;
        const double y = ys[j];
        const double ma = m[0][t], mb = m[1][t], mc = m[2][t];
        const double pa = p[0][t], pb = p[1][t], pc = p[2][t];
        // Side of centre (x, y, z) to the plane of abc: orient3d's filter on the terms above.
        auto side = [&](double z) {
          const double adz = a.z - z, bdz = b.z - z, cdz = c.z - z;
          const double det = adz * ma + bdz * mb + cdz * mc;
          const double permanent = pa * std::abs(adz) + pb * std::abs(bdz) + pc * std::abs(cdz);
          if (in_range(permanent)) {
            const double bound = detail::kOrient3dErr * permanent;
            if (det > bound) return -1;  // orient3d's sign is the negation of Shewchuk's det
            if (det < -bound) return 1;
          }
          return perturbed_side(a, b, c, {x, y, z});
        };
        // Starting guess of `below`: the number of centres under the plane (truncation + 1
        // stands in for ceil; NaN and out-of-range values are clamped first).
        double g = k0 + kx * (x - a.x) + ky * (y - a.y);
        if (!(g > -1)) g = -1;
        if (g > nk) g = nk;
        int below = std::clamp(static_cast<int>(g) + 1, 0, nk);
        // Centre k is below the triangle iff its perturbed side is opposite to n_z (the side is
        // never 0: n_z ≠ 0). The common case, the guess right and both of its neighbours
        // decided by the filter, takes one paired evaluation of the side filter (the same
        // operations as `side` on both centres; ~6% of the call at 512³ together with keeping
        // the minors); otherwise the walk below tests centre by centre.
        if (below > 0 && below < nk) {
          const v2d z = {zs[below - 1], zs[below]};
          const v2d adz = v2d{a.z, a.z} - z, bdz = v2d{b.z, b.z} - z, cdz = v2d{c.z, c.z} - z;
          const v2d det = adz * ma + bdz * mb + cdz * mc;
          const v2d permanent = pa * vabs(adz) + pb * vabs(bdz) + pc * vabs(cdz);
          const v2d bound = detail::kOrient3dErr * permanent;
          // Below: orient3d = −n_z, i.e. n_z·det > bound; above: n_z·det < −bound.
          const v2d sdet = snz * det;
          if ((kModerate || (in_range(permanent[0]) & in_range(permanent[1]))) &
              (sdet[0] > bound[0]) & (sdet[1] < -bound[1])) {
            out.push_back({static_cast<uint32_t>((i - band_first_row) * ny + j), leaf,
                           static_cast<uint32_t>(below), nz});
            continue;
          }
        }
        auto is_below = [&](int k) { return side(zs[k]) == -nz; };
        while (below > 0 && !is_below(below - 1)) --below;
        while (below < nk && is_below(below)) ++below;
        out.push_back({static_cast<uint32_t>((i - band_first_row) * ny + j), leaf,
                       static_cast<uint32_t>(below), nz});
      }
    }
  }
}

/// Vertex loads in mesh order miss the caches (bunny00's faces reference vertices all over its
/// 900 KB vertex array): the loops over triangles prefetch the vertices kAhead triangles ahead
/// (~5% of the call at 512³).
constexpr size_t kAhead = 8;
void prefetch_face_vertices(const Solid& solid, size_t f) {
  for (const uint32_t v : solid.face(f)) __builtin_prefetch(&solid.vertices[v]);
}

/// Sets bits [k0, k1) of one column.
void fill(uint64_t* column, int k0, int k1) {
  if (k0 >= k1) return;
  const int w0 = k0 >> 6, w1 = (k1 - 1) >> 6;  // first and last word touched
  const uint64_t head = ~uint64_t{0} << (k0 & 63);
  const uint64_t tail = ~uint64_t{0} >> (63 - ((k1 - 1) & 63));
  if (w0 == w1) {
    column[w0] |= head & tail;
    return;
  }
  column[w0] |= head;
  for (int w = w0 + 1; w < w1; ++w) column[w] = ~uint64_t{0};
  column[w1] |= tail;
}

}  // namespace

VoxelLattice voxel_lattice(const Bbox& result_box, const VoxelizeOptions& options) {
  const bool by_size = options.voxel_size != 0;
  const bool by_dims = options.dims != std::array<int, 3>{};
  if (!by_size && !by_dims) {
    const int n = options.resolution;
    return cubic_lattice(
        options.bounds ? *options.bounds : default_voxel_bounds(result_box, std::max(n, 3)), n);
  }
  if (by_size && by_dims)
    throw InputError(parameter("voxel_size") + " and " + parameter("dims") +
                     ": give one of them, not both");
  if (by_size && !(options.voxel_size > 0 && std::isfinite(options.voxel_size)))
    throw InputError(parameter("voxel_size") + ": expected a finite number > 0");
  for (const int d : options.dims)
    if (by_dims && (d < 1 || d > kMaxVoxelDims))
      throw InputError(parameter("dims") + ": expected three whole numbers from 1 to " +
                       std::to_string(kMaxVoxelDims) + ", got " + std::to_string(d));
  // The box B to cover: the given cube, else the result's box; no extent anywhere (or empty):
  // the unit cube around its centre.
  Bbox box = result_box;
  if (options.bounds) {
    const VoxelBounds& b = *options.bounds;
    box = Bbox{b.min, b.min + Vec3{b.size, b.size, b.size}};
  }
  std::array<double, 3> lo{}, extent{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = box.empty() ? 0 : box.min[a];
    extent[a] = box.empty() ? 0 : std::max(0.0, box.max[a] - box.min[a]);
  }
  if (!(std::max({extent[0], extent[1], extent[2]}) > 0)) {
    for (int a = 0; a < 3; ++a) lo[a] = lo[a] + 0.5 * extent[a] - 0.5, extent[a] = 1;
  }
  VoxelLattice lattice;
  lattice.origin = {lo[0], lo[1], lo[2]};
  if (by_size) {
    const double h = options.voxel_size;
    lattice.spacing = h;
    for (int a = 0; a < 3; ++a) {
      const double guess = std::ceil(extent[a] / h);
      if (!(guess <= kMaxVoxelDims))
        throw InputError(parameter("voxel_size") + ": " + shortest(h) + " gives more than " +
                         std::to_string(kMaxVoxelDims) + " voxels on an axis");
      int d = std::max(1, static_cast<int>(guess));
      while (d * h < extent[a]) ++d;  // the rounded quotient may fall short by one
      if (d > kMaxVoxelDims)
        throw InputError(parameter("voxel_size") + ": too small, more than " +
                         std::to_string(kMaxVoxelDims) + " voxels on an axis");
      lattice.dims[a] = d;
    }
  } else {
    lattice.dims = options.dims;
    double h = 0;
    for (int a = 0; a < 3; ++a) h = std::max(h, extent[a] / lattice.dims[a]);
    for (int a = 0; a < 3; ++a)
      while (lattice.dims[a] * h < extent[a]) h = std::nextafter(h, INFINITY);
    lattice.spacing = h;
  }
  return lattice;
}

VoxelGrid voxelize(const Prepared& prepared, const VoxelizeOptions& options) {
  VoxelGrid g;
  voxelize(prepared, options, g);
  return g;
}

void voxelize(const Prepared& prepared, const VoxelizeOptions& options, VoxelGrid& g) {
  const Solid& solid = prepared.solid();
  VoxelLattice lattice;
  if (options.bounds) {
    lattice = voxel_lattice(Bbox{}, options);
  } else {
    const std::optional<Bbox> box = result_bounds(solid);
    lattice = voxel_lattice(box && !box->empty() ? *box : solid.bbox(), options);
  }
  voxelize_brick(prepared, lattice, whole_box(lattice), g, options.progress);
}

VoxelGrid voxelize(const Solid& solid, const VoxelizeOptions& options) {
  const Prepared prepared(solid);
  return voxelize(prepared, options);
}

void voxelize_brick(const Prepared& prepared, const VoxelLattice& lattice, const IndexBox& box,
                    VoxelGrid& grid, const std::function<void(double)>& progress) {
  const Solid& solid = prepared.solid();
  // Open and field leaves: membership is not a sweep of crossings: classify the centres.
  if (solid.has_open_leaf() || solid.has_implicit_leaf()) {
    grid = empty_voxel_grid(lattice, box);
    classify_lattice(prepared, lattice, box, [&](int i, int j, int k) { grid.set(i, j, k); });
    if (progress) progress(1.0);
    return;
  }
  if (box == whole_box(lattice)) {  // every face: no culling to do
    voxelize_brick(solid, lattice, box, nullptr, grid, progress);
    return;
  }
  // The faces with a covering triangle whose box may reach the brick's column centres: BVH
  // nodes whose (outward-rounded) x/y bounds meet [x of the first column, x of the last] × the
  // same for y, and whose top is not below the brick's lowest centre (a triangle wholly below
  // every centre of the brick has none of them below it: it adds nothing). Only culling: the
  // sweep decides every row and column exactly.
  const double xlo = lattice.centre(box.lo[0], 0, 0).x, xhi = lattice.centre(box.hi[0] - 1, 0, 0).x;
  const double ylo = lattice.centre(0, box.lo[1], 0).y, yhi = lattice.centre(0, box.hi[1] - 1, 0).y;
  const double zlo = lattice.centre(0, 0, box.lo[2]).z;
  std::vector<uint32_t> faces;
  walk(
      prepared.bvh(),
      [&](const Bvh::Node& node) {
        return node.lo[0] <= xhi && node.hi[0] >= xlo && node.lo[1] <= yhi && node.hi[1] >= ylo &&
               node.hi[2] >= zlo;
      },
      [&](const Bvh::Tri& t, uint32_t) { faces.push_back(t.face); });
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  voxelize_brick(solid, lattice, box, &faces, grid, progress);
}

void voxelize_brick(const Solid& solid, const VoxelLattice& lattice, const IndexBox& box,
                    const std::vector<uint32_t>* face_list, VoxelGrid& g,
                    const std::function<void(double)>& progress) {
  g.lattice = lattice;
  g.box = box;
  // A brick is the whole-grid algorithm run on the slices of the global centre arrays
  // (docs/scale-out.md#bricks): every decision below is taken on the same doubles by the same exact
  // predicates as for the whole grid. centre_range finds, within the slices, exactly the rows
  // and columns whose centres the triangle's x/y range contains (the rest of the grid's columns
  // are not visited); `below` over the sliced zs is the number of the brick's centres below the
  // crossing, i.e. the global count clamped to [k0, k1) and shifted by k0. As a crossing adds
  // its sign to the winding of every centre below it, one above the brick still counts for all
  // of the brick's centres of that column (below = nk) and one under the brick for none
  // (below = 0): the brick's windings, hence its bits, equal the whole grid's.
  const int nx = g.nx(), ny = g.ny(), nk = g.nz();
  const double h = lattice.spacing;
  const std::vector<double> xs = centres(lattice.origin.x, h, box.lo[0], nx),
                            ys = centres(lattice.origin.y, h, box.lo[1], ny),
                            zs = centres(lattice.origin.z, h, box.lo[2], nk);
  const double inv_hx = nx > 1 ? 1 / (xs[1] - xs[0]) : 1, inv_hy = ny > 1 ? 1 / (ys[1] - ys[0]) : 1;
  // Whether all centres, and all vertices (one pass here instead of nine tests per triangle:
  // those would be ~4% of the call at 512³), are moderate().
  bool moderate_centres = true, moderate_vertices = true;
  for (const double x : xs) moderate_centres &= moderate(x);
  for (const double y : ys) moderate_centres &= moderate(y);
  for (const double z : zs) moderate_centres &= moderate(z);
  // A brick given its faces checks their vertices triangle by triangle instead (no pass over
  // the whole mesh per brick).
  if (face_list)
    moderate_vertices = false;
  else
    for (const Vec3& v : solid.vertices) moderate_vertices &= moderate(v);
  const size_t words = g.words_per_column();
  // No zeroing pass here: step 2 writes every word of every band (a reused grid keeps its memory).
  resize_huge(g.bits, g.word_count());

  // The covering triangles are the fan triangles (v0, v_k, v_k+1) of each face in its leaf's own
  // orientation, numbered face by face (those a Bvh is built over; degenerate ones have n_z = 0
  // and cross no column). They are read straight from the faces, not materialized (a copy, a
  // serial compaction and fresh pages for a few MB at 512³). Faces are taken
  // in list order (face_of(p): the p-th face of face_list, or face p); a triangle's position in
  // that order does not change the grid (a column's crossings are sorted by their keys).
  const size_t faces = face_list ? face_list->size() : solid.face_count();
  auto face_of = [face_list](size_t p) { return face_list ? (*face_list)[p] : p; };
  std::vector<uint32_t> first_tri(faces + 1, 0);
  for (size_t p = 0; p < faces; ++p) {
    const size_t k = solid.face(face_of(p)).size();
    first_tri[p + 1] = first_tri[p] + static_cast<uint32_t>(k >= 3 ? k - 2 : 0);
  }
  // Rows (x index i) are processed in bands of `band_rows`; a band's crossings are found,
  // grouped by column and swept by one task in cache-sized scratch, and its columns (contiguous
  // in the grid) written once, so no pass sorts all crossings over all N² columns (cache misses
  // throughout, and it does not scale with threads).
  const int band_rows = std::max(1, nx / 64);
  const size_t bands = (static_cast<size_t>(nx) + band_rows - 1) / band_rows;

  // 1. Each covering triangle's n_z and exact row and column ranges (centre_range), and the
  //    triangles of each band: counted per (chunk of faces, band), then listed in (band, chunk,
  //    triangle) order. A listed triangle carries its vertex indices, leaf and ranges: reaching
  //    them through the faces from the band pass (face_start, face_vertices, face_sign,
  //    face_leaf: scattered loads) would cost cache misses.
  std::vector<BandTriangle> tris(first_tri[faces]);
  constexpr size_t kChunk = 4096;  // faces
  const size_t chunks = (faces + kChunk - 1) / kChunk;
  std::vector<uint32_t> per_chunk(chunks * bands, 0);  // [chunk][band] counts, then offsets
  parallel_for(faces, kChunk, [&](size_t begin, size_t end) {
    uint32_t* count = per_chunk.data() + begin / kChunk * bands;
    for (size_t p = begin; p < end; ++p) {
      if (p + kAhead < end) prefetch_face_vertices(solid, face_of(p + kAhead));
      const size_t f = face_of(p);
      const auto face = solid.face(f);
      const bool rev = solid.face_sign[f] < 0;  // back to the leaf's own orientation
      auto index = [&](size_t k) { return face[rev ? face.size() - 1 - k : k]; };
      for (uint32_t t = first_tri[p]; t < first_tri[p + 1]; ++t) {
        const size_t k = t - first_tri[p] + 1;
        BandTriangle& tri = tris[t];
        tri = {{index(0), index(k), index(k + 1)}, solid.face_leaf[f], 1, 0, 1, 0, 0, false};
        const Vec3 &a = solid.vertices[tri.v[0]], &b = solid.vertices[tri.v[1]],
                   &c = solid.vertices[tri.v[2]];
        tri.moderate = moderate_vertices || (moderate(a) && moderate(b) && moderate(c));
        const int nz = orient2d(a, b, c, 2);
        if (nz == 0) continue;  // parallel to z (or degenerate): no perturbed column line crosses
        const auto [i0, i1] =
            centre_range(xs, inv_hx, std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}));
        const auto [j0, j1] =
            centre_range(ys, inv_hy, std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}));
        if (i0 > i1 || j0 > j1) continue;
        tri.i0 = static_cast<uint16_t>(i0);
        tri.i1 = static_cast<uint16_t>(i1);
        tri.j0 = static_cast<uint16_t>(j0);
        tri.j1 = static_cast<uint16_t>(j1);
        tri.nz = static_cast<int8_t>(nz);
        for (int band = i0 / band_rows; band <= i1 / band_rows; ++band) ++count[band];
      }
    }
  });
  std::vector<uint32_t> band_start(bands + 1, 0);
  for (size_t band = 0, total = 0; band < bands; ++band) {
    band_start[band] = static_cast<uint32_t>(total);
    for (size_t chunk = 0; chunk < chunks; ++chunk) {
      const uint32_t count = per_chunk[chunk * bands + band];
      per_chunk[chunk * bands + band] = static_cast<uint32_t>(total);
      total += count;
    }
    band_start[band + 1] = static_cast<uint32_t>(total);
  }
  std::vector<BandTriangle> listed(band_start[bands]);
  parallel_for(faces, kChunk, [&](size_t begin, size_t end) {
    uint32_t* next = per_chunk.data() + begin / kChunk * bands;
    for (uint32_t t = first_tri[begin]; t < first_tri[end]; ++t)
      if (tris[t].nz != 0)
        for (int band = tris[t].i0 / band_rows; band <= tris[t].i1 / band_rows; ++band)
          listed[next[band]++] = tris[t];
  });

  // 2. Per band: crossings, grouped by column (counting sort), each column sorted by its packed
  //    (below, leaf, sign) keys and swept upwards with per-leaf windings; every word of the
  //    band's columns is written (zeros included), runs where the result is inside set. The
  //    grid depends neither on the threads nor on the order in which bands are processed.
  const size_t leaves = solid.leaves.size();
  std::vector<uint8_t> none(leaves, 0);
  const bool outside_value = solid.tree.evaluate(none);  // membership with every winding 0
  // Up to kTableLeaves leaves, the tree's value for every set of inside leaves, tabulated once:
  // the sweep then looks runs up instead of evaluating the tree once per run.
  constexpr size_t kTableLeaves = 10;
  const bool use_table = leaves <= kTableLeaves;
  const std::vector<uint8_t> table =
      use_table ? solid.tree.truth_table(leaves) : std::vector<uint8_t>{};
  auto sweep_band = [&](size_t band) {
    // Per-thread scratch, reused across bands and calls (no allocation per band).
    thread_local std::vector<Crossing> found;
    thread_local std::vector<uint32_t> start;
    thread_local std::vector<uint64_t> keys;
    thread_local std::vector<int> winding;
    thread_local std::vector<uint8_t> inside;
    const int row0 = static_cast<int>(band) * band_rows;
    const int row1 = std::min(nx, row0 + band_rows) - 1;
    found.clear();
    for (uint32_t i = band_start[band]; i < band_start[band + 1]; ++i) {
      if (i + kAhead < band_start[band + 1])
        for (const uint32_t v : listed[i + kAhead].v) __builtin_prefetch(&solid.vertices[v]);
      const BandTriangle& t = listed[i];
      const Vec3 &a = solid.vertices[t.v[0]], &b = solid.vertices[t.v[1]],
                 &c = solid.vertices[t.v[2]];
      const int i0 = std::max<int>(t.i0, row0), i1 = std::min<int>(t.i1, row1);
      if (t.moderate && moderate_centres)
        crossings_of<true>(a, b, c, t.leaf, t.nz, i0, i1, t.j0, t.j1, row0, xs, ys, zs, found);
      else
        crossings_of<false>(a, b, c, t.leaf, t.nz, i0, i1, t.j0, t.j1, row0, xs, ys, zs, found);
    }
    const size_t band_columns = static_cast<size_t>(row1 - row0 + 1) * ny;
    start.assign(band_columns + 1, 0);
    for (const Crossing& c : found) ++start[c.column + 1];
    for (size_t col = 0; col < band_columns; ++col) start[col + 1] += start[col];
    keys.resize(found.size());
    for (const Crossing& c : found) keys[start[c.column]++] = crossing_key(c);
    // start[col] is now the end of column col; its first slot is start[col − 1] (0 for col 0).
    winding.assign(leaves, 0);
    inside.assign(leaves, 0);
    // The band's words, zeroed with one memset, then the inside runs set column by column.
    uint64_t* band_bits = g.bits.data() + static_cast<size_t>(row0) * ny * words;
    std::memset(band_bits, 0, band_columns * words * sizeof(uint64_t));
    for (size_t col = 0; col < band_columns; ++col) {
      uint64_t* column = band_bits + col * words;
      uint64_t* first = keys.data() + (col == 0 ? 0 : start[col - 1]);
      uint64_t* last = keys.data() + start[col];
      if (first == last) {
        if (outside_value) fill(column, 0, nk);
        continue;
      }
      if (last - first == 2) {  // the common case: one entry and one exit
        if (first[1] < first[0]) std::swap(first[0], first[1]);
        if (use_table) {
          // Centres below both crossings see both windings, those between only the upper one,
          // those above neither (the sweep below, unrolled: ~6% of the call at 512³).
          const uint32_t l0 = key_leaf(first[0]), l1 = key_leaf(first[1]);
          const int b0 = key_below(first[0]), b1 = key_below(first[1]);
          const bool cancel = l0 == l1 && key_sign(first[0]) + key_sign(first[1]) == 0;
          const uint32_t both = cancel ? 0 : (uint32_t{1} << l0) | (uint32_t{1} << l1);
          if (table[both]) fill(column, 0, b0);
          if (table[uint32_t{1} << l1]) fill(column, b0, b1);
          if (outside_value) fill(column, b1, nk);
          continue;
        }
      } else {
        std::sort(first, last);
      }
      // Winding of centre k = Σ sign over crossings with below > k; `mask` has bit l set iff
      // leaf l's winding is nonzero (used with the table).
      uint32_t mask = 0;
      auto update = [&](uint64_t key, int sign) {
        const uint32_t l = key_leaf(key);
        winding[l] += sign;
        if (use_table) mask = (mask & ~(uint32_t{1} << l)) | uint32_t{winding[l] != 0} << l;
      };
      for (const uint64_t* c = first; c != last; ++c) update(*c, key_sign(*c));
      int k = 0;
      const uint64_t* c = first;
      for (;;) {
        while (c != last && key_below(*c) <= k) {
          update(*c, -key_sign(*c));
          ++c;
        }
        const int run_end = c == last ? nk : key_below(*c);
        bool member;
        if (use_table) {
          member = table[mask];
        } else {
          for (size_t l = 0; l < leaves; ++l) inside[l] = winding[l] != 0;
          member = solid.tree.evaluate(inside);
        }
        if (member) fill(column, k, run_end);
        if (c == last || run_end >= nk) break;
        k = run_end;
      }
      for (; c != last; ++c) winding[key_leaf(*c)] -= key_sign(*c);  // back to all zeros
    }
  };
  // One parallel loop over all bands (dynamic load balancing, no barrier for the progress
  // callback). Progress is reported from the calling thread, which takes part in the loop, after
  // each band it finishes.
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<size_t> bands_done{0};
  parallel_for(bands, 1, [&](size_t begin, size_t end) {
    for (size_t band = begin; band < end; ++band) sweep_band(band);
    const size_t done = bands_done.fetch_add(end - begin) + (end - begin);
    if (progress && std::this_thread::get_id() == caller && done < bands)
      progress(static_cast<double>(done) / bands);
  });
  if (progress) progress(1.0);
}

}  // namespace cover
