#pragma once
// cover::Model — the one object a user needs (docs/library.md): a non-evaluated CSG
// solid with a method per kernel. Built from a mesh or scene file (load), primitives (box,
// sphere, cylinder), a triangle mesh from arrays (mesh), and combined with | & - ~ and
// transformed(); none of these evaluates anything ([Segura2004 §4]: faces are concatenated, signs
// flipped). Every query reuses one BVH over the covering triangles (covering/bvh.h), built on
// the first query that needs it.
//
// Value semantics: a Model is an immutable handle (copies share the solid and its BVH), cheap to
// copy and safe to query from several threads at once (the BVH is built once, under
// std::call_once). The free functions of the modules stay available for those who want them:
// solid() gives the Solid and bvh() its BVH.
//
// Errors (solid/errors.h): InputError for bad input (files, arrays, options), with the CLI's
// one-line message; NotComputable for a valid request no exact method can answer; among them an
// unbounded result (a complement at the root) asked for a volume, an evaluation, cells, a clip or
// a decomposition (always NotComputable; a grid without bounds — voxel_bounds, voxelize, octree —
// is an InputError: give bounds); PreconditionError for a violated precondition of a caller.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cover/boolean/evaluate.h"
#include "cover/brep/cells.h"
#include "cover/brep/clip.h"
#include "cover/brep/decompose.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/prepared.h"
#include "cover/covering/ray.h"
#include "cover/covering/volume.h"
#include "cover/field/field.h"
#include "cover/io/scene.h"
#include "cover/io/zarr_io.h"
#include "cover/octree/octree.h"
#include "cover/points/point_set.h"
#include "cover/polygonize/polygonize.h"
#include "cover/render/camera.h"
#include "cover/render/render.h"
#include "cover/solid/errors.h"
#include "cover/solid/solid.h"
#include "cover/solid/transform.h"
#include "cover/voxel/voxelize.h"

namespace cover {

/// What Model::evaluate_cells() gives: the plain evaluation and its pieces per cell.
struct CellsEvaluation {
  brep::CellGrid grid;          ///< the cube and the cells per axis
  EvaluateResult evaluated;     ///< evaluate(): the mesh that was cut
  brep::CellsResult cells;      ///< pieces in (i, j, k) order and, glued, the same solid
  double evaluate_seconds = 0;  ///< wall-clock time of evaluate()
};

class Model {
 public:
  /// The empty solid (no leaves): the identity of `|`; classifies every point outside, volume 0,
  /// evaluates to an empty mesh; ~Model() throws PreconditionError (all of space has no leaf).
  Model();
  /// Wraps a solid (for instance from parse_scene); `warnings` are kept for warnings().
  explicit Model(Solid solid, std::vector<std::string> warnings = {});

  const Solid& solid() const;
  /// One line each, from loading and repairs (a leaf re-oriented, an open leaf, ...); a
  /// parameter is named by `name_of` (a front end's flag or keyword), else as C++ spells it
  /// (solid/errors.h show_parameters).
  std::vector<std::string> warnings(
      const std::function<std::string(std::string_view)>& name_of = {}) const;
  size_t leaf_count() const;
  /// True for the empty Model (no leaf): the empty set.
  bool empty() const { return leaf_count() == 0; }

  /// The solid prepared for the kernels (covering/prepared.h): its BVH and open-leaf trees,
  /// each built on first use (thread-safe) and shared by copies and every query.
  const Prepared& prepared() const;
  /// The BVH of every covering triangle (prepared().bvh()).
  const Bvh& bvh() const;
  /// The open leaves' generalized-winding-number trees (covering/gwn.h), built on first use;
  /// nullptr when every leaf is closed. Open leaves (docs/cli.md#semantics): inside where
  /// |w| > 1/2; classify, windings-free kernels (cast, render, voxelize, octree, volume) use it.
  const GwnForest* gwn() const;

