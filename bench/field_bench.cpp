// Field leaves against plain doubles and against the peers' route to a picture (one process, one
// machine, the same thread count):
//   classify   Model::classify of N random points over the support box of a blend of P point
//              primitives (certified: interval filter, then exact rationals), against a plain
//              double evaluation of the same sum with the same support-box pruning and the same
//              parallel loop (`f > T` per point: no certificate)
//   render     Model::render of a W×W picture of a blend of Q segment and point primitives
//              (crossings by certified bisection), against the peers' routes, each a level set
//              of the same field at grid spacing h = (box's longest side) / n, its mesh as a
//              Cover mesh, then a render of that mesh with the same camera (Cover's own mesh
//              render, the fastest mesh renderer at hand), summed: OpenVDB (dense sampling of the
//              n³ cell centres into a FloatGrid, tools::volumeToMesh at the threshold) and, when
//              built with COVER_BENCH_MANIFOLD, Manifold (Manifold::LevelSet of f − T over the
//              box with edge length h, its MeshGL); interleaved, median of 3 each, wall clock
//   octree     (only with --octree D) Model::octree of the same blend at depth D (cells full /
//              empty where interval bounds certify them), against OpenVDB's level set of the same
//              field at the matching resolution: f − T by field::evaluate (doubles) at every voxel
//              centre of the (2^D)³ lattice over the octree's cube into a tools::Dense array,
//              tools::copyFromDense into a FloatGrid, tools::levelSetRebuild (narrow band, half
//              width 3); interleaved, median of 3 each, wall clock
// Usage: field_bench [--points N] [--primitives P] [--render W] [--blend Q] [--grid n]
//                    [--octree D] [--threads T]
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>
#if COVER_BENCH_MANIFOLD
#include <manifold/manifold.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/field/field.h"
#include "cover/model/model.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/polygon_mesh.h"
#include "cover/solid/primitives.h"

namespace {

using bench::Clock;
using bench::since;
using cover::FieldLeaf;
using cover::FieldPrimitive;
using cover::SkeletonKind;
using cover::Vec3;

/// P point primitives with centres uniform in [−2, 2]³, R = 1, r_T = 0.5, n = 2.
FieldLeaf point_blend(int p, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2, 2);
  FieldLeaf f;
  for (int i = 0; i < p; ++i) {
    FieldPrimitive prim;
    prim.kind = SkeletonKind::kPoint;
    prim.points = {{u(rng), u(rng), u(rng)}};
    prim.radius = 0.5;
    prim.influence = 1;
    f.primitives.push_back(prim);
  }
  return f;
}

/// A chain of Q − Q/5 segments on a helix and Q/5 points beside it (r_T/R = 1/2, n = 2).
FieldLeaf chain_blend(int q) {
  FieldLeaf f;
  const int points = q / 5, segments = q - points;
  auto helix = [](double t) { return Vec3{1.5 * std::cos(t), 1.5 * std::sin(t), 0.25 * t - 1.5}; };
  for (int i = 0; i < segments; ++i) {
    FieldPrimitive s;
    s.kind = SkeletonKind::kSegment;
    s.points = {helix(0.3 * i), helix(0.3 * (i + 1))};
    s.radius = 0.25;
    s.influence = 0.5;
    f.primitives.push_back(s);
  }
  for (int i = 0; i < points; ++i) {
    FieldPrimitive p;
    p.kind = SkeletonKind::kPoint;
    const Vec3 c = helix(0.3 * segments * (i + 0.5) / points);
    p.points = {{c.x * 1.25, c.y * 1.25, c.z}};
    p.radius = 0.375;
    p.influence = 0.75;
    f.primitives.push_back(p);
  }
  return f;
}

/// The plain double sum with the support-box test the kernels use (a term is 0 beyond R of its
/// skeleton's box along an axis): what an uncertified evaluation costs.
double plain_f(const FieldLeaf& f, const Vec3& p) {
  double sum = 0;
  for (const FieldPrimitive& prim : f.primitives) {
    const Vec3& c = prim.points[0];
    const double R = prim.influence;
    if ((std::abs(p.x - c.x) > R) | (std::abs(p.y - c.y) > R) | (std::abs(p.z - c.z) > R)) continue;
    const double d2 =
        (p.x - c.x) * (p.x - c.x) + (p.y - c.y) * (p.y - c.y) + (p.z - c.z) * (p.z - c.z);
    if (d2 >= R * R) continue;
    const double x = 1 - d2 / (R * R);
    double g = x;
    for (int k = 1; k < prim.exponent; ++k) g *= x;
    sum += prim.weight * g;
  }
  return sum;
}

