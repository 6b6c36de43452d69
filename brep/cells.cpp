// Cells of a cubic grid by repeated plane clip and patch, and the gluing of the pieces
// (brep/cells.h has the notation).
//
// Cutting: the mesh is first clipped by the cube's six faces, then by the interior walls. The
// outer caps must exist before any interior wall is cut: a clip decomposes the cap of each half
// on its own, so the two halves of an interior wall carry different cap diagonals, and an outer
// wall cut later would cross them at different points on the two sides (its kept outer caps
// would then have border edges without partners). Interior walls cross an outer cap face once,
// at points shared by both halves.
// A part is clipped only by the walls it crosses (a part whose box lies on one side of
// a wall goes there whole, unclipped: the clip would put it there too, since a face lying in the
// wall goes to the half it bounds from outside). Each clip reports the input face of every output
// face (ClipHalf::face_source), so the kind of a face (surface, interior cap, outer cap) follows
// it through all later clips.
//
// Gluing: in each piece the faces other than interior caps leave border half-edges (a→b whose
// twin b→a is an interior cap's). Across a wall the two pieces hold the same wall edge in
// opposite directions with bit-identical end points (module comment of cells.h), so each border
// half-edge is paired with the border half-edge of another piece that has its end points swapped
// (exact coordinate equality; −0 and +0 are one value), and paired ends become one vertex
// (union–find). Vertices are identified only through paired edges, never by coordinates alone,
// so distinct vertices at equal coordinates (pinched fans of the input) stay distinct.
#include "cover/brep/cells.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

#include "cover/brep/detail/cells_check.h"
#include "cover/mesh/rounding_repair.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/parallel.h"

namespace cover::brep {
namespace {

using Clock = std::chrono::steady_clock;

/// A wall coordinate with 17 significant digits (it reads back to the same double).
std::string wall_text(double c) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", c);
  return buffer;
}

/// A closed mesh and the kind of each of its faces.
struct Part {
  PolygonMesh mesh;
  std::vector<CellFace> faces;
  int64_t forced_ears = 0;  ///< in the clips that made it
  bool empty() const { return mesh.face_count() == 0; }
};

void measure(CellPiece& piece);
bool on_cell_wall(const CellPiece& piece, uint32_t v, const CellGrid& grid);

class Cutter {
 public:
  Cutter(const CellGrid& grid, const CellsOptions& options) : grid_(grid), options_(options) {}

  /// `part` ∩ cube: clipped by the cube's six faces, x first (module comment: before any
  /// interior wall).
  Part clip_to_cube(Part part) {
    for (int axis = 0; axis < 3; ++axis) {
      part = split(std::move(part), axis, 0, CellFace::kOuter).second;
      part = split(std::move(part), axis, grid_.n, CellFace::kOuter).first;
    }
    return part;
  }

  /// Pieces of `part` (inside the cube) for the cells whose indices before `axis` are those of
  /// `cell`, in (i, j, k) order.
  void start_axis(Part part, int axis, std::array<int, 3> cell, std::vector<CellPiece>& out) {
    cut_range(std::move(part), axis, 0, grid_.n, cell, out);
  }

  int64_t clips() const { return clips_.load(); }
  int64_t forced_ears() const { return forced_.load(); }

 private:
  /// `part` lies between walls a and b of `axis`: bisects the walls between them.
  void cut_range(Part part, int axis, int a, int b, std::array<int, 3> cell,
                 std::vector<CellPiece>& out) {
    if (part.empty()) return;
    if (b - a == 1) {
      cell[axis] = a;
      if (axis < 2)
        start_axis(std::move(part), axis + 1, cell, out);
      else
        out.push_back(finish(std::move(part), cell));
      return;
    }
    const int mid = a + (b - a) / 2;
    auto [lo, hi] = split(std::move(part), axis, mid, CellFace::kInterior);
    std::vector<CellPiece> right;
    parallel_invoke([&, &lo = lo] { cut_range(std::move(lo), axis, a, mid, cell, out); },
                    [&, &hi = hi] { cut_range(std::move(hi), axis, mid, b, cell, right); });
    for (CellPiece& piece : right) out.push_back(std::move(piece));
  }

