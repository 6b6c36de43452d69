#pragma once
// A closed mesh cut into the cells of a cubic grid by the plane patcher ([Erleben2006],
// the octree-cell application of its §1), and the pieces glued back.
//
// Notation
//   grid      the cube [min, min + size]³ split into n×n×n cells; wall k of axis a is the plane
//             x_a = c_k with c_k = min_a + k·(size/n) for 0 < k < n, c_0 = min_a,
//             c_n = min_a + size.
//   cell      (i, j, k) = [c_i, c_i+1] × [c_j, c_j+1] × [c_k, c_k+1].
//   piece     mesh ∩ cell, closed by caps on the cell's walls (brep::clip): a closed, outward,
//             2-manifold mesh; a cell the mesh misses has no piece, a cell wholly inside it is
//             its box.
//   interior wall   c_k with 0 < k < n; caps there are the ones glue removes.
//
// Cutting is hierarchical: the mesh is split by the x walls (bisecting the wall list, so the two
// halves of each level run in parallel), each slab by the y walls, each column by the z walls.
// A clip rounds each constructed point once to the nearest double and hands the same point to
// both halves, and later cuts split a shared wall edge identically on both sides, so the border
// edges that the interior caps leave behind match exactly across a wall: gluing pairs them by
// their coordinates and identifies their end vertices (no tolerance).
//
// Rounding repair: a wall within rounding distance of a vertex makes the fan of edges at that
// vertex cross the wall at exact points that round to one double point (or to points an ulp
// apart across each other), and a cap ring of such points may admit no triangulation valid on
// both the exact and the rounded points (ClipResult::forced_ears). The written piece would touch
// itself there. After gluing (which uses the pieces as cut), each piece is checked exactly for
// faces that meet, among the faces with a vertex on one of its walls (every constructed vertex
// lies on a wall), and such contacts are removed by collapsing rounding-scale edges
// (mesh/rounding_repair.h). A repaired piece may then differ from its neighbour by that
// collapsed edge on their common wall.

#include <array>
#include <cstdint>
#include <vector>

#include "cover/brep/clip.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/polygon_mesh.h"

namespace cover::brep {

/// The cube and its cells per axis.
struct CellGrid {
  Vec3 min;         ///< lower corner of the cube
  double size = 1;  ///< edge length of the cube (finite, > 0)
  int n = 1;        ///< cells per axis (≥ 1)
};

/// Coordinate c_k of wall k (0 ≤ k ≤ n) along any axis a of `grid` (see the notation above).
double cell_wall(const CellGrid& grid, int axis, int k);

struct CellsOptions {
  bool glue = true;  ///< also build CellsResult::glued
  ClipOptions clip;  ///< cap faces: convex polygons (default) or triangles
  /// Refuse (InputError, check_memory's message) when cells_memory_bytes(n, faces of the mesh)
  /// exceeds this many bytes (the CLI's --max-memory; default 4096 MiB); 0: no limit.
  uint64_t max_memory_bytes = kDefaultMaxMemoryBytes;
};

/// An upper bound on the peak bytes of cutting a mesh of `mesh_faces` faces into n×n×n cells
/// and writing the pieces (cut_cells, its result, the glued mesh and the pieces' index, as
/// `cover evaluate --cells` holds them): 3 KiB per cell (a full cell's box piece with its
/// allocations, its part of the glued mesh and of the index, measured at about 1.9 KiB) plus
/// 1 KiB per face of the mesh (its copies in the first clips and its fragments in the pieces,
/// measured at about 0.5 KiB). With mesh_faces = 0 it is the cells' part alone, what a caller
/// can check before evaluating. A double, so that n³ cannot wrap.
double cells_memory_bytes(int n, double mesh_faces = 0);

/// Face kinds of a piece.
enum class CellFace : uint8_t {
  kSurface = 0,   ///< part of a face of the input mesh
  kInterior = 1,  ///< cap on an interior wall (removed by gluing)
  kOuter = 2,     ///< cap on the cube's own boundary (where the mesh leaves the cube)
};

struct CellPiece {
  std::array<int, 3> cell{0, 0, 0};  ///< (i, j, k)
  PolygonMesh mesh;                  ///< closed, outward, 2-manifold
  std::vector<CellFace> faces;       ///< #F kind of each face of `mesh`
  int64_t cap_faces = 0;             ///< faces that are caps (interior or outer)
  double volume = 0;                 ///< signed_volume(mesh)
  double area = 0;                   ///< surface_area(mesh)
  double cap_area = 0;               ///< area of the cap faces
  /// Ear-clipping fallbacks (ClipResult::forced_ears) in the clips that made this piece: 0
  /// unless a cap ring's exact and rounded points admit no common triangulation.
  int64_t forced_ears = 0;
  /// Rounding-scale edges collapsed by the rounding repair (module comment): 0 unless rounding
  /// made the piece touch itself.
  int64_t collapsed_edges = 0;
  /// Face pairs still meeting after the repair (0 unless the repair found no allowed collapse).
  int64_t rounding_contacts = 0;
};

struct CellsResult {
  std::vector<CellPiece> pieces;  ///< the non-empty pieces in (i, j, k) order (i slowest)
  PolygonMesh glued;              ///< the pieces without interior caps, wall vertices identified
  int64_t cap_faces = 0;          ///< Σ pieces' cap_faces
  int64_t clips = 0;              ///< plane clips run (walls a piece does not cross are skipped)
  int64_t forced_ears = 0;        ///< Σ ClipResult::forced_ears over all clips
  int64_t collapsed_edges = 0;    ///< Σ pieces' collapsed_edges
  int64_t rounding_contacts = 0;  ///< Σ pieces' rounding_contacts (0: every piece valid)
  double cut_seconds = 0;         ///< wall-clock time of the cuts
  double glue_seconds = 0;        ///< wall-clock time of the gluing
  double repair_seconds = 0;      ///< wall-clock time of the rounding repair of the pieces
};

/// Cuts `mesh` into the cells of `grid`. `mesh` is what brep::clip accepts: closed, outward,
/// 2-manifold, without self-intersections. The glued mesh is mesh ∩ cube (the same solid as
/// `mesh` when the cube contains it), with extra vertices where the walls cross its faces.
/// Deterministic: the same pieces for any thread count.
/// Every piece and the glued mesh are checked as written (closed, consistently oriented
/// 2-manifold, no face with all its vertices on one line, no self-intersection by CGAL's exact
/// test, left out when `mesh` has distinct vertices at one point, exact volume > 0).
/// \throws InputError for n < 1, a non-finite min or a size that is not finite and > 0, a
/// cells_memory_bytes estimate over options.max_memory_bytes, and as brep::clip; NotComputable
/// as brep::clip, and when a piece or the glued mesh is not valid as written in doubles (a wall
/// within rounding distance of the surface; the message names the cell); InternalError if a
/// wall edge finds no partner.
CellsResult cut_cells(const PolygonMesh& mesh, const CellGrid& grid,
                      const CellsOptions& options = {});

}  // namespace cover::brep