  /// Union, intersection, difference and complement (concatenation, [Segura2004 §4]). Lazy:
  /// each builds a node in O(1); the solid is built on first use, a chain of one operator
  /// (m = m | part in a loop) as one n-ary operation, O(total size).
  friend Model operator|(const Model& a, const Model& b);
  friend Model operator&(const Model& a, const Model& b);
  friend Model operator-(const Model& a, const Model& b);
  Model operator~() const;

  /// The solid mapped by the affine `m` (solid/transform.h transform_solid); a mirror keeps
  /// leaves outward. \throws InputError when m is not finite, singular, or maps a vertex outside
  /// ±kMaxCoordinate.
  Model transformed(const Transform& m) const;
  /// transformed() by a translation, scale (non-zero factors per axis), rotation (about a
  /// non-zero axis through the origin, right-handed, degrees) or mirror (through the plane
  /// through the origin with a non-zero normal). \throws InputError as transformed(), and for a
  /// zero factor, axis or normal, or a non-finite value.
  Model translated(Vec3 offset) const;
  Model scaled(Vec3 factors) const;
  Model scaled(double factor) const { return scaled(Vec3{factor, factor, factor}); }
  Model rotated(Vec3 axis, double degrees) const;
  Model mirrored(Vec3 normal) const;

  /// The solid as bytes (io/serialize.h): how a Model travels to another process (pickling,
  /// Dask workers) with the same doubles and expression; load warnings are not kept.
  std::string to_bytes() const;
  /// The Model of to_bytes(). \throws InputError naming `what` for bytes that are not a solid.
  static Model from_bytes(std::string_view bytes, const std::string& what = "model bytes");

  /// True when the result is a bounded set (covering/bounds.h).
  bool bounded() const;
  /// A box containing the result (empty box for an empty result); nullopt when unbounded.
  std::optional<Bbox> bounds() const;

  /// Exact class of each point (covering/classify.h). \throws InputError for a non-finite point
  /// or one outside ±kMaxCoordinate, naming its index.
  std::vector<PointClass> classify(std::span<const Vec3> points,
                                   const ClassifyOptions& options = {}) const;

  /// classify() and the count of points it could not certify (covering/classify.h
  /// Classification: circle skeletons' undecided points, several surfaces meeting at a point).
  /// \throws InputError as classify().
  Classification classify_counted(std::span<const Vec3> points,
                                  const ClassifyOptions& options = {}) const;

  /// The field queries of the HybridTree: per point and field leaf (row-major: point i's value
  /// for the k-th field leaf at i·leaves.size() + k), f and ∇f in doubles (field/field.h
  /// evaluate). A warp leaf whose child is one field leaf (or a warp of one) counts as a field
  /// leaf: f∘w⁻¹ and Jᵀ·∇f (field/warp.h). \throws InputError for a solid without field
  /// leaves, and as classify().
  struct FieldValues {
    std::vector<uint32_t> leaves;  ///< the field leaves' ids, in solid().leaves order
    std::vector<field::FieldValue> values;
  };
  FieldValues field(std::span<const Vec3> points) const;

  /// Every leaf's winding number at every point (covering/classify.h LeafWindings): a closed
  /// leaf's exact winding number; an open leaf's generalized winding number w rounded to the
  /// nearest integer (covering/gwn.h open_windings): 0 exactly where |w| ≤ 1/2 as classify()
  /// decides it, so an entry is nonzero exactly where classify() counts that leaf inside.
  /// Where a point is on leaf l's surface (on_surface) the entry is undefined: a closed leaf's
  /// holds a neighbouring count, an open leaf's 0. \throws InputError as classify().
  LeafWindings windings(std::span<const Vec3> points, const ClassifyOptions& options = {}) const;

  /// Signed distance of each point to the result's boundary: negative inside, positive outside,
  /// 0 exactly where classify() finds the point on the boundary (the sign is classify()'s, exact
  /// where classify is). The magnitude is the distance, in doubles, to the evaluated B-rep
  /// (evaluate(): the exact boundary rounded once for mesh trees; with field, warp or open
  /// leaves, the mixed evaluation's mesh, within `evaluated.tolerance` at its vertices and
  /// h·√3 of the surface; thinner features than its grid are not promised). An empty result
  /// gives +∞. \throws InputError as classify(); NotComputable for an unbounded result.
  struct Distances {
    std::vector<double> distance;
    std::vector<PointClass> classes;  ///< classify() of the points
    size_t uncertain = 0;             ///< as classify_counted()
    std::vector<MeshedLeaf> meshed;   ///< what the evaluation meshed first (empty: mesh trees)
  };
  Distances distance(std::span<const Vec3> points) const;