  /// (below, above) of `part` at wall k of `axis`; caps get `kind`.
  std::pair<Part, Part> split(Part part, int axis, int k, CellFace kind) {
    if (part.empty()) return {};
    const double c = cell_wall(grid_, axis, k);
    const Bbox box = face_bbox(part.mesh);
    if (box.max[axis] <= c) return {std::move(part), Part{}};
    if (box.min[axis] >= c) return {Part{}, std::move(part)};
    Vec3 normal;
    (axis == 0 ? normal.x : axis == 1 ? normal.y : normal.z) = 1;
    ClipResult r;
    try {
      r = clip(part.mesh, Plane{normal, c}, options_.clip);
    } catch (const NotComputable& e) {
      throw NotComputable(std::string("cells: the wall ") + "xyz"[axis] + " = " + wall_text(c) +
                          ": " + e.what());
    } catch (const InputError& e) {
      throw InputError(std::string("cells: the wall ") + "xyz"[axis] + " = " + wall_text(c) + ": " +
                       e.what());
    }
    ++clips_;
    forced_ += r.forced_ears;
    auto take = [&](ClipHalf& half) {
      Part q;
      q.mesh = std::move(half.mesh);
      q.faces.reserve(half.face_source.size());
      for (uint32_t s : half.face_source) q.faces.push_back(s == kNoFace ? kind : part.faces[s]);
      q.forced_ears = part.forced_ears + r.forced_ears;
      return q;
    };
    return {take(r.below), take(r.above)};
  }

  static CellPiece finish(Part part, const std::array<int, 3>& cell) {
    CellPiece piece;
    piece.cell = cell;
    piece.forced_ears = part.forced_ears;
    piece.mesh = std::move(part.mesh);
    piece.faces = std::move(part.faces);
    measure(piece);
    return piece;
  }

