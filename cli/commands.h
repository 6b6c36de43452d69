#pragma once
// The `cover` subcommands (docs/cli.md#commands). Each returns the process exit status and
// throws InputError / NotComputable for bad input (exit 2, handled in main.cpp). Conventions:
// a command estimates what it allocates and refuses estimates over --max-memory first
// (solid/memory_limit.h); one OutputBatch (io/atomic_file.h) holds all of its output files,
// committed after the last one is written and before anything is printed, so a failure leaves
// every existing file as it was.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cover/io/scene.h"
#include "cover/model/model.h"
#include "cover/solid/memory_limit.h"

namespace cover::cli {

struct CommonOptions {
  bool json = false;                               ///< print exactly one JSON object on stdout
  bool quiet = false;                              ///< no progress bars
  int threads = 0;                                 ///< 0: all cores
  uint64_t max_memory_mib = kDefaultMaxMemoryMiB;  ///< --max-memory: refuse estimates above it
  bool closed_only = false;  ///< --closed-only: refuse open leaves (else the winding-number rule)

  uint64_t max_memory_bytes() const { return max_memory_mib << 20; }
  /// How every command loads INPUT: each input file within the memory limit.
  LoadOptions load_options() const {
    LoadOptions options;
    options.max_file_bytes = max_memory_bytes();
    options.require_closed = closed_only;
    return options;
  }
};

/// Loads INPUT as every command does (cover::load with the --max-memory file limit, or `options`)
/// and prints its warnings on stderr ("cover: warning: ..."). For a command that refuses open
/// leaves, `closed_needed` gives the reason: an open leaf is then refused at once with InputError
/// "LEAF: open mesh (N boundary edges): REASON", and no warning is printed; so is a field leaf
/// ("INPUT: /json/path: field leaf: REASON", "closed leaves" reading "closed mesh leaves"), or
/// with `field_reason` where that is given.
/// `curved_ok`: a tree with field or warp leaves is accepted whole (open leaves beside them too).
Model load_model(const std::string& input, const LoadOptions& options,
                 const std::string& closed_needed = {}, const std::string& field_reason = {},
                 bool curved_ok = false);

struct InfoOptions {
  std::string input;
  bool check_self_intersection = true;  ///< --no-self-intersection skips the (exact) check
};

struct VolumeCommandOptions {
  std::string input;
  bool exact = false;  ///< --exact
  long rays = 0;       ///< --rays N (ray-integration resolution; 0 = default)
  /// --tolerance t: relative target of the ray and bracket methods (default 1e-4 and 1e-2)
  std::optional<double> tolerance;
};

struct ClassifyCommandOptions {
  std::string input;
  std::string points;  ///< file or "-"
  std::string output;  ///< --output OUT.npy: the classes as uint8 codes instead of words on stdout
};

struct DistanceCommandOptions {
  std::string input;
  std::string points;  ///< file or "-"
  std::string output;  ///< --output D.npy: float64 (N,) instead of lines on stdout
};

struct FieldCommandOptions {
  std::string input;
  std::string points;  ///< file or "-"
};

struct RenderCommandOptions {
  std::string input;
  std::string output;  ///< -o OUT.png
  std::string size = "800x600";
  std::string view = "iso";
  bool perspective = false;
  std::string section;  ///< "nx,ny,nz,d" or empty
  std::string depth;    ///< --depth D.png
  std::string ids;      ///< --ids I.png
  std::string background = "255,255,255";
  bool outline = true;
  int samples = 2;                  ///< --samples S: S×S rays per pixel (anti-aliasing), 1 to 4
  double crease = 30;               ///< --crease DEG: smooth shading below it (0: flat)
  std::string up = "z";             ///< --up x|y|z: the axis shown upright
  std::optional<double> elevation;  ///< --elevation DEG (default: the view's)
  double azimuth = 0;               ///< --azimuth DEG: the view turned about the up axis
  double zoom = 1;                  ///< --zoom F (> 1 magnifies)
  std::string pan;                  ///< --pan X,Y: the view moved by image widths, heights
  bool fit = false;                 ///< --fit: frame what --section keeps
  int turntable = 0;                ///< --turntable N: N frames OUT_000.png ... around the up axis
  std::string views;                ///< --views iso,front,...: one frame per view, OUT_iso.png ...
};

struct ViewCommandOptions {
  std::string input;
  std::string host = "127.0.0.1";  ///< --host
  int port = 0;                    ///< --port (0: any free port)
  double poll = 0.5;               ///< --poll SECONDS between checks of the files
};

struct VoxelizeCommandOptions {
  std::string input;
  std::string output;     ///< -o OUT.(binvox|vti|npy|raw|zarr|vdb)
  int res = 0;            ///< --res N (0: not given; then --voxel-size or --dims)
  std::string bounds;     ///< --bounds xmin,ymin,zmin,size
  double voxel_size = 0;  ///< --voxel-size h (0: not given)
  std::string dims;       ///< --dims NX,NY,NZ
  int chunk = 128;        ///< --chunk C (.zarr)
  std::string surface;    ///< --surface OUT.(obj|stl|off|ply)
};

struct OctreeCommandOptions {
  std::string input;
  std::string output;  ///< -o OUT.(htg|bt|json)
  int depth = 0;       ///< --depth D
  std::string bounds;
  double threshold = 0.5;
};

struct ClipCommandOptions {
  std::string input;
  std::string plane;         ///< --plane nx,ny,nz,d
  std::string output;        ///< -o ABOVE (mesh or .json scene)
  std::string below;         ///< --below BELOW (same kind as ABOVE)
  bool triangulate = false;  ///< --triangulate: triangle caps instead of convex polygons
};

struct EvaluateCommandOptions {
  std::string input;
  std::string output;     ///< -o OUT.(off|obj|stl|ply)
  bool leaf_ids = false;  ///< --leaf-ids: each face's source leaf (PLY face property, OBJ groups)
  int cells = 0;          ///< --cells N: through N×N×N cells (0: plain evaluation)
  std::string pieces;     ///< --pieces DIR: DIR/cell_I_J_K.ext and DIR/pieces.json (with --cells)
  std::string bounds;     ///< --bounds xmin,ymin,zmin,size: the cells' cube (with --cells)
  int mesh_resolution = 128;  ///< --mesh-resolution: field, warp and open leaves' grid
  double mesh_tolerance = 0;  ///< --mesh-tolerance: their vertices' distance (0: cell/1024)
};

struct PolygonizeCommandOptions {
  std::string input;
  std::string output;    ///< -o OUT (any mesh format)
  int resolution = 128;  ///< --resolution: cells along the largest extent, at least
  double cell_size = 0;  ///< --cell-size: the step instead (a power of two at most this)
  double tolerance = 0;  ///< --tolerance: every vertex's distance from the surface (0: h/1024)
};

struct DecomposeCommandOptions {
  std::string input;
  std::string output;        ///< -o DIR: piece_NNNN.EXT and pieces.json
  std::string ext = ".off";  ///< --ext: the pieces' mesh format
};

struct SubdivideCommandOptions {
  std::string input;                     ///< a mesh file
  std::string output;                    ///< -o OUT.(off|obj|stl|ply)
  std::string scheme = "catmull-clark";  ///< --scheme: catmull-clark, doo-sabin, loop or sqrt3
  int levels = 1;                        ///< --levels N
  bool exact_rounding = false;           ///< --exact-rounding
  bool check_self_intersection = true;   ///< --no-self-intersection skips the (exact) check
};

/// `cover modify`, `cover pipe`, `cover extrude`: modeling operations on a closed mesh
/// (modeler/script.h). `modify` applies a recorded script; `pipe` and `extrude` are one-step
/// scripts built from their flags.
struct ModifyCommandOptions {
  std::string input;                    ///< a closed mesh file
  std::string output;                   ///< -o OUT.(off|obj|stl|ply)
  std::string ops;                      ///< modify: --ops FILE.json
  std::vector<int> faces;               ///< pipe: --faces F1,F2; extrude: --face F
  std::vector<double> near;             ///< --near x,y,z[,x,y,z]: faces by a point near them
  int segments = 1;                     ///< pipe: --segments
  double twist = 0;                     ///< pipe: --twist DEG (rounded to whole corners)
  bool curved = false;                  ///< pipe: --curved (a Hermite handle)
  std::vector<double> weights;          ///< pipe: --weights W1,W2 (end tangents)
  std::vector<double> through;          ///< pipe: --through x,y,z (repeatable): path points
  double distance = 0;                  ///< extrude: --distance
  std::string kind = "straight";        ///< extrude: --kind (straight, cubical, ...)
  bool check_self_intersection = true;  ///< --no-self-intersection skips the (exact) check
};

/// A library parameter's flag, for InputError messages and warnings (InputError::text,
/// Model::warnings): "--" and the name with '-' for '_', where the flag is not shorter or named
/// otherwise.
std::string flag_of(std::string_view name);

int run_info(const InfoOptions& o, const CommonOptions& common);
int run_volume(const VolumeCommandOptions& o, const CommonOptions& common);
int run_classify(const ClassifyCommandOptions& o, const CommonOptions& common);
int run_field(const FieldCommandOptions& o, const CommonOptions& common);
int run_render(const RenderCommandOptions& o, const CommonOptions& common);
int run_view(const ViewCommandOptions& o, const CommonOptions& common);
int run_voxelize(const VoxelizeCommandOptions& o, const CommonOptions& common);
/// `cover clip`: ABOVE = solid ∩ {n·x ≥ d}, BELOW = solid ∩ {n·x ≤ d}, capped.
int run_clip(const ClipCommandOptions& o, const CommonOptions& common);
int run_octree(const OctreeCommandOptions& o, const CommonOptions& common);
int run_evaluate(const EvaluateCommandOptions& o, const CommonOptions& common);
/// `cover evaluate --cells N`: the result cut into N³ cells and glued back (brep/cells.h).
int run_evaluate_cells(const EvaluateCommandOptions& o, const CommonOptions& common);
/// `cover decompose`: exact convex pieces by reflex-edge plane cuts (brep/decompose.h).
int run_decompose(const DecomposeCommandOptions& o, const CommonOptions& common);
/// `cover distance`: signed distances to the result's boundary (Model::distance).
int run_distance(const DistanceCommandOptions& o, const CommonOptions& common);
/// `cover polygonize`: the whole result by certified marching tetrahedra (polygonize/).
int run_polygonize(const PolygonizeCommandOptions& o, const CommonOptions& common);
/// `cover subdivide`: `levels` rounds of a subdivision scheme on a mesh (subdivision/subdivide.h).
int run_subdivide(const SubdivideCommandOptions& o, const CommonOptions& common);
/// `cover modify` / `pipe` / `extrude` (`command` names which; modeler/script.h).
int run_modify(std::string_view command, const ModifyCommandOptions& o,
               const CommonOptions& common);

}  // namespace cover::cli