  /// All hits and inside spans of each ray (covering/ray.h). \throws InputError for a zero or
  /// non-finite direction or a non-finite origin, naming the ray's index.
  std::vector<RayResult> cast(std::span<const Ray> rays, const CastOptions& options = {}) const;
  /// The first entry into the result along each ray (FirstHit::hit false where there is none).
  /// \throws InputError as cast().
  std::vector<FirstHit> first_hits(std::span<const Ray> rays,
                                   const CastOptions& options = {}) const;

  /// Volume, area where known, method ("covering", "rays" or "brep") and error bound: the
  /// covering's exact value where the expression allows it (covering/volume.h); else the ray
  /// method with its proven bound; else — options.exact, or (options.rays == 0) a bound that
  /// misses options.target_relative_error — the exact volume and area of the evaluated B-rep
  /// (method "brep", error_bound 0), when evaluate() accepts the leaves (otherwise the ray
  /// result, target_met false, stays). Field and warp leaves: the bracket method (method
  /// "bracket"), options.exact included (a curved solid has no exact volume in doubles).
  /// \throws NotComputable for an unbounded result; with options.exact, InputError when the
  /// B-rep cannot be evaluated (a leaf face whose boundary crosses itself).
  VolumeResult volume(const VolumeOptions& options = {}) const;

  /// The default grid cube of voxelize() and octree() for n cells per side: the result's box made
  /// cubic with one cell of margin per side (n < 3 gets the margin of n = 3; voxel/voxel_grid.h).
  /// \throws InputError for an unbounded result (give explicit bounds instead).
  VoxelBounds voxel_bounds(int n) const;

  /// The global grid voxelize(options) covers (voxel/voxelize.h voxel_lattice): cubic from
  /// resolution and bounds, or from voxel_size / dims over options.bounds or the result's box.
  /// Bricks of it are voxelize_brick's input. \throws InputError for a resolution out of
  /// 1..kMaxVoxelDims (16384), an unbounded result without options.bounds, bad voxel_size or
  /// dims (voxel_lattice).
  VoxelLattice voxel_lattice(const VoxelizeOptions& options = {}) const;

  /// Presence-buffer voxelization of the whole lattice (voxel/voxelize.h). \throws InputError
  /// as voxel_lattice(), and for a cubic resolution above 4096 (use voxelize_to_zarr or bricks).
  VoxelGrid voxelize(const VoxelizeOptions& options = {}) const;

  /// Brick API (docs/scale-out.md#bricks): the voxels of the index box [box.lo, box.hi) of
  /// `lattice`, bit-identical to the same region of voxelize() over that lattice (global centres,
  /// the same exact predicates and tie rule), at a cost ∝ the covering triangles whose x/y range
  /// reaches the brick's columns (found through the BVH) and the brick's voxels. grid.lattice =
  /// lattice, grid.box = box; local voxel (i, j, k) is global box.lo + (i, j, k). Thread-safe.
  /// \throws InputError for an empty box or one outside [0, lattice.dims), dims out of
  /// 1..16384, a non-finite origin or a spacing that is not finite and > 0.
  VoxelGrid voxelize_brick(const VoxelLattice& lattice, const IndexBox& box) const;
  /// The same into `grid`, reusing its memory (one grid per worker).
  void voxelize_brick(const VoxelLattice& lattice, const IndexBox& box, VoxelGrid& grid) const;

