// `cover`: command-line front end (docs/cli.md). Exit status: 0 success, 2 bad input or usage
// (one line "cover: error: ..." on stderr), 1 internal failure.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <new>
#include <sstream>
#include <string>
#include <string_view>

#include "cover/cli/commands.h"
#include "cover/io/atomic_file.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace {

int fail(int status, const std::string& what) {
  std::fprintf(stderr, "cover: error: %s\n", what.c_str());
  return status;
}

/// A command-line value for a message: in single quotes, control bytes as '?' (one line).
std::string shown(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  return "'" + text + "'";
}

/// Transform for an integer option: a whole number from lo to hi (a leading '+' allowed, as in
/// the readers), rewritten in plain decimal so that CLI11 never reads it as octal or hex. CLI11
/// prefixes the message with the option's name: "--res: expected a whole number from 1 to
/// 4096, got 'abc'"; with no upper limit, "--rays: expected a positive whole number, got '0'".
CLI::Validator whole_number(long long lo, long long hi = std::numeric_limits<int>::max()) {
  const bool positive = lo == 1 && hi == std::numeric_limits<int>::max();
  const std::string expected =
      positive ? "a positive whole number"
               : "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        std::string_view digits = text;
        if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
        long long value = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec != std::errc() || end != digits.data() + digits.size() || value < lo || value > hi)
          return "expected " + expected + ", got " + shown(text);
        text = std::to_string(value);
        return "";
      },
      positive ? "POSITIVE" : "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

/// Check for a real option: a finite number from lo to hi ("--threshold: expected a number from
/// 0 to 1, got 'x'").
CLI::Validator real_number(double lo, double hi) {
  std::ostringstream range;
  range << lo << " to " << hi;
  const std::string expected = "a number from " + range.str();
  std::ostringstream help;
  help << "FLOAT in [" << lo << " - " << hi << "]";
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        std::string_view digits = text;
        if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
        double value = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec != std::errc() || end != digits.data() + digits.size() ||
            !(value >= lo && value <= hi))
          return "expected " + expected + ", got " + shown(text);
        return "";
      },
      help.str());
}

/// Check for a positive real option: a finite number > 0 ("--zoom: expected a positive number,
/// got '0'").
CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string_view digits = text;
        if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
        double value = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (ec != std::errc() || end != digits.data() + digits.size() || !(value > 0) ||
            !std::isfinite(value))
          return "expected a positive number, got " + shown(text);
        return "";
      },
      "POSITIVE FLOAT");
}

/// Check for a path or list option: not empty ("--pieces: expected a folder, got ''"); an empty
/// value would otherwise read as "not given".
CLI::Validator non_empty(const std::string& expected) {
  return CLI::Validator(
      [expected](std::string& text) -> std::string {
        return text.empty() ? "expected " + expected + ", got ''" : "";
      },
      "NON-EMPTY");
}

void add_common(CLI::App* cmd, cover::cli::CommonOptions& common) {
  cmd->add_flag("--json", common.json, "Print exactly one JSON object on stdout");
  cmd->add_flag("--quiet", common.quiet, "No progress bars");
  cmd->add_option("--threads", common.threads, "Worker threads (default: all cores)")
      ->transform(whole_number(1, 4096));
  cmd->add_option("--max-memory", common.max_memory_mib,
                  "Refuse work estimated to need more MiB (inputs, images, grids, octrees)")
      ->capture_default_str()
      ->transform(whole_number(1));
  cmd->add_flag("--closed-only", common.closed_only,
                "Refuse open meshes (exit 2) instead of using the generalized winding number");
}

/// "unknown command 'bogus' (expected info, volume, ...)" when the first argument names no
/// command (CLI11 would say only "A subcommand is required"); empty when it does or is an option.
std::string unknown_command(const CLI::App& app, int argc, char** argv) {
  std::string names;
  bool known = false;
  for (const CLI::App* cmd : app.get_subcommands([](const CLI::App*) { return true; })) {
    names += (names.empty() ? "" : ", ") + cmd->get_name();
    known = known || (argc > 1 && cmd->check_name(argv[1]));
  }
  if (argc > 1 && (known || argv[1][0] == '-')) return "";
  if (argc <= 1) return "no command given (expected " + names + "; try --help)";
  return "unknown command " + shown(argv[1]) + " (expected " + names + ")";
}

}  // namespace

