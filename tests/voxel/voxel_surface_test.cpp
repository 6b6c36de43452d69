// Voxel boundary surface (voxel/voxel_surface.h). Every mesh is checked by validate_mesh (closed,
// manifold without pinched vertices, oriented, outward) and against quantities computed here
// independently of the mesh: volume = count·h³, area = faces·h², face count = boundary voxel
// faces, components = occupied 6-components + empty 18-components − 1 (the components of the
// occupied and empty space, adjacent through the surface, form a tree), and the Euler
// characteristic χ = 2·χ(occupied) of the (6, 18) voxel object: voxels − face-adjacent pairs +
// full 2×2 squares − full 2×2×2 cubes (χ of the 6-connected set, as for (6, 26)) + one per 2×2×2
// block missing only two opposite octants (the hexagon of 6 voxels around the block's centre
// bounds a disk, as the two empty octants are not 18-adjacent).
// The per-fan vertex copies of voxel_surface.h separate voxels touching at a corner on both
// sides, occupied and empty, and empty voxels touching along an edge stay joined: empty space is
// 18-connected, not 26-connected.

#include "cover/voxel/voxel_surface.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "cover/solid/measure.h"
#include "cover/voxel/voxel_grid.h"
#include "helpers.h"
#include "voxel_grids.h"