  /// Exact class (classify()) of the centres of the brick's voxels, in [x][y][z] order (z
  /// fastest): index ((i − lo₀)·ny + (j − lo₁))·nz + (k − lo₂). Where it says inside / outside,
  /// voxelize_brick's bit agrees; on a leaf's boundary the voxel follows the tie rule.
  /// \throws InputError as voxelize_brick().
  std::vector<PointClass> classify_brick(const VoxelLattice& lattice, const IndexBox& box,
                                         const ClassifyOptions& options = {}) const;

  /// Voxelizes voxel_lattice(options) straight into a Zarr v2 store (io/zarr_io.h), brick
  /// by brick (chunk columns; memory bounded by the bricks in flight), so N up to 16384 fits
  /// one machine. options.progress is not used (zarr.progress is). \throws InputError as
  /// voxel_lattice() and write_zarr().
  ZarrResult voxelize_to_zarr(const std::filesystem::path& path, const VoxelizeOptions& options,
                              const ZarrOptions& zarr = {}) const;

  /// Direct octree (octree/octree.h) over `bounds`, default: the voxel bounds of the result at
  /// 2^depth cells per side. \throws InputError as build_octree(), and for an unbounded result
  /// without bounds; NotComputable beyond 2^32 nodes.
  Octree octree(const OctreeOptions& options = {},
                const std::optional<VoxelBounds>& bounds = std::nullopt) const;

  /// The camera that frames the result from options.view: its box (every leaf's when unbounded)
  /// tightened by result_support (render/camera.h) where bounded; with options.fit, only the
  /// part that `section` keeps (section_box; the whole box where that part is empty).
  /// \throws InputError for an image size out of 1..16384, options.fit without a section or
  /// with a zero or non-finite one, and as frame_camera().
  Camera camera(const CameraOptions& options = {},
                const std::optional<Plane>& section = std::nullopt) const;
  /// Ray-cast preview (render/render.h) through camera(camera_options, options.section).
  /// \throws InputError for an image size out of 1..16384 or a zero section normal.
  Image render(const CameraOptions& camera_options = {}, const RenderOptions& options = {}) const;
  /// The same through a given camera.
  Image render(const Camera& camera, const RenderOptions& options = {}) const;

  /// The result as one closed, outward 2-manifold triangle mesh (boolean/evaluate.h), with each
  /// face's source leaf (EvaluateResult::face_leaf, indices into solid().leaves). A
  /// self-intersecting leaf stands for its nonzero-winding set, as in classify(). Field, warp
  /// and open-mesh leaves are meshed first by polygonize() (mixed evaluation: options.
  /// mesh_resolution, mesh_tolerance), then the exact Booleans combine them with the mesh leaves;
  /// EvaluateResult::meshed and tolerance say which and how close. The evaluation with default
  /// options (any grain) is built once and kept, as the BVH is, and shared with clip(),
  /// evaluate_cells() and decompose(); other options evaluate again.
  /// \throws NotComputable for an unbounded result; InputError for a leaf face whose boundary
  /// crosses itself.
  EvaluateResult evaluate(const EvaluateOptions& options = {}) const;

  /// The whole result's boundary by certified marching tetrahedra (polygonize/polygonize.h) over
  /// its bounds: any tree, closed, outward, 2-manifold and free of self-intersections, every
  /// vertex within PolygonizeResult::tolerance of the surface. \throws NotComputable for an
  /// unbounded result; InputError as cover::polygonize().
  PolygonizeResult polygonize(const PolygonizeOptions& options = {}) const;

  /// Plane clip and patch (brep/clip.h) of the result: a single closed mesh leaf is clipped as it
  /// is, any other expression (fields, warps, open leaves included) is evaluated first.
  /// \throws InputError for a zero or non-finite plane, or (as brep::clip) a non-manifold leaf;
  /// NotComputable for an unbounded result and when the cap cannot be built.
  brep::ClipResult clip(const brep::Plane& plane, const brep::ClipOptions& options = {}) const;