int main(int argc, char** argv) {
  cover::remove_temporaries_on_signals();  // first: threads started later inherit its mask
  CLI::App app{"cover: CSG solids by simplicial coverings (exact volume, classification)"};
  app.set_version_flag("--version", "cover " COVER_VERSION);
  app.require_subcommand(1);

  cover::cli::CommonOptions common;

  cover::cli::InfoOptions info;
  CLI::App* info_cmd = app.add_subcommand("info", "Validate and describe a mesh or scene");
  info_cmd->add_option("INPUT", info.input, "Mesh (.obj .off .stl .ply) or scene (.json)")
      ->required();
  info_cmd->add_flag("!--no-self-intersection", info.check_self_intersection,
                     "Skip the exact self-intersection check");
  add_common(info_cmd, common);

  cover::cli::VolumeCommandOptions vol;
  CLI::App* vol_cmd = app.add_subcommand("volume", "Volume (and area where exact) of the solid");
  vol_cmd->add_option("INPUT", vol.input, "Mesh or scene")->required();
  vol_cmd->add_flag("--exact", vol.exact, "Require an exact method (B-rep evaluation)");
  vol_cmd
      ->add_option("--rays", vol.rays,
                   "Ray integration with fixed finest cells: 1/N of the square (N rounded up to a "
                   "power of two)")
      ->transform(whole_number(1, 2048));
  vol_cmd
      ->add_option("--tolerance", vol.tolerance,
                   "Relative error target of the ray and bracket (field leaves) methods")
      ->check(real_number(1e-12, 1));
  add_common(vol_cmd, common);

  // The points of classify and field (cli/points.h reads them).
  const auto add_points_option = [](CLI::App* cmd, std::string& points) {
    cmd->add_option(
           "--points", points,
           "Points: text (x y z per line; - for stdin) or .npy (float64/float32, shape (N, 3))")
        ->required();
  };
  cover::cli::ClassifyCommandOptions cls;
  CLI::App* cls_cmd =
      app.add_subcommand("classify", "Classify points: inside/outside/face/edge/vertex");
  cls_cmd->add_option("INPUT", cls.input, "Mesh or scene")->required();
  add_points_option(cls_cmd, cls.points);
  cls_cmd->add_option(
      "--output", cls.output,
      "Write the classes to OUT.npy (uint8 (N,): outside 0, inside 1, face 2, edge 3, "
      "vertex 4) instead of printing them; --json then prints counts and seconds only");
  add_common(cls_cmd, common);

  cover::cli::DistanceCommandOptions dst;
  CLI::App* dst_cmd = app.add_subcommand(
      "distance", "Signed distance of points to the result's boundary (negative inside)");
  dst_cmd->add_option("INPUT", dst.input, "Mesh or scene")->required();
  add_points_option(dst_cmd, dst.points);
  dst_cmd->add_option("--output", dst.output,
                      "Write the distances to OUT.npy (float64 (N,)) instead of printing them");
  add_common(dst_cmd, common);

  cover::cli::FieldCommandOptions fld;
  CLI::App* fld_cmd =
      app.add_subcommand("field", "Field value f and gradient of each field leaf at points");
  fld_cmd->add_option("INPUT", fld.input, "Scene with field leaves")->required();
  add_points_option(fld_cmd, fld.points);
  add_common(fld_cmd, common);

  cover::cli::RenderCommandOptions ren;
  CLI::App* ren_cmd =
      app.add_subcommand("render", "Ray-cast preview PNG of the non-evaluated solid");
  ren_cmd->add_option("INPUT", ren.input, "Mesh or scene")->required();
  ren_cmd->add_option("-o,--output", ren.output, "Output PNG")
      ->required()
      ->check(non_empty("a file"));
  ren_cmd->add_option("--size", ren.size, "Image size WxH")->capture_default_str();
  ren_cmd->add_option("--view", ren.view, "iso, front, back, left, right, top or bottom")
      ->capture_default_str();
  ren_cmd->add_flag("--perspective", ren.perspective, "Perspective camera (default orthographic)");
  ren_cmd->add_option("--section", ren.section, "Remove n.x > d and show the cut: nx,ny,nz,d");
  ren_cmd->add_option("--depth", ren.depth, "Also write 16-bit depth PNG")
      ->check(non_empty("a file"));
  ren_cmd->add_option("--ids", ren.ids, "Also write 16-bit leaf-id PNG (0 background, 65535 cap)")
      ->check(non_empty("a file"));
  ren_cmd->add_option("--background", ren.background, "Background colour r,g,b (0-255)")
      ->capture_default_str();
  ren_cmd->add_flag("!--no-outline", ren.outline, "Do not outline silhouettes and creases");
  ren_cmd->add_option("--samples", ren.samples,
                      "Anti-aliasing: SxS rays per pixel, S from 1 to 4 (default 2; 1: none)");
  ren_cmd
      ->add_option("--crease", ren.crease,
                   "Smooth shading where faces meet at less than DEG (0: flat shading)")
      ->capture_default_str()
      ->check(real_number(0, 180));
  ren_cmd->add_option("--up", ren.up, "The axis shown upright: x, y or z (Y-up scans: y)")
      ->capture_default_str();
  ren_cmd
      ->add_option("--elevation", ren.elevation,
                   "The eye's angle above the horizontal plane in DEG (default: the view's; "
                   "iso 35.26)")
      ->check(real_number(-90, 90));
  ren_cmd
      ->add_option("--azimuth", ren.azimuth,
                   "Turn the view about the up axis by DEG (counter-clockwise from above)")
      ->check(real_number(-360, 360));
  ren_cmd->add_option("--zoom", ren.zoom, "Magnify by F about the image centre (F > 1: larger)")
      ->capture_default_str()
      ->check(positive_number());
  ren_cmd->add_option("--pan", ren.pan,
                      "Move the view by X image widths right and Y heights up: X,Y");
  ren_cmd->add_flag("--fit", ren.fit, "Frame the part --section keeps instead of the whole model");
  auto* turntable = ren_cmd
                        ->add_option("--turntable", ren.turntable,
                                     "N frames around the up axis, one framing: "
                                     "OUT_000.png ... (one load, one BVH)")
                        ->transform(whole_number(1, 3600));
  ren_cmd
      ->add_option("--views", ren.views,
                   "Frames from several views, e.g. iso,front,top: OUT_iso.png ... "
                   "(one load, one BVH)")
      ->check(non_empty("views, e.g. iso,front,top"))
      ->excludes(turntable);
  add_common(ren_cmd, common);

  cover::cli::ViewCommandOptions viw;
  CLI::App* viw_cmd = app.add_subcommand(
      "view", "Browser viewer of exact frames: orbit, section, leaves, picks, auto-reload");
  viw_cmd->add_option("INPUT", viw.input, "Mesh or scene")->required();
  viw_cmd->add_option("--host", viw.host, "Interface to listen on")
      ->capture_default_str()
      ->check(non_empty("an address"));
  viw_cmd->add_option("--port", viw.port, "Port (0: any free port)")
      ->capture_default_str()
      ->transform(whole_number(0, 65535));
  viw_cmd->add_option("--poll", viw.poll, "Seconds between checks of the files for changes")
      ->capture_default_str()
      ->check(real_number(0.05, 3600));
  add_common(viw_cmd, common);

  cover::cli::VoxelizeCommandOptions vox;
  CLI::App* vox_cmd = app.add_subcommand("voxelize", "Voxelize the solid (presence buffer)");
  vox_cmd->add_option("INPUT", vox.input, "Mesh or scene")->required();
  CLI::Option* vox_res =
      vox_cmd
          ->add_option("--res", vox.res,
                       "Voxels per axis (cubic grid; up to 4096, 16384 for .zarr)")
          ->transform(whole_number(1, 16384));
  CLI::Option* vox_size =
      vox_cmd
          ->add_option("--voxel-size", vox.voxel_size,
                       "Spacing h of a grid over the box (dims = ceil(extent / h))")
          ->check(CLI::Validator(
              [](std::string& text) -> std::string {
                double value = 0;
                const auto [end, ec] =
                    std::from_chars(text.data(), text.data() + text.size(), value);
                if (ec != std::errc() || end != text.data() + text.size() || !(value > 0) ||
                    !std::isfinite(value))
                  return "expected a finite number > 0, got " + shown(text);
                return "";
              },
              "FLOAT > 0"))
          ->excludes(vox_res);
  vox_cmd->add_option("--dims", vox.dims, "NX,NY,NZ: voxel counts of a grid over the box")
      ->excludes(vox_res)
      ->excludes(vox_size);
  vox_cmd->add_option("-o,--output", vox.output, "OUT.binvox, .vti, .npy, .raw, .zarr or .vdb")
      ->required();
  vox_cmd->add_option("--bounds", vox.bounds,
                      "Grid cube xmin,ymin,zmin,size (default: the box, cubic)");
  vox_cmd->add_option("--chunk", vox.chunk, "Zarr chunk edge C (default 128)")
      ->transform(whole_number(1, 16384));
  vox_cmd
      ->add_option("--surface", vox.surface,
                   "Also write the blocky boundary mesh (.obj .stl .off .ply)")
      ->check(non_empty("a file"));
  add_common(vox_cmd, common);

  cover::cli::OctreeCommandOptions oct;
  CLI::App* oct_cmd =
      app.add_subcommand("octree", "Direct octree generation (exact full/empty cells)");
  oct_cmd->add_option("INPUT", oct.input, "Mesh or scene")->required();
  oct_cmd->add_option("--depth", oct.depth, "Maximum depth")
      ->required()
      ->transform(whole_number(0, 16));
  oct_cmd->add_option("-o,--output", oct.output, "OUT.htg, .bt or .json")->required();
  oct_cmd->add_option("--bounds", oct.bounds, "Octree cube xmin,ymin,zmin,size");
  oct_cmd
      ->add_option("--threshold", oct.threshold,
                   "Occupancy deciding partial cells where a format needs yes/no")
      ->capture_default_str()
      ->check(real_number(0, 1));
  add_common(oct_cmd, common);

  cover::cli::ClipCommandOptions clp;
  CLI::App* clp_cmd =
      app.add_subcommand("clip", "Exact plane clip; both halves capped (closed 2-manifolds)");
  clp_cmd->add_option("INPUT", clp.input, "Mesh or scene")->required();
  clp_cmd->add_option("--plane", clp.plane, "Plane nx,ny,nz,d (ABOVE: n.x >= d)")->required();
  clp_cmd->add_option("-o,--output", clp.output, "ABOVE: mesh (.off .obj .stl .ply) or .json scene")
      ->required();
  clp_cmd->add_option("--below", clp.below, "Also write BELOW (same kind as ABOVE)")
      ->check(non_empty("a file"));
  clp_cmd->add_flag("--triangulate", clp.triangulate,
                    "Triangulate caps (default: convex polygons)");
  add_common(clp_cmd, common);

  cover::cli::EvaluateCommandOptions eva;
  CLI::App* eva_cmd =
      app.add_subcommand("evaluate", "The CSG result as one closed 2-manifold mesh (B-rep)");
  eva_cmd->add_option("INPUT", eva.input, "Mesh or scene")->required();
  eva_cmd->add_option("-o,--output", eva.output, "OUT.off, .obj, .stl or .ply")->required();
  eva_cmd->add_flag(
      "--leaf-ids", eva.leaf_ids,
      "Each face's source leaf index i: PLY face property 'leaf', OBJ groups 'g leaf_<i>'");
  eva_cmd
      ->add_option("--cells", eva.cells,
                   "Evaluate through N×N×N cells (plane clip and patch); OUT = the pieces glued")
      ->transform(whole_number(1));
  eva_cmd
      ->add_option("--pieces", eva.pieces,
                   "With --cells: write DIR/cell_I_J_K.ext (closed pieces) and DIR/pieces.json")
      ->check(non_empty("a folder"));
  eva_cmd->add_option(
      "--bounds", eva.bounds,
      "With --cells: the cells' cube xmin,ymin,zmin,size (default: the box, cubic)");
  eva_cmd
      ->add_option("--mesh-resolution", eva.mesh_resolution,
                   "Field, warp and open leaves are meshed first: cells along each one's box")
      ->capture_default_str()
      ->transform(whole_number(2));
  eva_cmd
      ->add_option("--mesh-tolerance", eva.mesh_tolerance,
                   "Their vertices' largest distance from the surface (0: the cell size / 1024)")
      ->check(CLI::NonNegativeNumber);
  add_common(eva_cmd, common);

  cover::cli::PolygonizeCommandOptions pol;
  CLI::App* pol_cmd = app.add_subcommand(
      "polygonize", "Certified marching tetrahedra of the whole result (any tree)");
  pol_cmd->add_option("INPUT", pol.input, "Mesh or scene")->required();
  pol_cmd->add_option("-o,--output", pol.output, "OUT mesh (.off .obj .stl .ply .gltf .glb .3mf)")
      ->required();
  pol_cmd
      ->add_option("--resolution", pol.resolution,
                   "Cells along the largest extent, at least (the step is a power of two)")
      ->capture_default_str()
      ->transform(whole_number(2));
  pol_cmd->add_option("--cell-size", pol.cell_size, "The step instead (a power of two ≤ this)")
      ->check(CLI::PositiveNumber);
  pol_cmd
      ->add_option("--tolerance", pol.tolerance,
                   "Every vertex's largest distance from the surface (0: the cell size / 1024)")
      ->check(CLI::NonNegativeNumber);
  add_common(pol_cmd, common);

  cover::cli::DecomposeCommandOptions dec;
  CLI::App* dec_cmd = app.add_subcommand(
      "decompose", "Exact convex decomposition by plane cuts through reflex edges");
  dec_cmd->add_option("INPUT", dec.input, "Closed mesh or scene (evaluated first)")->required();
  dec_cmd->add_option("-o,--output", dec.output, "DIR: piece_NNNN.EXT and pieces.json")
      ->required()
      ->check(non_empty("a folder"));
  dec_cmd->add_option("--ext", dec.ext, "Pieces' mesh format: .off, .obj or .ply (exact doubles)")
      ->capture_default_str();
  add_common(dec_cmd, common);

  cover::cli::SubdivideCommandOptions sub;
  CLI::App* sub_cmd = app.add_subcommand(
      "subdivide", "Subdivision surface: Catmull-Clark, Doo-Sabin, Loop or sqrt3 rounds on a mesh");
  sub_cmd->add_option("INPUT", sub.input, "Mesh (.obj .off .stl .ply)")->required();
  sub_cmd->add_option("-o,--output", sub.output, "OUT.off, .obj, .stl or .ply")->required();
  sub_cmd
      ->add_option("--scheme", sub.scheme,
                   "catmull-clark (quads), doo-sabin (dual), loop or sqrt3 (triangle meshes)")
      ->capture_default_str();
  sub_cmd->add_option("--levels", sub.levels, "Rounds of the scheme (0: the input unchanged)")
      ->capture_default_str()
      ->transform(whole_number(0, 30));
  sub_cmd->add_flag("--exact-rounding", sub.exact_rounding,
                    "Each new point the correctly rounded value of its exact stencil");
  sub_cmd->add_flag("!--no-self-intersection", sub.check_self_intersection,
                    "Skip the exact self-intersection check of the result");
  add_common(sub_cmd, common);

  // Modeling (modeler/script.h): a recorded script, or one pipe / extrusion from flags.
  cover::cli::ModifyCommandOptions mod;
  const auto add_modeling = [&](const char* name, const char* help) {
    CLI::App* cmd = app.add_subcommand(name, help);
    cmd->add_option("INPUT", mod.input, "Closed mesh (.obj .off .stl .ply)")->required();
    cmd->add_option("-o,--output", mod.output, "OUT.off, .obj, .stl or .ply")->required();
    cmd->add_flag("!--no-self-intersection", mod.check_self_intersection,
                  "Skip the exact self-intersection check of the result");
    add_common(cmd, common);
    return cmd;
  };
  CLI::App* mod_cmd = add_modeling("modify", "Apply recorded modeling operations (DLFL) to a mesh");
  mod_cmd->add_option("--ops", mod.ops, "Operations file (JSON; docs/cli.md \"Modeling\")")
      ->required();
  CLI::App* pip_cmd = add_modeling("pipe", "A pipe (handle or tunnel) between two faces");
  pip_cmd->add_option("--faces", mod.faces, "F1,F2: face ids (input face indices)")->delimiter(',');
  pip_cmd
      ->add_option("--near", mod.near,
                   "x,y,z (twice, or six numbers): the faces whose centroids are nearest")
      ->delimiter(',');
  pip_cmd->add_option("--segments", mod.segments, "Edges along the pipe")
      ->capture_default_str()
      ->transform(whole_number(1, 4096));
  pip_cmd->add_option("--twist", mod.twist, "DEG the pipe turns (rounded to whole corners)")
      ->capture_default_str();
  pip_cmd->add_flag("--curved", mod.curved,
                    "A curved handle: the centre on a Hermite curve leaving and entering along "
                    "the faces' normals");
  pip_cmd->add_option("--weights", mod.weights, "W1,W2: the curve's end tangents (default 1,1)")
      ->delimiter(',')
      ->expected(2);
  pip_cmd
      ->add_option("--through", mod.through,
                   "x,y,z (repeatable): points the curved pipe's centre passes through")
      ->delimiter(',');
  CLI::App* ext_cmd = add_modeling("extrude", "Extrude a face along its normal");
  ext_cmd->add_option("--face", mod.faces, "F: a face id (input face index)")->delimiter(',');
  ext_cmd->add_option("--near", mod.near, "x,y,z: the face nearest to a point")->delimiter(',');
  ext_cmd->add_option("--distance", mod.distance, "Distance along the face's normal")->required();
  ext_cmd
      ->add_option("--kind", mod.kind,
                   "straight, cubical (Doo-Sabin), dodecahedral, stellate (a cone) or dome")
      ->capture_default_str();

  if (const std::string unknown = unknown_command(app, argc, argv); !unknown.empty())
    return fail(2, unknown);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(2, e.what());
  }

  try {
    cover::ThreadLimit limit(common.threads);
    if (info_cmd->parsed()) return cover::cli::run_info(info, common);
    if (vol_cmd->parsed()) return cover::cli::run_volume(vol, common);
    if (cls_cmd->parsed()) return cover::cli::run_classify(cls, common);
    if (dst_cmd->parsed()) return cover::cli::run_distance(dst, common);
    if (fld_cmd->parsed()) return cover::cli::run_field(fld, common);
    if (ren_cmd->parsed()) return cover::cli::run_render(ren, common);
    if (viw_cmd->parsed()) return cover::cli::run_view(viw, common);
    if (vox_cmd->parsed()) return cover::cli::run_voxelize(vox, common);
    if (oct_cmd->parsed()) return cover::cli::run_octree(oct, common);
    if (eva_cmd->parsed()) return cover::cli::run_evaluate(eva, common);
    if (clp_cmd->parsed()) return cover::cli::run_clip(clp, common);
    if (dec_cmd->parsed()) return cover::cli::run_decompose(dec, common);
    if (pol_cmd->parsed()) return cover::cli::run_polygonize(pol, common);
    if (sub_cmd->parsed()) return cover::cli::run_subdivide(sub, common);
    if (mod_cmd->parsed()) return cover::cli::run_modify("modify", mod, common);
    if (pip_cmd->parsed()) return cover::cli::run_modify("pipe", mod, common);
    if (ext_cmd->parsed()) return cover::cli::run_modify("extrude", mod, common);
    return fail(2, "no command given (try --help)");
  } catch (const cover::InputError& e) {
    return fail(2, e.text(cover::cli::flag_of));
  } catch (const cover::NotComputable& e) {
    return fail(2, e.what());
  } catch (const std::bad_alloc&) {
    return fail(1, "out of memory");
  } catch (const std::exception& e) {
    return fail(1, std::string("internal error: ") + e.what());
  }
}