cover::Model field_model(FieldLeaf f, const std::string& name) {
  return cover::Model(cover::make_field_leaf(std::move(f), name, "/" + name));
}

/// One run of a peer's route to a picture: seconds per step, and what it made.
struct PeerRun {
  double sample = 0;   // the level set: OpenVDB's dense sampling; Manifold's whole LevelSet
  double mesh = 0;     // OpenVDB's volumeToMesh (inside LevelSet for Manifold)
  double convert = 0;  // the peer's mesh to a Cover mesh leaf (orientation check included)
  double render = 0;   // Cover's mesh render
  size_t quads = 0, triangles = 0, vertices = 0, pixels = 0;
  double volume = 0;       // signed volume of the Cover mesh
  double peer_volume = 0;  // the peer's own volume (Manifold::Volume)
  int status = 0;          // Manifold::Error (0: NoError)
  double total() const { return sample + mesh + convert + render; }
};

/// The run of median total among three.
PeerRun median_run(std::vector<PeerRun> runs) {
  std::sort(runs.begin(), runs.end(),
            [](const PeerRun& a, const PeerRun& b) { return a.total() < b.total(); });
  return runs[runs.size() / 2];
}

/// A mesh leaf with outward faces (reversed where the signed volume is negative); `volume` gets
/// the mesh's signed volume before that.
cover::Model outward_model(cover::PolygonMesh mesh, double& volume) {
  volume = cover::signed_volume(mesh);
  if (volume < 0)
    for (size_t fi = 0; fi < mesh.face_count(); ++fi)
      std::reverse(mesh.face_vertices.begin() + mesh.face_start[fi],
                   mesh.face_vertices.begin() + mesh.face_start[fi + 1]);
  return cover::Model(cover::make_leaf(std::move(mesh), "level set"));
}

size_t covered_pixels(const cover::Image& img) {
  size_t covered = 0;
  for (uint16_t id : img.ids) covered += id != cover::Image::kBackgroundId;
  return covered;
}

}  // namespace