  /// The result through n×n×n cells (brep/cells.h): evaluate(), then its mesh cut by the plane
  /// patcher into one closed, outward 2-manifold piece per cell it meets (a cell inside the
  /// result gives its box), over the cube `bounds` (default voxel_bounds(n), the cube voxelize
  /// uses). cells.glued is the pieces glued back: the same solid as evaluate() when the cube
  /// contains the result (else the result ∩ cube). Cells are cut in parallel. Every piece and
  /// the glued mesh are checked exactly as written (brep::cut_cells).
  /// \throws InputError for n < 1, bad bounds, brep::cells_memory_bytes(n) over
  /// options.max_memory_bytes (checked first, before evaluating; then with the evaluated mesh's
  /// faces), and as evaluate(); NotComputable as evaluate() and brep::clip, and when a piece or
  /// the glued mesh is not valid as written in doubles.
  CellsEvaluation evaluate_cells(int n, const std::optional<VoxelBounds>& bounds = std::nullopt,
                                 const brep::CellsOptions& options = {}) const;

  /// Exact convex decomposition (brep/decompose.h) of the result: a single closed mesh leaf as it
  /// is, any other expression evaluated first. Every piece is a closed, outward triangle mesh,
  /// convex exactly on its doubles; the volumes sum to the result's. \throws InputError (as
  /// brep::decompose) for a non-manifold leaf; NotComputable for an
  /// unbounded result (as evaluate()) and when a cut cannot be made (a self-intersecting leaf).
  brep::DecomposeResult decompose(const brep::DecomposeOptions& options = {}) const;

 private:
  /// evaluate() with default options, built once and kept.
  const EvaluateResult& evaluated() const;

  struct State;
  static std::shared_ptr<const State> make_state(Solid solid, std::vector<std::string> warnings);
  /// The lazy node `op` over a (and b; nullptr for a complement).
  static Model operation(CsgOp op, const Model& a, const Model* b);
  explicit Model(std::shared_ptr<const State> state) : state_(std::move(state)) {}
  std::shared_ptr<const State> state_;
};

/// The union of all `models` (the empty Model for none), and the intersection of all (at least
/// one; PreconditionError for none): O(total size), as one n-ary operation.
Model union_all(std::span<const Model> models);
Model intersection_all(std::span<const Model> models);

/// Loads a mesh (one leaf) or a JSON scene (docs/cli.md#input), repaired as the CLI does.
/// \throws InputError naming the file and the place (io/scene.h load_input).
Model load(const std::filesystem::path& path, const LoadOptions& options = {});

/// A JSON scene given as text (docs/cli.md#input), as load() reads a scene file: relative mesh
/// and point-cloud paths resolve against `base` (default: the working directory), messages
/// name the scene "<scene>". \throws InputError naming the place.
Model scene(const std::string& json, const std::filesystem::path& base = {},
            const LoadOptions& options = {});

/// Primitives as closed, outward leaves (solid/primitives.h).
/// \throws InputError for min ≥ max on an axis, a radius ≤ 0, segments < 3, base = top, or
/// non-finite values.
Model box(Vec3 min, Vec3 max);
Model sphere(Vec3 center, double radius, int segments = 32);
Model cylinder(Vec3 base, Vec3 top, double radius, int segments = 32);

/// A leaf from a triangle mesh given as arrays (outward or inside-out; repaired as a loaded file,
/// io/scene.h prepare_leaf). \throws InputError for an index out of range, a non-finite
/// coordinate, an open mesh (options.require_closed), a non-orientable surface, naming `name`.
Model mesh(std::span<const Vec3> vertices, std::span<const std::array<uint32_t, 3>> triangles,
           const std::string& name = "mesh", const LoadOptions& options = {});
/// The same from polygons (solid/polygon_mesh.h). \throws as above.
Model mesh(PolygonMesh polygons, const std::string& name = "mesh", const LoadOptions& options = {});

/// A point-set leaf (points/point_set.h): the set where the oriented cloud's winding number
/// exceeds 1/2, as an open leaf of dipole triangles; `normals` one per point, or empty to estimate
/// them (PCA, MST orientation). \throws InputError as point_set_mesh(), naming `name`.
Model point_set(std::span<const Vec3> points, std::span<const Vec3> normals = {},
                const PointSetOptions& options = {}, const std::string& name = "points");

}  // namespace cover