  const CellGrid& grid_;
  const CellsOptions& options_;
  std::atomic<int64_t> clips_{0}, forced_{0};
};

/// Volume, areas and cap faces of `piece` from its mesh and face kinds.
void measure(CellPiece& piece) {
  PolygonMesh caps;
  caps.vertices = piece.mesh.vertices;
  piece.cap_faces = 0;
  for (size_t f = 0; f < piece.faces.size(); ++f) {
    if (piece.faces[f] == CellFace::kSurface) continue;
    caps.add_face(piece.mesh.face(f));
    ++piece.cap_faces;
  }
  piece.cap_area = surface_area(caps);
  piece.volume = signed_volume(piece.mesh);
  piece.area = surface_area(piece.mesh);
}

/// The rounding repair of one piece (module comment of cells.h): vertices on the cell's walls
/// are the rounded ones.
void repair_piece(CellPiece& piece, const CellGrid& grid) {
  std::vector<uint8_t> rounded(piece.mesh.vertices.size(), 0);
  for (uint32_t v = 0; v < rounded.size(); ++v) rounded[v] = on_cell_wall(piece, v, grid);
  // Cap faces on one wall are one valid triangulation of its rounded rings (no forced ear:
  // every triangle counter-clockwise on the rounded points and empty of other nodes, brep/cap.cpp)
  // merged into convex faces, so they are not tested against each other; a ring that is not
  // simple as rounded shows as side faces meeting. With a forced ear everything is tested.
  std::vector<uint32_t> group;
  if (piece.forced_ears == 0) {
    group.assign(piece.faces.size(), 0);
    for (size_t f = 0; f < piece.faces.size(); ++f) {
      if (piece.faces[f] == CellFace::kSurface) continue;
      const auto loop = piece.mesh.face(f);
      for (int a = 0; a < 3 && group[f] == 0; ++a)
        for (int side = 0; side < 2; ++side) {
          const double c = cell_wall(grid, a, piece.cell[a] + side);
          if (std::all_of(loop.begin(), loop.end(),
                          [&](uint32_t v) { return piece.mesh.vertices[v][a] == c; })) {
            group[f] = static_cast<uint32_t>(1 + 2 * a + side);
            break;
          }
        }
    }
  }
  RoundingRepair r = repair_rounding(piece.mesh, rounded, group);
  piece.rounding_contacts = r.remaining_pairs;
  if (!r.changed()) return;
  piece.collapsed_edges = r.collapsed_edges;
  std::vector<CellFace> faces;
  faces.reserve(r.face_origin.size());
  for (uint32_t f : r.face_origin) faces.push_back(piece.faces[f]);
  piece.faces = std::move(faces);
  measure(piece);
}

/// Coordinates as an ordered key; −0 becomes +0 so that equal values compare equal.
std::array<double, 3> key(const Vec3& p) { return {p.x + 0.0, p.y + 0.0, p.z + 0.0}; }

uint32_t find(std::vector<uint32_t>& parent, uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

/// Whether vertex v of `piece` lies on a wall of its cell (every constructed point does).
bool on_cell_wall(const CellPiece& piece, uint32_t v, const CellGrid& grid) {
  for (int a = 0; a < 3; ++a) {
    const double x = piece.mesh.vertices[v][a];
    if (x == cell_wall(grid, a, piece.cell[a]) || x == cell_wall(grid, a, piece.cell[a] + 1))
      return true;
  }
  return false;
}

/// The pieces glued (module comment); `rounded` gets one flag per output vertex: on a wall.
PolygonMesh glue(const std::vector<CellPiece>& pieces, const CellGrid& grid,
                 std::vector<uint8_t>& rounded) {
  std::vector<uint32_t> base(pieces.size() + 1, 0);
  for (size_t p = 0; p < pieces.size(); ++p)
    base[p + 1] = base[p] + static_cast<uint32_t>(pieces[p].mesh.vertices.size());
  // Border half-edges of every piece (global vertex ids), keyed by their end coordinates.
  struct Border {
    std::array<double, 3> from, to;
    uint32_t a, b, piece;
  };
  std::vector<Border> border;
  std::vector<uint64_t> edges;
  std::vector<uint32_t> parent(base.back());
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t p = 0; p < pieces.size(); ++p) {
    const CellPiece& piece = pieces[p];
    edges.clear();
    for (size_t f = 0; f < piece.faces.size(); ++f) {
      if (piece.faces[f] == CellFace::kInterior) continue;
      const auto loop = piece.mesh.face(f);
      for (size_t i = 0; i < loop.size(); ++i)
        edges.push_back(uint64_t{loop[i]} << 32 | loop[(i + 1) % loop.size()]);
    }
    std::sort(edges.begin(), edges.end());
    for (uint64_t e : edges) {
      const uint32_t a = static_cast<uint32_t>(e >> 32), b = static_cast<uint32_t>(e);
      if (std::binary_search(edges.begin(), edges.end(), uint64_t{b} << 32 | a)) continue;
      const auto from = key(piece.mesh.vertices[a]), to = key(piece.mesh.vertices[b]);
      if (from == to) {  // two constructed points rounded to one: one vertex, nothing to pair
        parent[find(parent, base[p] + a)] = find(parent, base[p] + b);
        continue;
      }
      border.push_back({from, to, base[p] + a, base[p] + b, static_cast<uint32_t>(p)});
    }
  }
  auto less = [](const Border& x, const Border& y) {
    return std::tie(x.from, x.to, x.piece, x.a) < std::tie(y.from, y.to, y.piece, y.a);
  };
  std::sort(border.begin(), border.end(), less);
  std::vector<uint8_t> paired(border.size(), 0);
  for (size_t e = 0; e < border.size(); ++e) {
    if (paired[e]) continue;
    const Border& x = border[e];
    auto it = std::lower_bound(border.begin(), border.end(), Border{x.to, x.from, 0, 0, 0}, less);
    for (; it != border.end() && it->from == x.to && it->to == x.from; ++it) {
      const size_t t = static_cast<size_t>(it - border.begin());
      if (!paired[t] && it->piece != x.piece) break;
    }
    if (it == border.end() || it->from != x.to || it->to != x.from)
      throw InternalError("cells: a wall edge of cell piece " + std::to_string(x.piece) +
                          " has no partner across the wall");
    paired[e] = paired[static_cast<size_t>(it - border.begin())] = 1;
    parent[find(parent, x.a)] = find(parent, it->b);
    parent[find(parent, x.b)] = find(parent, it->a);
  }
  // Output: the kept faces over their identified vertices, numbered in order of first use.
  PolygonMesh out;
  std::vector<uint32_t> index(base.back(), kNoFace), loop;
  for (size_t p = 0; p < pieces.size(); ++p) {
    const CellPiece& piece = pieces[p];
    for (size_t f = 0; f < piece.faces.size(); ++f) {
      if (piece.faces[f] == CellFace::kInterior) continue;
      loop.clear();
      for (uint32_t v : piece.mesh.face(f)) {
        const uint32_t r = find(parent, base[p] + v);
        if (index[r] == kNoFace) {
          index[r] = static_cast<uint32_t>(out.vertices.size());
          out.vertices.push_back(piece.mesh.vertices[v]);
          rounded.push_back(on_cell_wall(piece, v, grid));
        }
        // Two corners identified (a wall within rounding distance of a mesh vertex made two
        // constructed points round to one double point): one corner.
        if (loop.empty() || loop.back() != index[r]) loop.push_back(index[r]);
      }
      while (loop.size() > 1 && loop.front() == loop.back()) loop.pop_back();
      if (loop.size() >= 3) out.add_face(loop);
    }
  }
  return out;
}

}  // namespace