int main(int argc, char** argv) {
  const long n_points = bench::arg(argc, argv, "--points", 1000000);
  const int prims = static_cast<int>(bench::arg(argc, argv, "--primitives", 100));
  const int width = static_cast<int>(bench::arg(argc, argv, "--render", 1024));
  const int blend = static_cast<int>(bench::arg(argc, argv, "--blend", 50));
  const int grid = static_cast<int>(bench::arg(argc, argv, "--grid", 256));
  const int octree_depth = static_cast<int>(bench::arg(argc, argv, "--octree", 0));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  std::printf("threads %d\n", threads);

  // --- classify: certified against plain doubles, interleaved, best of 3 each -----------------
  {
    const FieldLeaf f = point_blend(prims, 7);
    const cover::Model model = field_model(f, "blend");
    const cover::Bbox box = model.solid().leaves[0].bbox;
    std::mt19937_64 rng(1);
    std::vector<Vec3> pts(static_cast<size_t>(n_points));
    for (Vec3& p : pts)
      p = {std::uniform_real_distribution<double>(box.min.x, box.max.x)(rng),
           std::uniform_real_distribution<double>(box.min.y, box.max.y)(rng),
           std::uniform_real_distribution<double>(box.min.z, box.max.z)(rng)};
    const double T = cover::field::threshold(f);
    double best_cert = 1e300, best_plain = 1e300;
    size_t in_cert = 0, in_plain = 0;
    for (int round = 0; round < 3; ++round) {
      auto t0 = Clock::now();
      const auto classes = model.classify(pts);
      best_cert = std::min(best_cert, since(t0));
      in_cert = static_cast<size_t>(
          std::count(classes.begin(), classes.end(), cover::PointClass::kInside));
      t0 = Clock::now();
      std::vector<uint8_t> inside(pts.size());
      cover::parallel_for(pts.size(), 256, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) inside[i] = plain_f(f, pts[i]) > T;
      });
      best_plain = std::min(best_plain, since(t0));
      in_plain = static_cast<size_t>(std::count(inside.begin(), inside.end(), 1));
    }
    std::printf(
        "classify %ld points, blend of %d points: certified %.3f s, plain double %.3f s, ratio "
        "%.2f (inside: %zu certified, %zu plain)\n",
        n_points, prims, best_cert, best_plain, best_cert / best_plain, in_cert, in_plain);
  }

  // --- render: Cover's certified rays against the peers' level set + mesh + mesh render -------
  {
    const FieldLeaf f = chain_blend(blend);
    const cover::Model model = field_model(f, "chain");
    cover::CameraOptions co;
    co.width = co.height = width;
    const cover::Camera cam = model.camera(co);
    const cover::Bbox box = model.solid().leaves[0].bbox;
    const double side =
        std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
    const double h = side / grid;  // both peers' grid spacing
    const double T = cover::field::threshold(f);
    const cover::VolumeResult bracket = model.volume();
    openvdb::initialize();

    // OpenVDB: dense sampling of f − T on the n³ cell centres of the cube [box.min, box.min +
    // side], slab by slab in parallel into per-slab grids, merged (the accessor is not
    // thread-safe); values T − f, negative inside as OpenVDB's level sets; voxels where f = 0
    // keep the background T. Then volumeToMesh at 0.
    auto openvdb_route = [&]() {
      PeerRun run;
      auto t0 = Clock::now();
      const float Tf = static_cast<float>(T);
      auto fgrid = openvdb::FloatGrid::create(Tf);
      fgrid->setTransform(openvdb::math::Transform::createLinearTransform(h));
      std::vector<openvdb::FloatGrid::Ptr> slabs(grid);
      cover::parallel_for(static_cast<size_t>(grid), 1, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
          slabs[i] = openvdb::FloatGrid::create(Tf);
          auto acc = slabs[i]->getAccessor();
          for (int j = 0; j < grid; ++j)
            for (int k = 0; k < grid; ++k) {
              const Vec3 p{box.min.x + (i + 0.5) * h, box.min.y + (j + 0.5) * h,
                           box.min.z + (k + 0.5) * h};
              const float v = static_cast<float>(cover::field::evaluate(f, p).value) - Tf;
              if (v != -Tf) acc.setValue(openvdb::Coord(static_cast<int>(i), j, k), -v);
            }
        }
      });
      for (auto& s : slabs) fgrid->tree().merge(s->tree());
      run.sample = since(t0);
      t0 = Clock::now();
      std::vector<openvdb::Vec3s> points;
      std::vector<openvdb::Vec3I> tris;
      std::vector<openvdb::Vec4I> quads;
      openvdb::tools::volumeToMesh(*fgrid, points, tris, quads, 0.0);
      run.mesh = since(t0);
      fgrid.reset();
      t0 = Clock::now();
      cover::PolygonMesh mesh;
      // World points: voxel (i, j, k) is at (i, j, k)·h, sampled at box.min + (i + ½)·h.
      for (const auto& p : points)
        mesh.vertices.push_back({box.min.x + p.x() + 0.5 * h, box.min.y + p.y() + 0.5 * h,
                                 box.min.z + p.z() + 0.5 * h});
      for (const auto& t : tris) mesh.add_face({t[0], t[1], t[2]});
      for (const auto& q : quads) mesh.add_face({q[0], q[1], q[2], q[3]});
      const cover::Model meshed = outward_model(std::move(mesh), run.volume);
      run.convert = since(t0);
      run.quads = quads.size();
      run.triangles = tris.size();
      t0 = Clock::now();
      run.pixels = covered_pixels(meshed.render(cam));
      run.render = since(t0);
      return run;
    };
#if COVER_BENCH_MANIFOLD
    // Manifold: LevelSet of f − T (positive inside, as LevelSet wants) over the field's box with
    // edge length h (its body-centred grid: (box / h + 1) nodes per axis plus the cell centres),
    // its MeshGL (float positions, CCW from outside) to a Cover mesh.
    const manifold::Box mbox({box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z});
    const manifold::vec3 mdim = mbox.Size();
    const int gx = static_cast<int>(mdim.x / h + 1.0), gy = static_cast<int>(mdim.y / h + 1.0),
              gz = static_cast<int>(mdim.z / h + 1.0);
    auto manifold_route = [&]() {
      PeerRun run;
      auto t0 = Clock::now();
      const manifold::Manifold solid = manifold::Manifold::LevelSet(
          [&f, T](manifold::vec3 p) {
            return cover::field::evaluate(f, Vec3{p.x, p.y, p.z}).value - T;
          },
          mbox, h);
      run.sample = since(t0);
      run.status = static_cast<int>(solid.Status());
      run.triangles = solid.NumTri();
      run.peer_volume = solid.Volume();
      t0 = Clock::now();
      const manifold::MeshGL gl = solid.GetMeshGL();
      cover::PolygonMesh mesh;
      mesh.vertices.reserve(gl.NumVert());
      for (size_t v = 0; v < gl.NumVert(); ++v) {
        const float* p = gl.vertProperties.data() + v * gl.numProp;
        mesh.vertices.push_back({p[0], p[1], p[2]});
      }
      mesh.face_vertices.reserve(gl.triVerts.size());
      mesh.face_start.reserve(gl.NumTri() + 1);
      for (size_t t = 0; t < gl.NumTri(); ++t)
        mesh.add_face({gl.triVerts[3 * t], gl.triVerts[3 * t + 1], gl.triVerts[3 * t + 2]});
      const cover::Model meshed = outward_model(std::move(mesh), run.volume);
      run.convert = since(t0);
      run.vertices = gl.NumVert();
      t0 = Clock::now();
      run.pixels = covered_pixels(meshed.render(cam));
      run.render = since(t0);
      return run;
    };
