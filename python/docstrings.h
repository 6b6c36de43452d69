#pragma once
// Docstrings of cover._cover (module.cpp): shapes, dtypes and conventions of every function.
// Arrays are NumPy arrays; "float64 (n, 3)" means dtype float64 and shape (n, 3). The stubs in
// cover/__init__.pyi carry the same signatures.

namespace cover::python::doc {

inline constexpr const char* kModule =
    R"(Cover: CSG solids without boundary evaluation (simplicial coverings).

Build a Model with load(), box(), sphere(), cylinder() or mesh(); combine with | & - ~;
query it with classify(), winding(), volume(), voxelize(), cast(), render(), evaluate(),
clip(). numpy in, numpy out; kernels release the GIL and take threads= (None or 0: all
cores; results never depend on it); Ctrl-C stops long kernels (KeyboardInterrupt).)";

inline constexpr const char* kHits = R"(First hits of Model.cast(), one entry per ray:
hit bool (n,); t float64 (n,) ray parameter of the hit (inf where none; a distance when the
direction has unit length); leaf int32 (n,) leaf index (-1 where none); face int64 (n,) the
leaf's face index (-1 where none); normal float64 (n, 3) unit outward normal of the result at
the hit (0 where none).)";

inline constexpr const char* kInputError =
    R"(Invalid input (file contents, scene, arrays, options); a ValueError.
The message is the CLI's one-line error without its "cover: error: " prefix, naming the file
and the line / record / JSON path where it applies.)";

inline constexpr const char* kNotComputable =
    R"(A well-formed request that no exact method can answer (e.g. the volume or
bounds of an unbounded result); a RuntimeError.)";

inline constexpr const char* kPreconditionError =
    R"(A violated precondition (e.g. ~Model() of the empty Model); a ValueError.)";

inline constexpr const char* kModel =
    R"(A non-evaluated CSG solid: leaves (closed meshes) and the expression over them.

Immutable; copies share the solid and its BVH (built once, on the first query that needs
it). Safe to query from several Python threads at once.)";

inline constexpr const char* kModelInit = "The empty solid (no leaves): the identity of |.";
inline constexpr const char* kLeaves = "Number of leaves (int).";
inline constexpr const char* kEmpty = "True for the empty Model (no leaves).";
inline constexpr const char* kBounded =
    "True when the result is a bounded set (no complement at the root).";
inline constexpr const char* kWarnings =
    "Warnings from loading and repairs (list of str, one line each).";
inline constexpr const char* kOr = "Union (regularized): a | b.";
inline constexpr const char* kAnd = "Intersection (regularized): a & b.";
inline constexpr const char* kSub = "Difference (regularized): a - b.";
inline constexpr const char* kInvert =
    "Complement: ~a (unbounded). Raises PreconditionError for the empty Model.";

inline constexpr const char* kTransform =
    R"(A new Model mapped by the affine 4x4 matrix M (p' = M @ [p, 1]).

M: array-like (4, 4), last row 0 0 0 1. A mirror keeps solids solid. Raises InputError when
M is not affine, not finite, or singular.)";
inline constexpr const char* kTranslate = "A new Model moved by v (3 numbers).";
inline constexpr const char* kScale =
    R"(A new Model scaled about the origin by s: one number or 3 (per axis, non-zero).)";
inline constexpr const char* kRotate =
    R"(A new Model rotated about the line through the origin along `axis` (3 numbers,
non-zero) by `degrees` (right-hand rule).)";

inline constexpr const char* kMirror =
    R"(A new Model reflected through the plane through the origin with normal `normal`
(3 numbers, non-zero). Solids stay solid.)";
inline constexpr const char* kUnionAll =
    R"(The union of all Models in `models` (an iterable; the empty Model for none).

Like a | b | ..., whose chains Cover also collects: one n-ary union, built in time linear in the
total size.)";
inline constexpr const char* kIntersectionAll =
    R"(The intersection of all Models in `models` (at least one;