namespace cover {
namespace {

using test::empty_grid;
using test::random_grid;
using test::sphere_grid;

VoxelGrid grid_of(int n, const std::vector<std::array<int, 3>>& voxels) {
  VoxelGrid grid = empty_grid(n);
  for (const auto& v : voxels) grid.set(v[0], v[1], v[2]);
  return grid;
}

bool occupied(const VoxelGrid& g, int i, int j, int k) {
  return i >= 0 && j >= 0 && k >= 0 && i < g.nx() && j < g.nx() && k < g.nx() && g.get(i, j, k);
}

/// Connected components of the occupied voxels (6-neighbours) or of the empty ones, including
/// the outside, (18-neighbours), by flood fill over the grid padded by one voxel.
int64_t count_components(const VoxelGrid& g, bool of_occupied) {
  const int m = g.nx() + 2;
  auto index = [&](int i, int j, int k) { return (static_cast<size_t>(i) * m + j) * m + k; };
  std::vector<uint8_t> seen(static_cast<size_t>(m) * m * m, 0);
  int64_t components = 0;
  std::vector<std::array<int, 3>> stack;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        if (seen[index(i, j, k)] || occupied(g, i - 1, j - 1, k - 1) != of_occupied) continue;
        ++components;
        seen[index(i, j, k)] = 1;
        stack.assign(1, {i, j, k});
        while (!stack.empty()) {
          const auto [a, b, c] = stack.back();
          stack.pop_back();
          for (int da = -1; da <= 1; ++da)
            for (int db = -1; db <= 1; ++db)
              for (int dc = -1; dc <= 1; ++dc) {
                const int steps = std::abs(da) + std::abs(db) + std::abs(dc);
                if (steps == 0 || steps > (of_occupied ? 1 : 2)) continue;
                const int x = a + da, y = b + db, z = c + dc;
                if (x < 0 || y < 0 || z < 0 || x >= m || y >= m || z >= m) continue;
                if (seen[index(x, y, z)] || occupied(g, x - 1, y - 1, z - 1) != of_occupied)
                  continue;
                seen[index(x, y, z)] = 1;
                stack.push_back({x, y, z});
              }
        }
      }
  return components;
}

/// χ of the occupied voxels as a (6, 18) object (see the top of the file).
int64_t euler_6_18(const VoxelGrid& g) {
  int64_t chi = 0;
  // Each cell: its lowest voxel (i, j, k) and the axes it spans; all its voxels occupied.
  for (int i = 0; i < g.nx(); ++i)
    for (int j = 0; j < g.nx(); ++j)
      for (int k = 0; k < g.nx(); ++k)
        for (int axes = 0; axes < 8; ++axes) {
          bool full = true;
          for (int o = 0; o < 8 && full; ++o)
            if ((o & ~axes) == 0)
              full = occupied(g, i + (o & 1), j + ((o >> 1) & 1), k + ((o >> 2) & 1));
          if (full) chi += std::popcount(static_cast<unsigned>(axes)) % 2 == 0 ? 1 : -1;
        }
  for (int i = -1; i < g.nx(); ++i)
    for (int j = -1; j < g.nx(); ++j)
      for (int k = -1; k < g.nx(); ++k)
        for (int o = 0; o < 4; ++o) {  // the 4 opposite pairs o, 7 − o
          bool hexagon = !occupied(g, i + (o & 1), j + ((o >> 1) & 1), k) &&
                         !occupied(g, i + 1 - (o & 1), j + 1 - ((o >> 1) & 1), k + 1);
          for (int p = 0; p < 8 && hexagon; ++p)
            if (p != o && p != 7 - o)
              hexagon = occupied(g, i + (p & 1), j + ((p >> 1) & 1), k + ((p >> 2) & 1));
          chi += hexagon;
        }
  return chi;
}

int64_t boundary_faces(const VoxelGrid& g) {
  int64_t faces = 0;
  for (int i = -1; i < g.nx(); ++i)
    for (int j = -1; j < g.nx(); ++j)
      for (int k = -1; k < g.nx(); ++k) {
        const bool v = occupied(g, i, j, k);
        faces += v != occupied(g, i + 1, j, k);
        faces += v != occupied(g, i, j + 1, k);
        faces += v != occupied(g, i, j, k + 1);
      }
  return faces;
}

struct Checked {
  PolygonMesh mesh;
  MeshReport report;
  int64_t midpoints = 0;  ///< face corners beyond 4 per face
};

/// Builds the surface and checks every invariant; `what` names the case in failures.
Checked check(const VoxelGrid& g, const std::string& what) {
  Checked c;
  c.mesh = voxel_surface(g);
  ValidateOptions options;
  options.check_self_intersection = false;  // copies coincide: contacts by construction
  c.report = validate_mesh(c.mesh, options);
  const MeshReport& r = c.report;
  const uint64_t count = g.count();
  const double h = g.voxel_size();
  EXPECT_TRUE(r.closed) << what;
  EXPECT_TRUE(r.manifold) << what;
  EXPECT_TRUE(r.oriented) << what;
  EXPECT_EQ(r.boundary_edges, 0) << what;
  EXPECT_EQ(r.nonmanifold_edges, 0) << what;
  EXPECT_EQ(r.degenerate_faces, 0) << what;
  EXPECT_EQ(r.outward, count > 0) << what;
  const double volume = static_cast<double>(count) * h * h * h;
  EXPECT_NEAR(signed_volume(c.mesh), volume, 1e-12 * volume) << what;
  const int64_t faces = boundary_faces(g);
  EXPECT_EQ(static_cast<int64_t>(c.mesh.face_count()), faces) << what;
  const double area = static_cast<double>(faces) * h * h;
  EXPECT_NEAR(surface_area(c.mesh), area, 1e-12 * area) << what;
  c.midpoints = static_cast<int64_t>(c.mesh.face_vertices.size()) - 4 * faces;
  EXPECT_EQ(c.midpoints % 2, 0) << what;
  if (count == 0) {
    EXPECT_EQ(c.mesh.face_count(), 0u) << what;
    return c;
  }
  EXPECT_EQ(r.components, count_components(g, true) + count_components(g, false) - 1) << what;
  // χ(surface) = 2·components − 2·genus = 2·χ₆.
  EXPECT_EQ(r.components - r.genus, euler_6_18(g)) << what;
  return c;
}

TEST(VoxelSurface, SingleVoxel) {
  for (int n : {1, 3}) {
    const int c = n / 2;
    const Checked s = check(grid_of(n, {{c, c, c}}), "single " + std::to_string(n));
    EXPECT_EQ(s.mesh.face_count(), 6u);
    EXPECT_EQ(s.mesh.vertices.size(), 8u);
    EXPECT_EQ(s.report.components, 1);
    EXPECT_EQ(s.report.genus, 0);
    // Corner coordinates: min + (i, j, k)·h.
    const double h = 2.5 / n;
    const Vec3 lo{-1.25 + c * h, 0.5 + c * h, 3.0 + c * h};
    EXPECT_EQ(s.mesh.vertices.front().x, lo.x);
    EXPECT_EQ(s.mesh.vertices.front().y, lo.y);
    EXPECT_EQ(s.mesh.vertices.front().z, lo.z);
  }
}

TEST(VoxelSurface, EmptyAndFullGrids) {
  const Checked empty = check(empty_grid(5), "empty");
  EXPECT_TRUE(empty.mesh.vertices.empty());
  VoxelGrid full = empty_grid(7);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      for (int k = 0; k < 7; ++k) full.set(i, j, k);
  const Checked s = check(full, "full");
  EXPECT_EQ(s.mesh.face_count(), 6u * 49);
  EXPECT_EQ(s.report.genus, 0);
  EXPECT_EQ(voxel_surface(VoxelGrid{}).face_count(), 0u);
}

TEST(VoxelSurface, VoxelsSharingOnlyAnEdgeOrACorner) {
  for (int axis = 0; axis < 3; ++axis) {
    std::array<int, 3> b = {1, 1, 1};
    b[axis] = 0;  // touches (0, 0, 0) along the edge parallel to `axis`
    const Checked s = check(grid_of(2, {{0, 0, 0}, b}), "edge " + std::to_string(axis));
    EXPECT_EQ(s.report.components, 2);
    EXPECT_EQ(s.report.genus, 0);
    EXPECT_EQ(s.mesh.vertices.size(), 16u);  // the shared edge's 2 corners are duplicated
  }
  const Checked s = check(grid_of(2, {{0, 0, 0}, {1, 1, 1}}), "corner");
  EXPECT_EQ(s.report.components, 2);
  EXPECT_EQ(s.report.genus, 0);
  EXPECT_EQ(s.mesh.vertices.size(), 16u);
  // Checkerboard 2×2×2: four voxels touching pairwise along edges only.
  const Checked board = check(grid_of(2, {{0, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}}), "board");
  EXPECT_EQ(board.report.components, 4);
  EXPECT_EQ(board.mesh.vertices.size(), 32u);
}

TEST(VoxelSurface, SixOctantRingAroundACorner) {
  // All of a 2×2×2 block but two opposite octants, which touch only at the centre corner. The
  // corner gets one vertex copy per notch (2 fans), so the two empty octants do not meet there:
  // the ring's hole is closed at the corner and the surface is a sphere, not a torus (with one
  // shared copy the vertex would be pinched: a torus whose hole shrinks to a point).
  std::vector<std::array<int, 3>> ring;
  for (int o = 1; o < 7; ++o) ring.push_back({1 + (o & 1), 1 + ((o >> 1) & 1), 1 + (o >> 2)});
  const Checked s = check(grid_of(4, ring), "ring");
  EXPECT_EQ(s.report.components, 1);
  EXPECT_EQ(s.report.genus, 0);
  EXPECT_EQ(s.mesh.vertices.size(), 26u);  // 27 corners − 2 outer ones unused + 1 copy
  // Its complement inside a 4×4×4 block: a ring-shaped cavity whose two occupied octants touch
  // only at the corner (split too): the cavity's surface is a sphere.
  VoxelGrid block = empty_grid(4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) block.set(i, j, k);
  for (const auto& v : ring) block.bits[block.column_word(v[0], v[1])] &= ~(uint64_t{1} << v[2]);
  const Checked c = check(block, "ring complement");
  EXPECT_EQ(c.report.components, 2);
  EXPECT_EQ(c.report.genus, 0);
}

TEST(VoxelSurface, CavityBlock) {
  VoxelGrid g = empty_grid(5);
  for (int i = 1; i < 4; ++i)
    for (int j = 1; j < 4; ++j)
      for (int k = 1; k < 4; ++k)
        if (i != 2 || j != 2 || k != 2) g.set(i, j, k);
  const Checked s = check(g, "cavity");
  EXPECT_EQ(s.report.components, 2);
  EXPECT_EQ(s.report.genus, 0);
  EXPECT_GT(s.report.volume, 0);
}

TEST(VoxelSurface, Torus) {
  // A square annulus, 3×3 minus its centre, one voxel thick.
  std::vector<std::array<int, 3>> torus;
  for (int i = 1; i < 4; ++i)
    for (int j = 1; j < 4; ++j)
      if (i != 2 || j != 2) torus.push_back({i, j, 2});
  const Checked s = check(grid_of(5, torus), "torus");
  EXPECT_EQ(s.report.components, 1);
  EXPECT_EQ(s.report.genus, 1);
  // A ring whose corners touch only along edges is no torus: four separate bars.
  const Checked d = check(grid_of(5, {{2, 1, 2}, {1, 2, 2}, {3, 2, 2}, {2, 3, 2}}), "diamond");
  EXPECT_EQ(d.report.components, 4);
  EXPECT_EQ(d.report.genus, 0);
}

TEST(VoxelSurface, TunnelThroughAnEdge) {
  // Two bars along x joined at both ends, so that the middle edge (x from 1 to 2 at y = z = 1)
  // has 4 boundary faces and its two occupied voxels are connected around both of its ends: the
  // tunnel passes through the edge. Vertex copies cannot separate the two sheets there, so the
  // faces of voxel (1, 0, 0) take the edge midpoint.
  std::vector<std::array<int, 3>> voxels;
  for (int i = 0; i < 3; ++i) {
    voxels.push_back({i, 0, 0});
    voxels.push_back({i, 1, 1});
  }
  voxels.push_back({0, 0, 1});
  voxels.push_back({2, 0, 1});
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::array<int, 3>> rotated;
    for (const auto& v : voxels) rotated.push_back({v[axis], v[(axis + 1) % 3], v[(axis + 2) % 3]});
    const Checked s = check(grid_of(3, rotated), "tunnel " + std::to_string(axis));
    EXPECT_EQ(s.report.components, 1);
    EXPECT_EQ(s.report.genus, 1);
    EXPECT_EQ(s.midpoints, 2);
  }
}