#endif

    // Interleaved rounds (Cover, OpenVDB, Manifold, Cover, ...); medians of 3.
    std::vector<double> cover_runs;
    std::vector<PeerRun> vdb_runs, mf_runs;
    size_t covered = 0;
    for (int round = 0; round < 3; ++round) {
      auto t0 = Clock::now();
      cover::RenderOptions one_ray;  // one ray per pixel, as the peers' images
      one_ray.samples = 1;
      const cover::Image img = model.render(cam, one_ray);
      cover_runs.push_back(since(t0));
      covered = covered_pixels(img);
      vdb_runs.push_back(openvdb_route());
#if COVER_BENCH_MANIFOLD
      mf_runs.push_back(manifold_route());
#endif
    }
    std::vector<double> sorted = cover_runs;
    std::sort(sorted.begin(), sorted.end());
    const double cover_s = sorted[1];
    std::printf(
        "render %dx%d, blend of %d (segments and points), median of 3 interleaved: cover %.3f s "
        "(runs %.3f %.3f %.3f; %zu pixels on the surface; bracket volume %.4f +- %.4f)\n",
        width, width, blend, cover_s, cover_runs[0], cover_runs[1], cover_runs[2], covered,
        bracket.volume, bracket.error_bound);
    const PeerRun vdb = median_run(vdb_runs);
    std::printf(
        "  openvdb route at %d^3 (h %.5f): sample %.3f s + volumeToMesh %.3f s (%zu quads, %zu "
        "triangles) + to a mesh %.3f s + mesh render %.3f s = %.3f s (runs %.3f %.3f %.3f); "
        "mesh volume %.4f, %zu pixels; ratio cover / openvdb %.2f\n",
        grid, h, vdb.sample, vdb.mesh, vdb.quads, vdb.triangles, vdb.convert, vdb.render,
        vdb.total(), vdb_runs[0].total(), vdb_runs[1].total(), vdb_runs[2].total(), vdb.volume,
        vdb.pixels, cover_s / vdb.total());
#if COVER_BENCH_MANIFOLD
    const PeerRun mf = median_run(mf_runs);
    std::printf(
        "  manifold route, LevelSet edge %.5f over the box (%dx%dx%d nodes, about %.1fM samples): "
        "level set %.3f s (status %d, %zu triangles, %zu vertices, volume %.4f) + MeshGL to a "
        "mesh %.3f s + mesh render %.3f s = %.3f s (runs %.3f %.3f %.3f); mesh volume %.4f, %zu "
        "pixels; ratio cover / manifold %.2f\n",
        h, gx, gy, gz, (2.0 * gx * gy * gz) / 1e6, mf.sample, mf.status, mf.triangles, mf.vertices,
        mf.peer_volume, mf.convert, mf.render, mf.total(), mf_runs[0].total(), mf_runs[1].total(),
        mf_runs[2].total(), mf.volume, mf.pixels, cover_s / mf.total());