PreconditionError for none).)";

inline constexpr const char* kClassify =
    R"(Exact class of each point: uint8 (n,), codes indexing CLASS_NAMES.

points: array-like (n, 3), converted once to float64 (no copy for a float64 C-contiguous
array). Codes: 0 outside, 1 inside, 2 face, 3 edge, 4 vertex (the last three: on the
result's boundary; a point on a leaf's surface buried in the result is inside / outside).
Same classes as `cover classify`. Raises ValueError for a wrong shape, InputError for a
non-finite point (naming its index).)";

inline constexpr const char* kClassifyCounted =
    R"(classify() and the number of points it could not certify: (codes, uncertain).

uncertain counts points of circle skeletons whose interval enclosure of f - T holds 0 (decided by
the double evaluation's sign) and points where several surfaces meet in a way the expression does
not settle (reported face); 0 for meshes and polynomial fields off such points.)";

inline constexpr const char* kField =
    R"(Field value and gradient of every field leaf at every point: (f, grad).

f: float64 (n, k), grad: float64 (n, k, 3), for the k field leaves in leaf order (Model.info()
names them). f is the blend's sum of w_i (1 - d_i^2 / R_i^2)^n_i (inside where f exceeds the
threshold). Raises InputError when the model has no field leaf.)";

inline constexpr const char* kWindings =
    R"(Every leaf's winding number at every point: int32 (n, leaves).

points: array-like (n, 3) as for classify(). Column l is leaf l (load order / operand order).
A closed leaf: its exact winding number. An open leaf: its generalized winding number w (the
solid angle its triangles subtend / 4 pi) rounded to the nearest integer, 0 exactly where
|w| <= 1/2 as classify() decides it; so an entry is nonzero exactly where classify() counts that
leaf inside. Where a point lies ON leaf l's surface the entry is undefined: a closed leaf's
holds the count of a symbolically perturbed point (a neighbouring value, 0 or 1 for a simple
leaf), an open leaf's 0: use classify() to detect such points (its face / edge / vertex codes).)";

inline constexpr const char* kWinding =
    R"(Deprecated name of windings() (a DeprecationWarning): the same array.)";

inline constexpr const char* kCast =
    R"(Every crossing of the solids' surfaces along each ray (as the C++ Model::cast): a
Casts named tuple of flat arrays.

origins: array-like (n, 3); directions: (n, 3), or (3,) for one direction shared by every
ray (non-zero, finite). A ray is origin + t * direction, t > 0. Ray i's crossings are
t[offsets[i]:offsets[i+1]] (sorted), with their leaf, face and sign (+1 leaving the leaf, -1
entering it); the intervals of the ray inside the result are spans[span_offsets[i]:
span_offsets[i+1]] ((k, 2) rows t0, t1); uncertain[i] counts pieces field bisection could not
certify. first_hits() gives the first entry only.)";

inline constexpr const char* kFirstHits =
    R"(First entry into the result along each ray (as the C++ Model::first_hits): a Hits
named tuple of arrays.

origins: array-like (n, 3); directions: (n, 3), or (3,) for one direction shared by every
ray (non-zero, finite). A ray is origin + t * direction, t > 0. Returns Hits(hit bool (n,),
t float64 (n,) [inf where no hit], leaf int32 (n,) [-1], face int64 (n,) [-1], normal
float64 (n, 3) unit outward normal of the result [0]).)";

inline constexpr const char* kCasts =
    R"(Model.cast()'s result: offsets int64 (n+1,), t float64 (k,), leaf int32 (k,), face
int64 (k,), sign int32 (k,) (+1 leaving, -1 entering the leaf), span_offsets int64 (n+1,), spans
float64 (s, 2), uncertain uint32 (n,).)";

inline constexpr const char* kVolume =
    R"(Volume of the result, as `cover volume`: a VolumeResult, a float (the volume) that also
carries .volume, .error_bound, .method ("covering", "rays", "bracket" or "brep"), .area (None
where it would need evaluation), .rays / .cells and .target_met, as the C++ VolumeResult.