double cell_wall(const CellGrid& grid, int axis, int k) {
  const double lo = grid.min[axis];
  if (k <= 0) return lo;
  if (k >= grid.n) return lo + grid.size;
  return lo + k * (grid.size / grid.n);
}

double cells_memory_bytes(int n, double mesh_faces) {
  const double cells = static_cast<double>(n) * n * n;
  return 3072 * cells + 1024 * mesh_faces;
}

CellsResult cut_cells(const PolygonMesh& mesh, const CellGrid& grid, const CellsOptions& options) {
  if (grid.n < 1) throw InputError("cells: expected at least 1 cell per axis");
  if (!std::isfinite(grid.min.x) || !std::isfinite(grid.min.y) || !std::isfinite(grid.min.z) ||
      !std::isfinite(grid.size) || !(grid.size > 0))
    throw InputError("cells: expected a finite cube corner and a finite size > 0");
  if (options.max_memory_bytes > 0)
    check_memory(cells_memory_bytes(grid.n, static_cast<double>(mesh.face_count())),
                 options.max_memory_bytes,
                 "cells: " + std::to_string(grid.n) + "³ cells of a mesh of " +
                     std::to_string(mesh.face_count()) + " faces");
  CellsResult result;
  const auto start = Clock::now();
  // A mesh with distinct vertices at one point touches itself; its pieces may too.
  bool touching = false;
  {
    std::vector<std::array<double, 3>> points;
    points.reserve(mesh.vertices.size());
    for (const Vec3& p : mesh.vertices) points.push_back(key(p));
    std::sort(points.begin(), points.end());
    touching = std::adjacent_find(points.begin(), points.end()) != points.end();
  }
  Part whole;
  whole.mesh = mesh;
  whole.faces.assign(mesh.face_count(), CellFace::kSurface);
  Cutter cutter(grid, options);
  cutter.start_axis(cutter.clip_to_cube(std::move(whole)), 0, {0, 0, 0}, result.pieces);
  result.clips = cutter.clips();
  result.forced_ears = cutter.forced_ears();
  for (const CellPiece& piece : result.pieces) result.cap_faces += piece.cap_faces;
  const auto cut_end = Clock::now();
  result.cut_seconds = std::chrono::duration<double>(cut_end - start).count();
  if (options.glue) {
    std::vector<uint8_t> rounded;
    result.glued = glue(result.pieces, grid, rounded);
    repair_rounding(result.glued, rounded);
    std::vector<uint8_t> no_kinds;
    detail::triangulate_nonplanar(result.glued, no_kinds);
    const std::string why = detail::invalid_reason(result.glued, touching);
    if (!why.empty())
      throw NotComputable("cells: the glued pieces are not valid as written in doubles (" + why +
                          "): a wall lies within rounding distance of the surface");
    result.glue_seconds = std::chrono::duration<double>(Clock::now() - cut_end).count();
  }
  const auto repair_start = Clock::now();
  std::vector<std::string> invalid(result.pieces.size());
  parallel_for(result.pieces.size(), 1, [&](size_t p0, size_t p1) {
    for (size_t p = p0; p < p1; ++p) {
      CellPiece& piece = result.pieces[p];
      repair_piece(piece, grid);
      // A piece of six cap faces over eight vertices is its cell's box (valid as it is).
      if (piece.faces.size() == 6 && piece.mesh.vertices.size() == 8 &&
          std::none_of(piece.faces.begin(), piece.faces.end(),
                       [](CellFace k) { return k == CellFace::kSurface; }))
        continue;
      const size_t faces = piece.faces.size();
      detail::triangulate_nonplanar(piece.mesh, piece.faces);
      if (piece.faces.size() != faces) measure(piece);
      invalid[p] = detail::invalid_reason(piece.mesh, touching);
    }
  });
  for (size_t p = 0; p < invalid.size(); ++p)
    if (!invalid[p].empty()) {
      const auto& c = result.pieces[p].cell;
      throw NotComputable("cells: the piece of cell (" + std::to_string(c[0]) + ", " +
                          std::to_string(c[1]) + ", " + std::to_string(c[2]) +
                          ") is not valid as written in doubles (" + invalid[p] +
                          "): a wall lies within rounding distance of the surface");
    }
  for (const CellPiece& piece : result.pieces) {
    result.collapsed_edges += piece.collapsed_edges;
    result.rounding_contacts += piece.rounding_contacts;
  }
  result.cap_faces = 0;
  for (const CellPiece& piece : result.pieces) result.cap_faces += piece.cap_faces;
  result.repair_seconds = std::chrono::duration<double>(Clock::now() - repair_start).count();
  return result;
}

}  // namespace cover::brep