TEST(VoxelSurface, RandomGrids) {
  int64_t midpoints = 0;
  for (int n = 2; n <= 12; ++n)
    for (double density : {0.1, 0.3, 0.5, 0.7, 0.9})
      for (uint64_t seed = 0; seed < 6; ++seed) {
        const VoxelGrid g = random_grid(n, density, seed * 1000 + n);
        midpoints += check(g, "n " + std::to_string(n) + " density " + std::to_string(density) +
                                  " seed " + std::to_string(seed))
                         .midpoints;
      }
  EXPECT_GT(midpoints, 0);  // the tunnel-through-an-edge case occurs in random grids
}

TEST(VoxelSurface, RandomGridsAcrossWordBoundaries) {
  for (int n : {62, 63, 64, 65})
    for (double density : {0.2, 0.8}) {
      const VoxelGrid g = random_grid(n, density, static_cast<uint64_t>(n));
      const Checked s = check(g, "n " + std::to_string(n) + " density " + std::to_string(density));
      // Padding bits above k = N − 1 are ignored.
      VoxelGrid padded = g;
      if (n % 64 != 0)
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            padded.bits[padded.column_word(i, j) + padded.words_per_column() - 1] |= ~uint64_t{0}
                                                                                     << (n % 64);
      EXPECT_EQ(voxel_surface(padded).face_vertices, s.mesh.face_vertices) << n;
    }
}