#endif
  }

  // --- octree: Cover's certified octree against OpenVDB's level set by dense sampling ----------
  if (octree_depth > 0) {
    const FieldLeaf f = chain_blend(blend);
    const cover::Model model = field_model(f, "chain");
    const int n = 1 << octree_depth;
    const cover::VoxelBounds cube = model.voxel_bounds(n);  // Model::octree's default cube
    const double h = cube.size / n;
    cover::OctreeOptions options;
    options.depth = octree_depth;

    openvdb::initialize();
    const double T = cover::field::threshold(f);
    const float background = static_cast<float>(T);  // T − f where f = 0: outside
    // Index (i, j, k) ↔ the voxel centre cube.min + (i + ½, j + ½, k + ½)·h, Cover's depth-D cell.
    const auto xform = openvdb::math::Transform::createLinearTransform(h);
    xform->postTranslate({cube.min.x + 0.5 * h, cube.min.y + 0.5 * h, cube.min.z + 0.5 * h});
    const openvdb::CoordBBox lattice(openvdb::Coord(0), openvdb::Coord(n - 1));

    struct PeerRun {
      double sample = 0, copy = 0, rebuild = 0;
      double total() const { return sample + copy + rebuild; }
    };
    std::vector<double> cover_runs;
    std::vector<PeerRun> peer_runs;
    cover::Octree tree;
    openvdb::FloatGrid::Ptr level_set;
    openvdb::Index64 sparse_bytes = 0;
    for (int round = 0; round < 3; ++round) {
      // Cover: the whole build (levels, certified cell states, partial leaves' occupancy).
      auto t0 = Clock::now();
      cover::Octree built = model.octree(options, cube);
      cover_runs.push_back(since(t0));
      tree = std::move(built);

      // OpenVDB. Sampling: the dense array's allocation and T − f (negative inside, as OpenVDB's
      // level sets) at every voxel centre, x slabs in parallel (z fastest: Dense's layout).
      PeerRun run;
      t0 = Clock::now();
      openvdb::tools::Dense<float> dense(lattice);
      float* values = dense.data();
      cover::parallel_for(static_cast<size_t>(n), 1, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
          for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
              const Vec3 p{cube.min.x + (i + 0.5) * h, cube.min.y + (j + 0.5) * h,
                           cube.min.z + (k + 0.5) * h};
              values[(i * n + j) * n + k] =
                  static_cast<float>(T - cover::field::evaluate(f, p).value);
            }
      });
      run.sample = since(t0);
      // Grid build: the sparse copy (voxels equal to the background stay inactive), then the
      // narrow-band level set of its zero isosurface (volumeToMesh + meshToVolume inside).
      t0 = Clock::now();
      auto sparse = openvdb::FloatGrid::create(background);
      sparse->setTransform(xform);
      openvdb::tools::copyFromDense(dense, *sparse, 0.0f);
      run.copy = since(t0);
      t0 = Clock::now();
      openvdb::FloatGrid::Ptr rebuilt = openvdb::tools::levelSetRebuild(*sparse, 0.0f, 3.0f);
      run.rebuild = since(t0);
      peer_runs.push_back(run);
      sparse_bytes = sparse->memUsage();
      level_set = rebuilt;
    }
    // Medians; OpenVDB's split is the one of its median run.
    std::vector<double> sorted = cover_runs;
    std::sort(sorted.begin(), sorted.end());
    const double cover_s = sorted[1];
    std::vector<PeerRun> by_total = peer_runs;
    std::sort(by_total.begin(), by_total.end(),
              [](const PeerRun& a, const PeerRun& b) { return a.total() < b.total(); });
    const PeerRun peer = by_total[1];

    const std::array<uint64_t, 3> leaves = tree.leaf_counts();  // {empty, full, partial}
    const uint64_t cover_bytes = tree.nodes.size() * sizeof(cover::Octree::Node);
    const uint64_t dense_bytes = static_cast<uint64_t>(n) * n * n * sizeof(float);
    std::printf(
        "octree depth %d (%d^3 finest cells, cube side %.4f), blend of %d (segments and points), "
        "median of 3 interleaved:\n",
        octree_depth, n, cube.size, blend);
    std::printf(
        "  cover Model::octree %.3f s (runs %.3f %.3f %.3f): %zu nodes x %zu bytes = %.1f MiB; "
        "leaves %llu full, %llu empty, %llu partial\n",
        cover_s, cover_runs[0], cover_runs[1], cover_runs[2], tree.nodes.size(),
        sizeof(cover::Octree::Node), cover_bytes / 1048576.0,
        static_cast<unsigned long long>(leaves[1]), static_cast<unsigned long long>(leaves[0]),
        static_cast<unsigned long long>(leaves[2]));
    std::printf(
        "  openvdb (f - T by cover::field::evaluate in doubles at the %d^3 voxel centres -> "
        "tools::Dense, copyFromDense, levelSetRebuild half width 3): sample %.3f s + "
        "copyFromDense %.3f s + levelSetRebuild %.3f s = %.3f s (runs %.3f %.3f %.3f); "
        "level set %llu active voxels, memUsage %.1f MiB (sparse copy %.1f MiB, dense array "
        "%.1f MiB)\n",
        n, peer.sample, peer.copy, peer.rebuild, peer.total(), peer_runs[0].total(),
        peer_runs[1].total(), peer_runs[2].total(),
        static_cast<unsigned long long>(level_set->activeVoxelCount()),
        level_set->memUsage() / 1048576.0, sparse_bytes / 1048576.0, dense_bytes / 1048576.0);
    std::printf("  ratio cover / openvdb %.3f\n", cover_s / peer.total());
  }
  return 0;
}