Exact from the covering where the expression allows it; else integrated over parallel rays
with a proven relative error bound of 1e-4 (or the exact B-rep volume when the bound is not
met); exact=True requires an exact method (B-rep evaluation; field and warp leaves: the bracket);
rays=N fixes the ray method's finest cells (1..2048). Field leaves: the certified bracket method
(midpoint of [V_in, V_out], relative half-width 1e-2 by default). tolerance=t sets the relative
target of the ray and bracket methods. Raises NotComputable for an unbounded result.)";

inline constexpr const char* kVolumeInfo =
    R"(Volume with its provenance: dict with volume (float), area (float or None where
it would need evaluation), method ("covering", "rays" or "brep"), error_bound (float, 0 for
exact methods); for the ray method also rays (int) and target_met (bool). Same keys and
values as `cover volume --json`. Arguments as volume().)";

inline constexpr const char* kBounds =
    R"(A box containing the result: float64 (2, 3), [min, max] (an empty result gives
[inf, -inf] rows). Raises NotComputable for an unbounded result.)";

inline constexpr const char* kVoxelBounds =
    R"(The default grid cube of voxelize(res): (xmin, ymin, zmin, size), the result's
box made cubic with one voxel of margin per side.)";

inline constexpr const char* kVoxelizeBrick = R"(The voxels of one brick of the res³ grid: bool
(i1-i0, j1-j0, k1-k0), indexed [x, y, z], for box = (i0, i1, j0, j1, k0, k1) (half-open index
ranges, 0 <= lo < hi <= res) and bounds = (xmin, ymin, zmin, size) (default: voxel_bounds(res)).
Bit-identical to voxelize(res, bounds)[i0:i1, j0:j1, k0:k1] (global centres, the same tie rule);
its cost follows the brick, and res may reach 16384 since only the brick is held. The building
block of cover.dask.voxelize. A brick needing more than max_memory MiB (9/8 byte a voxel) raises
InputError before anything is allocated.)";

inline constexpr const char* kToBytes =
    R"(The model as bytes: the same doubles and expression in another process
(Model.from_bytes, pickle); load warnings are not kept.)";

inline constexpr const char* kFromBytes =
    R"(The Model of to_bytes(); raises cover.InputError for bytes that are not one.)";

inline constexpr const char* kVoxelize =
    R"(Voxel grid of the result: bool (res, res, res), indexed [x, y, z].

Voxel (i, j, k) has centre min + (i + 1/2, j + 1/2, k + 1/2) * size / res and is True iff
the centre is inside (a centre exactly on a surface is decided for the point displaced
infinitesimally towards +x, then +y, then +z). bounds: (xmin, ymin, zmin, size) or None
for voxel_bounds(res). Equal to the .npy of `cover voxelize --res res` (uint8 there).
res: 1..4096. Instead of res, voxel_size=h (a grid of spacing h over the result's box, or over
bounds: dims = ceil(extent / h)) or dims=(NX, NY, NZ) give non-cubic grids (NX, NY, NZ), as the
CLI's --voxel-size and --dims. A grid needing more than max_memory MiB (9/8 byte a voxel: the
array and the packed grid) raises InputError before anything is allocated, as the CLI's
--max-memory.)";

inline constexpr const char* kRender =
    R"(Ray-cast preview of the non-evaluated solid: uint8 (height, width, 3) RGB, row 0 at the top.

view: "iso", "front", "back", "left", "right", "top" or "bottom"; section: (nx, ny, nz, d)
removes the half-space n.x > d and shows the exact cut faces; perspective: a perspective
camera (default orthographic). up: "x", "y" or "z", the axis shown upright (Y-up scans: "y");
elevation: the eye's angle above the horizontal plane in degrees, -90..90 (None: the view's,
iso 35.26); azimuth: the view turned about the up axis in degrees; zoom: magnification (> 0);
pan: (x, y) the view moved by x image widths right and y heights up after framing;
fit: frame the part the section keeps; samples: anti-aliasing, samples x samples rays per pixel
(1 to 4; 1: none); crease: smooth shading where faces meet at less than this angle in degrees
(0: flat shading, up to 180). The camera frames the result tightly (docs/cli.md). The same pixels as
`cover render --size WxH` with the same flags.)";