TEST(VoxelSurface, SphereAndDeterminism) {
  const VoxelGrid g = sphere_grid(64);
  const Checked s = check(g, "sphere");
  EXPECT_EQ(s.report.components, 1);
  EXPECT_EQ(s.report.genus, 0);
  EXPECT_EQ(s.midpoints, 0);  // a convex shape has no tunnel through an edge
  const PolygonMesh again = voxel_surface(g);
  EXPECT_EQ(again.face_vertices, s.mesh.face_vertices);
  EXPECT_EQ(again.vertices.size(), s.mesh.vertices.size());
}

TEST(VoxelSurface, OffRoundTrip) {
  const auto dir = test::temp_dir("voxel-surface");
  for (uint64_t seed = 0; seed < 3; ++seed) {
    const Checked s = check(random_grid(9, 0.5, seed), "round trip");
    write_mesh(dir / "s.off", s.mesh);
    const PolygonMesh back = read_mesh(dir / "s.off");
    ASSERT_EQ(back.vertices.size(), s.mesh.vertices.size());
    for (size_t v = 0; v < back.vertices.size(); ++v) {
      EXPECT_EQ(back.vertices[v].x, s.mesh.vertices[v].x);
      EXPECT_EQ(back.vertices[v].y, s.mesh.vertices[v].y);
      EXPECT_EQ(back.vertices[v].z, s.mesh.vertices[v].z);
    }
    EXPECT_EQ(back.face_start, s.mesh.face_start);
    EXPECT_EQ(back.face_vertices, s.mesh.face_vertices);
    ValidateOptions options;
    options.check_self_intersection = false;
    const MeshReport r = validate_mesh(back, options);
    EXPECT_TRUE(r.closed && r.manifold && r.oriented && r.outward);
    EXPECT_EQ(r.genus, s.report.genus);
    EXPECT_EQ(r.components, s.report.components);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
