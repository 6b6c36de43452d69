#pragma once
// Certified polygonization of any solid (docs/design.md "Polygonization"): the boundary of the
// result as a closed, outward 2-manifold triangle mesh, for trees Cover cannot evaluate exactly
// (field, warp and open-mesh leaves), by marching tetrahedra on an adaptive grid.
//
// Route
//   1. Grid: step h, a power of two, the largest with at least `resolution` cells along the
//      box's largest extent (or at most `cell_size`); grid points are integer multiples of h, so
//      every point below is a double exactly (no rounding anywhere in the construction). The
//      grid spans the box with one cell of margin per side.
//   2. Cells: an octree descent keeps the cells whose closed box the three-valued box test
//      (covering/box_states.h: interval enclosures for fields and warps, exact triangle tests
//      for meshes; an open leaf is always undecided) cannot decide, down to cells of side h.
//   3. Signs: every corner of those cells is classified (covering/classify.h, exact or
//      certified); a point on the boundary counts as inside (the symbolic tie-break), and points
//      on the grid's outer border count as outside, so the result is the solid ∩ the grid box.
//   4. Each cell is cut into the 6 tetrahedra of its Kuhn triangulation (around the diagonal
//      (0,0,0)–(1,1,1), the same in every cell, so faces match); each tetrahedron whose corners
//      differ gives one triangle (1|3) or two (2|2, split along the diagonal between its
//      opposite edges), oriented by the exact orient3d against an inside corner.
//   5. Crossings: on every grid edge whose ends differ, a certified bisection by classify()
//      keeps an inside (or boundary) end and an outside end; the vertex is the final interval's
//      midpoint, or the midpoint that classify() finds on the boundary. The segment between an
//      inside and an outside point meets the boundary, so every vertex is within half its final
//      interval of the surface: `tolerance` bounds them all.
// Guarantees: the mesh is closed, oriented and 2-manifold, and free of self-intersections
// exactly (every vertex lies exactly inside its grid edge, so each tetrahedron's triangles stay
// inside it and meet their neighbours' only along the shared faces' crossing segments);
// deterministic, the same for any thread count. Not promised: features thinner than the grid
// (a component or a tunnel between grid points may be missed or joined); the mesh is within
// `tolerance` of the surface at its vertices, not everywhere between them.

#include <cstddef>
#include <cstdint>

#include "cover/covering/prepared.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/polygon_mesh.h"

namespace cover {

struct PolygonizeOptions {
  /// Cells along the box's largest extent, at least (the step is the largest power of two that
  /// gives this many): 2 to 65536.
  int resolution = 128;
  /// When > 0, the step instead: the largest power of two ≤ cell_size.
  double cell_size = 0;
  /// The largest distance from the surface asked of every vertex; 0: h/1024. Bisection steps
  /// stop at the first count that meets it (at most 60).
  double tolerance = 0;
  uint64_t max_memory_bytes = kDefaultMaxMemoryBytes;  ///< refused beyond (estimated per level)
};

struct PolygonizeResult {
  PolygonMesh mesh;        ///< triangles, outward; empty when the grid finds no inside point
  double cell_size = 0;    ///< h
  double tolerance = 0;    ///< certified: every vertex is at most this far from the boundary
  size_t cells = 0;        ///< cells of side h the box test could not decide
  size_t grid_points = 0;  ///< corners classified
  size_t bisections = 0;   ///< classify() calls of the bisections
  size_t uncertain = 0;    ///< points whose class classify() could not certify (circle
                           ///< skeletons); a vertex built from one is not certified
  size_t clipped = 0;      ///< grid-border points that were inside (the box cut the solid)
};

/// Polygonizes the result within `box` (usually its bounds, covering/bounds.h). \throws
/// InputError for a bad resolution, cell size or tolerance, a grid beyond 2^30 cells per side,
/// and (check_memory) a descent over options.max_memory_bytes.
PolygonizeResult polygonize(const Prepared& prepared, const Bbox& box,
                            const PolygonizeOptions& options = {});

}  // namespace cover