inline constexpr const char* kDistance =
    R"(Signed distance of each point to the result's boundary: float64 (n,), negative inside.

The sign is classify()'s (exact; 0 exactly on the boundary); the magnitude the distance to the
evaluated B-rep (evaluate(): exact up to its final rounding for mesh trees, the mixed
evaluation's certified mesh with fields, warps and open leaves). As `cover distance`. Raises
NotComputable for an unbounded result.)";

inline constexpr const char* kEvaluate =
    R"(The result as one closed, outward, 2-manifold triangle mesh (exact evaluation).

Returns (V float64 (n, 3), F int64 (m, 3)), faces counter-clockwise seen from outside; the
same mesh as `cover evaluate -o out.off`. leaf_ids=True returns (V, F, L) with L int32 (m,):
each face's source leaf (index into the leaves in load order, as `cover evaluate --leaf-ids`).
A self-intersecting leaf stands for its nonzero-winding set (as classify). Field, warp and open
leaves are meshed first by polygonize() at mesh_resolution cells along each one's box, vertices
within mesh_tolerance (0: the cell size / 1024) of their surface, then combined exactly (as
`cover evaluate --mesh-resolution --mesh-tolerance`). Raises NotComputable for an unbounded
result, InputError for a leaf face whose boundary crosses itself. Not interruptible.)";

inline constexpr const char* kPolygonize =
    R"(The whole result by certified marching tetrahedra: (V, F, report).

V float64 (n, 3), F int64 (m, 3): closed, outward, 2-manifold, free of self-intersections, for
any tree (fields, warps, open leaves). resolution: cells along the largest extent, at least
(the step is a power of two); cell_size: the step instead; tolerance: the largest distance of a
vertex from the surface (0: the cell size / 1024). report: dict with cell_size, tolerance (the
certified bound achieved), cells, grid_points, bisections, uncertain, clipped (as
`cover polygonize --json`). Features thinner than the grid may be missed. Raises NotComputable
for an unbounded result. Not interruptible.)";

inline constexpr const char* kClip =
    R"(Plane clip and patch: ((V_above, F_above), (V_below, F_below)).

plane: (nx, ny, nz, d); above = result with n.x >= d, below = n.x <= d, each closed and
outward with cap triangles on the plane; V float64 (n, 3), F int64 (m, 3): polygon faces are
triangulated exactly (a fan for convex faces). A single leaf is clipped as it
is, any other expression is evaluated first (as `cover clip`). Not interruptible.)";

inline constexpr const char* kEvaluateCells =
    R"(The result through n x n x n cells: a list of pieces, one dict per cell the result meets.

Each piece is result ∩ cell, closed on the cell walls by the plane patcher (exact, as
`cover clip`): a closed, outward, 2-manifold mesh; a cell inside the result gives its box.
Dict keys: cell (i, j, k), vertices float64 (n, 3), faces int64 (m, 3) (cap polygons
triangulated), volume, area, cap_area. Pieces come in (i, j, k) order, i slowest. bounds =
(xmin, ymin, zmin, size) as in voxelize (default: the cube voxelize uses for res=n). The same
pieces as `cover evaluate --cells n --pieces DIR`. max_memory (MiB, default 4096, the CLI's
--max-memory): n whose pieces may need more (3 KiB a cell) is refused with InputError before
anything is evaluated. Not interruptible.)";
inline constexpr const char* kDecompose =
    R"(Exact convex decomposition by plane cuts through reflex edges: a list of pieces.

Each piece is (V float64 (n, 3), F int64 (m, 3)): a closed, outward triangle mesh, convex
exactly on its doubles (every vertex on the inner side of, or on, every face's plane); the
volumes sum to the result's. A single closed mesh leaf is decomposed as it is, any other
expression (fields, warps, open leaves: meshed first, as evaluate()) is evaluated first (as
`cover decompose`). Raises InputError for a non-manifold leaf. Not interruptible.)";

inline constexpr const char* kInfo =
    R"(Facts about the Model as `cover info --json` reports them: dict with vertices,
faces, leaves, bbox ((min, max) or None) and leaves_info (one dict per leaf: name, origin,
vertices, faces, closed, manifold, oriented, outward, boundary_edges, nonmanifold_edges,
components, genus, degenerate_faces, self_intersecting, self_touching, volume, bbox, brep).
A loaded Model is the repaired one (outward, consistently oriented), so for a file that needs
repairs this differs from `cover info`, which reports the file as found.
self_intersection=False skips the exact self-intersection check (self_intersecting is then
None).)";

inline constexpr const char* kLoad =
    R"(Loads a mesh (.obj .off .stl .ply: one leaf) or a JSON scene as a Model.

Repaired as the CLI does (inside-out leaves flipped, inconsistent orientation fixed), each
repair reported by a Python warning and in Model.warnings. Raises InputError with the CLI's
one-line message (naming the file and line / JSON path). An open mesh is accepted with a warning
(inside where its generalized winding number has |w| > 1/2); closed_only=True refuses it.)";

inline constexpr const char* kBox =
    R"(Axis-aligned box [min, max] (3 numbers each, min < max on every axis).)";
inline constexpr const char* kSphere =
    R"(UV sphere inscribed in the sphere (center, radius): `segments` longitudes (3..4096),
segments/2 latitude bands.)";
inline constexpr const char* kCylinder =
    R"(Cylinder from `base` to `top` with a regular `segments`-gon cross-section inscribed
in the circle of `radius`.)";
inline constexpr const char* kPoints =
    R"(A point-set leaf: the set where the oriented cloud's winding number exceeds 1/2.

P float (n, 3); N (n, 3) normals, or None to estimate them (PCA of the `neighbours` nearest
points, oriented along a minimum spanning tree from the point of largest x, pointed to +x).
Each point becomes a dipole of its tangent-plane Voronoi area (Barill et al. 2018), carried as
one small triangle: the Model is an open leaf answered by the generalized winding number, as
the scene's "points" node. Raises InputError for fewer than neighbours + 1 points, a zero normal,
or neighbours outside 3..64.)";

inline constexpr const char* kMesh = R"(A leaf from a triangle mesh given as arrays.

V: array-like (n, 3) of coordinates (used without a copy when float64 C-contiguous); F:
integer array-like (m, 3) of vertex indices, counter-clockwise seen from outside (an
inside-out mesh is flipped, with a warning). Raises ValueError for a wrong shape, TypeError
for non-integer F, InputError for an index out of range, a non-orientable mesh, or
(closed_only=True) an open mesh; otherwise an open mesh is inside where its generalized
winding number has |w| > 1/2.)";

inline constexpr const char* kFfd =
    R"(Free-form deformation (Sederberg-Parry) of a mesh: (V, F, report).

A trivariate Bernstein lattice of `degree` (l, m, n) over the box [lattice_min, lattice_max] with
control `points` ((l+1)(m+1)(n+1), 3), index ((i*(m+1)) + j)*(n+1) + k, i along x; the
undeformed lattice is the identity. Every vertex of the mesh must lie in the box. The mesh is
triangulated and refined (each triangle into 4) until the certified chord bound 0.5*M*e^2 is at
most `tolerance` (0: 1e-3 of the box's diagonal), M bounding the map's second derivatives from
the control points' second differences; report: levels, chord_bound. As the scene's "ffd" node.)";

inline constexpr const char* kSubdivide =
    R"(`levels` rounds of a subdivision scheme on a polygon mesh: returns (V, F).

V: array-like (n, 3) of coordinates; F: an integer array-like (m, k) of vertex indices (every
face of k vertices) or a list of index lists (faces of mixed degrees), counter-clockwise seen
from outside. scheme: "catmull-clark" (any polygons in, quads out), "doo-sabin" (any polygons,
dual), "loop" or "sqrt3" (triangles in and out). levels: 0 returns the input. exact_rounding:
every new point the correctly rounded value of its stencil evaluated exactly. The result's V is
float64 (n', 3); its F is int64 (m', k') when every face has k' vertices (always for
catmull-clark, loop and sqrt3; an empty result: (0, 3)), else a list of lists of int (doo-sabin
in general). Vertex and face order as cover::subdivide (docs/library.md), identical to
`cover subdivide`. Raises ValueError for a wrong shape, TypeError for non-integer F, InputError
for an index out of range, a face with fewer than 3 vertices or repeating a vertex, a
non-manifold or inconsistently oriented mesh, a non-triangle face for loop or sqrt3, an unknown
scheme, levels < 0 or an output beyond 2^30 vertices or face entries.

uv (keyword): face-varying attributes (texture coordinates, colours), float (corners, k) with
one row per corner of F in face order, or (m, n, k) for faces of n vertices; the result is then
(V, F, UV) with UV float64 (corners', k) for the result's corners. They are interpolated within
each face, never smoothed (cover::CornerAttributes): corners at old vertices keep their values,
edge points take the mean of the edge's two corners in that face, face points the face's mean;
doo-sabin applies its own mask within the face; seams stay seams.)";

inline constexpr const char* kOctree =
    R"(A direct octree (as `cover octree`): nodes breadth-first, an inner node's 8 children
consecutive from first_child (Morton order: child c at offset (c&1, (c>>1)&1, (c>>2)&1) along
x, y, z). Arrays per node: first_child uint32 (0 for a leaf), level uint8, state uint8 (0 empty,
1 full, 2 partial), occupancy float32 (partial leaves: the share of their samples^3 sub-points
inside); depth, bounds (xmin, ymin, zmin, size), leaf_counts; save(path) writes it.)";

inline constexpr const char* kOctreeSave =
    R"(Writes the octree as the CLI does, by extension: .htg (VTK HyperTreeGrid XML), .bt
(OctoMap binary; cells with occupancy >= threshold are occupied; the cube must lie on OctoMap's
grid: build the tree with bounds="octomap") or .json; atomically.)";

inline constexpr const char* kOctreeMethod =
    R"(The direct octree of the result (octree/octree.h, as `cover octree`): cells no
surface meets become full or empty leaves, the others split down to depth (0..16); partial
leaves carry the occupancy of samples^3 sub-points. bounds: (xmin, ymin, zmin, size), None for
voxel_bounds(2^depth), or "octomap" for the cube on OctoMap's grid that a .bt needs (the one
`cover octree -o x.bt` picks). An estimate over max_memory MiB raises InputError before
building.)";

inline constexpr const char* kWriteVoxels =
    R"(Writes a voxel grid (bool or 0/1, shape (NX, NY, NZ) indexed [x, y, z], as
Model.voxelize returns) in the CLI's formats, by extension: .binvox (cubic grids), .vti, .npy,
.raw (with its .raw.json sidecar), .zarr (a Zarr v2 store of chunk³ chunks, as `cover voxelize
-o OUT.zarr --chunk`) or .vdb; atomically, as `cover voxelize` writes them. The grid's place is
bounds = (xmin, ymin, zmin, size) for a cubic grid (Model.voxel_bounds(res)) or lattice =
Model.voxel_lattice(...) (or (origin, spacing)) for any grid; .vti, .raw, .zarr and .vdb record
it.)";

inline constexpr const char* kVoxelLattice =
    R"(The grid voxelize(res, bounds, voxel_size=, dims=) covers, with the same arguments:
cover.VoxelLattice(origin, spacing, dims, cube_size), voxel (i, j, k) centred at origin +
(i + 1/2, j + 1/2, k + 1/2) * spacing; write_voxels(path, grid, lattice=...) takes it.)";

inline constexpr const char* kScene =
    R"(A Model from a JSON scene given as a dict (or its JSON text): every node kind a scene
file takes (mesh, box, sphere, cylinder, field, blend with point, segment, triangle, polyline,
circle and mesh skeletons, twist, taper, bend, points, subdivide, ffd, union, intersection,
difference, complement, transforms; docs/cli.md "Input"). Relative file paths resolve against
base (default: the working directory). Raises InputError naming the node's JSON path.)";

inline constexpr const char* kWritePng =
    R"(Writes an RGB image (uint8 (height, width, 3), as Model.render() returns) as a PNG file,
atomically (a temporary beside it, then renamed), as `cover render` writes its frames.)";

inline constexpr const char* kLeafColours =
    R"(uint8 (leaves, 3): each leaf's display colour, RGB: the scene's "color" of the leaf's node or
its nearest ancestor with one, else the render palette's colour of its index. What render() draws
and `cover evaluate` writes into glTF and 3MF materials.)";

inline constexpr const char* kWriteMesh =
    R"(Writes a mesh file, atomically (a temporary beside the target, then renamed).

The format follows the extension: .off, .obj, .stl, .ply, .gltf, .glb or .3mf (docs/cli.md
"Mesh formats written"). V, F as for subdivide(). leaf_ids (optional, an integer per face, e.g.
the third result of Model.evaluate(leaf_ids=True)): .ply gets a face property `int leaf`, .obj
a group per leaf, .gltf / .glb / .3mf a material per leaf in its colour: colours[leaf] when given
(a (leaves, 3) uint8 array such as Model.leaf_colours), else the render palette's; .off and .stl
cannot hold them (InputError). Raises InputError for an unsupported extension, an index out of
range, a non-finite coordinate or a file that cannot be written.)";

inline constexpr const char* kModify =
    R"(Modeling operations on a closed mesh (the DLFL modeler): returns (V, F).

V, F as for subdivide(); the mesh must be closed, oriented and manifold. operations: the JSON
text of `cover modify --ops` (docs/cli.md "Modeling"), or the same as Python objects (a list of
one-key dicts, or {"operations": [...]}), e.g. [{"pipe": {"faces": [1, 0], "segments": 2}},
{"subdivide": {"levels": 2}}]. Faces, edges and vertices are ids or points [x, y, z] near
them. Every operation is built from the DLFL's minimal operators, so the result is an
orientable 2-manifold. The result's F is int64 (m', k') when every face has k' vertices, else a
list of lists of int. Raises InputError naming the operation's JSON path for a bad operation,
and for an open, non-manifold or inconsistently oriented mesh.)";

inline constexpr const char* kHalfedgeMesh =
    R"(A closed orientable 2-manifold mesh in the DLFL modeler, edited in place.

HalfedgeMesh(V, F): V, F as for subdivide(); the mesh must be closed, oriented and manifold.
Elements are named by id (the input's vertex and face indices until an operation renumbers) or
by a point [x, y, z] near them (the face whose centroid, the edge whose midpoint, the vertex
nearest to it). The minimal operators: create_vertex(p) -> id (a point-sphere),
delete_vertex(v), insert_edge(c1, c2) between corners (face, vertex) or a point-sphere's vertex,
delete_edge(e); and remove_edge(e), subdivide_edge(e, points=1), pipe(f1, f2, segments=1,
twist=0.0 degrees, curved=False, weights=(1, 1), path=None: points the curved centre passes
through), extrude(face, distance, kind="straight"|"cubical"|"dodecahedral"|"stellate"|
"dome"), truncate(vertex, fraction=0.25), apply(operations) (a `cover modify` script).
vertex_count, edge_count, face_count, genus, components; arrays() -> (V, F); check() raises
when an invariant is broken. Operators raise InputError naming the problem.)";

}  // namespace cover::python::doc
