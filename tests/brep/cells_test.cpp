// brep::cut_cells (brep/cells.h): pieces of evaluated CSG results over boxes, spheres and small
// libcgal-demo meshes at N = 1..4 (each piece valid, volumes summing, glue = the input solid),
// walls through mesh vertices and along mesh faces, full cells, a cube smaller than the solid,
// determinism; and `cover evaluate --cells` / `--pieces` on the command line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

#include "cells_checks.h"
#include "cover/boolean/evaluate.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

Solid box_leaf(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

brep::CellGrid grid(Vec3 min, double size, int n) { return {min, size, n}; }

TEST(Cells, FullCellsAreTheirBoxes) {
  // [0,2]³ over the cube [0,2]³ in 2³ cells: walls on the box's faces and through its middle.
  const PolygonMesh cube = make_box({0, 0, 0}, {2, 2, 2});
  const brep::CellsResult r = test::expect_valid_cells(cube, grid({0, 0, 0}, 2, 2), "cube");
  ASSERT_EQ(r.pieces.size(), 8u);
  for (const brep::CellPiece& piece : r.pieces) {
    EXPECT_EQ(piece.volume, 1);
    EXPECT_EQ(piece.area, 6);
    EXPECT_EQ(piece.cap_area, 3);  // three interior walls, three faces of the input
    for (const Vec3& p : piece.mesh.vertices)
      for (int a = 0; a < 3; ++a) EXPECT_TRUE(p[a] == piece.cell[a] || p[a] == piece.cell[a] + 1);
  }
  EXPECT_EQ(r.pieces.front().cell, (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(r.pieces.back().cell, (std::array<int, 3>{1, 1, 1}));
}

TEST(Cells, MeshOnWallsIsNotClipped) {
  // [0,1]³ in the cell (0,0,0) of [0,2]³: every face lies on a wall, no clip is needed.
  const PolygonMesh cube = make_box({0, 0, 0}, {1, 1, 1});
  const brep::CellsResult r = test::expect_valid_cells(cube, grid({0, 0, 0}, 2, 2), "unit cube");
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.clips, 0);
  EXPECT_EQ(r.cap_faces, 0);
  EXPECT_EQ(r.glued.face_count(), 6u);
}

TEST(Cells, ResultFacesLyingInAWall) {
  // An L: [0,1]×[0,2]×[0,2] ∪ [1,2]×[0,1]×[0,2]; its face x = 1, y ∈ [1,2] lies in the wall x = 1.
  const EvaluateResult l =
      evaluate(unite({box_leaf({0, 0, 0}, {1, 2, 2}), box_leaf({1, 0, 0}, {2, 1, 2})}));
  for (int n : {1, 2, 3, 4}) {
    const brep::CellsResult r = test::expect_valid_cells(l.mesh, grid({0, 0, 0}, 2, n), "L");
    if (n == 2) {
      EXPECT_EQ(r.pieces.size(), 6u);
    }
    if (n == 4) {
      EXPECT_EQ(r.pieces.size(), 48u);
    }
  }
  // A slot flush with walls: [0,4]³ minus [1,3]×[−1,5]×[2,4], walls at 1, 2, 3.
  const EvaluateResult slot =
      evaluate(subtract({box_leaf({0, 0, 0}, {4, 4, 4}), box_leaf({1, -1, 2}, {3, 5, 4})}));
  test::expect_valid_cells(slot.mesh, grid({0, 0, 0}, 4, 4), "slot");
  test::expect_valid_cells(slot.mesh, grid({-1, -1, -1}, 6, 3), "slot");
}

TEST(Cells, WallsThroughVertices) {
  // A sphere centred on walls: its poles, equator and meridian vertices lie on them.
  const PolygonMesh ball = make_sphere({0, 0, 0}, 1, 16);
  for (int n : {2, 4}) test::expect_valid_cells(ball, grid({-1.5, -1.5, -1.5}, 3, n), "sphere");
  // An octahedron whose six vertices lie on the walls x, y, z = 0.
  PolygonMesh octa;
  octa.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (uint32_t s : {4u, 5u})
    for (auto [a, b] : {std::pair{0u, 2u}, {2u, 1u}, {1u, 3u}, {3u, 0u}})
      octa.add_face(s == 4 ? std::initializer_list<uint32_t>{a, b, s}
                           : std::initializer_list<uint32_t>{b, a, s});
  const brep::CellsResult r =
      test::expect_valid_cells(octa, grid({-1, -1, -1}, 2, 2), "octahedron");
  EXPECT_EQ(r.pieces.size(), 8u);
  for (const brep::CellPiece& piece : r.pieces) EXPECT_DOUBLE_EQ(piece.volume, 1.0 / 6);
}

TEST(Cells, CubeSmallerThanTheSolid) {
  // [0,2]³ cut to the cube [0.5,1.5]³: the glue keeps the outer caps, a box of volume 1.
  const brep::CellsResult r =
      brep::cut_cells(make_box({0, 0, 0}, {2, 2, 2}), grid({0.5, 0.5, 0.5}, 1, 2));
  ASSERT_EQ(r.pieces.size(), 8u);
  for (const brep::CellPiece& piece : r.pieces) EXPECT_EQ(piece.volume, 0.125);
  const test::HalfCheck c = test::check_half(r.glued, {}, -1);
  EXPECT_TRUE(c.report.closed && c.report.manifold);
  EXPECT_EQ(c.volume, 1);
  EXPECT_EQ(surface_area(r.glued), 6);
}

TEST(Cells, EmptyAndBadGrids) {
  const PolygonMesh cube = make_box({0, 0, 0}, {1, 1, 1});
  EXPECT_TRUE(brep::cut_cells(cube, grid({5, 5, 5}, 1, 3)).pieces.empty());  // misses the cube
  EXPECT_TRUE(brep::cut_cells(PolygonMesh{}, grid({0, 0, 0}, 1, 3)).pieces.empty());
  EXPECT_THROW(brep::cut_cells(cube, grid({0, 0, 0}, 1, 0)), InputError);
  EXPECT_THROW(brep::cut_cells(cube, grid({0, 0, 0}, 0, 2)), InputError);
}

// ---- random CSG scenes
// ---------------------------------------------------------------------------

/// `name` (box, sphere or a libcgal-demo mesh) scaled to `size`, turned and moved at random.
Solid random_leaf(std::mt19937_64& rng, const std::string& name, double size) {
  std::uniform_real_distribution<double> u(-1, 1);
  PolygonMesh m = name == "box"      ? make_box({-0.5, -0.35, -0.4}, {0.5, 0.35, 0.4})
                  : name == "sphere" ? make_sphere({0, 0, 0}, 0.5, 20)
                                     : read_mesh(test::cgal_mesh(name + ".off"));
  const Bbox b = face_bbox(m);
  const Vec3 c = 0.5 * (b.min + b.max);
  const double ext = std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
  Vec3 axis{u(rng), u(rng), u(rng)};
  if (dot(axis, axis) < 1e-3) axis = {0, 0, 1};
  const double k = 2 * size / ext;
  apply_transform(
      Transform::trs({k, k, k}, axis, 180 * u(rng), {0.25 * u(rng), 0.25 * u(rng), 0.25 * u(rng)}) *
          Transform::translation({-c.x, -c.y, -c.z}),
      m);
  return make_leaf(m, name);
}

TEST(Cells, RandomScenes) {
  const std::vector<std::vector<std::string>> sets = {
      {"box", "sphere"}, {"sphere", "box", "box"}, {"knot1", "box"}, {"fandisk", "sphere"}};
  for (unsigned i = 0; i < sets.size(); ++i) {
    std::mt19937_64 rng(300 + i);
    std::uniform_int_distribution<int> op(0, 2);
    Solid s = random_leaf(rng, sets[i][0], 0.8);
    std::string label = "seed " + std::to_string(300 + i) + " " + sets[i][0];
    for (size_t k = 1; k < sets[i].size(); ++k) {
      Solid t = random_leaf(rng, sets[i][k], sets[i][k] == "box" ? 0.6 : 0.8);
      const int o = op(rng);
      s = o == 0 ? unite({std::move(s), std::move(t)})
                 : (o == 1 ? intersect({std::move(s), std::move(t)})
                           : subtract({std::move(s), std::move(t)}));
      label += std::string(o == 0 ? " ∪ " : (o == 1 ? " ∩ " : " − ")) + sets[i][k];
    }
    const EvaluateResult e = evaluate(s);
    // Seed 300 and 301 have cut rings with corners whose turn the exact and the rounded points
    // disagree on, and points that round to one double point (brep/cap.cpp's split before ear
    // clipping, cells.h's rounding repair): every piece is checked all the same.
    for (int n : {1, 2, 3, 4})
      test::expect_valid_cells(e.mesh, test::cells_around(e.mesh, n), label);
  }
}

TEST(Cells, SamePiecesForAnyThreadCount) {
  const PolygonMesh ball = make_sphere({0.1, 0.2, 0.3}, 1, 24);
  const brep::CellGrid g = test::cells_around(ball, 4);
  const brep::CellsResult all = brep::cut_cells(ball, g);
  brep::CellsResult one;
  {
    ThreadLimit limit(1);
    one = brep::cut_cells(ball, g);
  }
  ASSERT_EQ(all.pieces.size(), one.pieces.size());
  for (size_t p = 0; p < all.pieces.size(); ++p) {
    EXPECT_EQ(all.pieces[p].cell, one.pieces[p].cell);
    EXPECT_EQ(all.pieces[p].mesh.vertices, one.pieces[p].mesh.vertices);
    EXPECT_EQ(all.pieces[p].mesh.face_vertices, one.pieces[p].mesh.face_vertices);
  }
  EXPECT_EQ(all.glued.vertices, one.glued.vertices);
  EXPECT_EQ(all.glued.face_vertices, one.glued.face_vertices);
}

// ---- pieces valid as written, or refused ------------------------------------------------------

/// Cuts `mesh` into `grid`'s cells: either NotComputable, or every piece and the glued mesh
/// valid by CGAL's exact checks, the pieces' volumes summing to the glued volume and that to
/// `volume` (the solid's, or of its part inside the cube). Returns whether it was refused.
bool expect_valid_or_refused(const PolygonMesh& mesh, const brep::CellGrid& g, double volume,
                             const std::string& label) {
  brep::CellsResult r;
  try {
    r = brep::cut_cells(mesh, g);
  } catch (const NotComputable& e) {
    EXPECT_NE(std::string(e.what()).find("not valid as written"), std::string::npos) << e.what();
    return true;
  }
  double sum = 0;
  for (const brep::CellPiece& piece : r.pieces) {
    EXPECT_EQ(test::cgal_verdict(piece.mesh), "")
        << label << " cell " << piece.cell[0] << "," << piece.cell[1] << "," << piece.cell[2];
    sum += signed_volume(piece.mesh);
  }
  EXPECT_EQ(test::cgal_verdict(r.glued), "") << label << " glued";
  EXPECT_NEAR(sum, volume, 1e-9 * volume) << label;
  EXPECT_NEAR(signed_volume(r.glued), volume, 1e-9 * volume) << label;
  return false;
}

TEST(Cells, CubeCuttingTheResultGluesToResultInCube) {
  // The cube cuts the result: its outer caps are made before any interior wall, so the walls
  // split them at points both sides share (no wall edge without a partner). The glued mesh is
  // result ∩ cube, whose volume the evaluator gives independently.
  const Solid s = subtract(
      {box_leaf({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "ball")});
  const EvaluateResult e = evaluate(s);
  for (const auto& [min, size] :
       {std::pair{Vec3{0.5, 0.5, 0.5}, 1.0}, std::pair{Vec3{-0.5, 0.3, 0.1}, 1.7},
        std::pair{Vec3{1, 1, 1}, 2.0}}) {
    const double in_cube =
        signed_volume(evaluate(intersect({s, box_leaf(min, min + Vec3{size, size, size})})).mesh);
    for (int n : {2, 3, 5}) {
      const brep::CellsResult r = brep::cut_cells(e.mesh, grid(min, size, n));
      EXPECT_EQ(test::cgal_verdict(r.glued), "") << n;
      EXPECT_NEAR(signed_volume(r.glued), in_cube, 1e-12 * in_cube) << n;
      double sum = 0;
      for (const brep::CellPiece& piece : r.pieces) sum += piece.volume;
      EXPECT_NEAR(sum, in_cube, 1e-12 * in_cube) << n;
    }
  }
}

TEST(Cells, BoxCellsAreBoxesOfSixFaces) {
  // A cube inside a box: every piece is its cell's box. Cap corners that are straight (where an
  // earlier wall split a side) are merged across, so no cap diagonal is left for later walls to
  // cross; the volumes are the products of the wall differences, exactly.
  const PolygonMesh big = make_box({0, 0, 0}, {4, 4, 4});
  const brep::CellGrid g = grid({1, 1, 1}, 2, 7);
  const brep::CellsResult r = brep::cut_cells(big, g);
  ASSERT_EQ(r.pieces.size(), 343u);
  EXPECT_EQ(r.forced_ears, 0);
  EXPECT_EQ(r.collapsed_edges, 0);
  for (const brep::CellPiece& piece : r.pieces) {
    EXPECT_EQ(piece.mesh.face_count(), 6u);
    EXPECT_EQ(piece.mesh.vertices.size(), 8u);
    double expected = 1;
    for (int a = 0; a < 3; ++a)
      expected *= brep::cell_wall(g, a, piece.cell[a] + 1) - brep::cell_wall(g, a, piece.cell[a]);
    EXPECT_NEAR(piece.volume, expected, 1e-15);
  }
}

TEST(Cells, DefaultSceneWallsThroughNearZeroVerticesGiveValidPieces) {
  // models/default.json: its sphere, cylinders and turned torus have vertices within 1e-16 of
  // the walls x, y, z = 0 that even N put there. Every piece and the glued mesh as written pass
  // CGAL's exact checks.
  const Model m = load(test::source_dir() / "models" / "default.json");
  const PolygonMesh mesh = m.evaluate().mesh;
  const double volume = signed_volume(mesh);
#ifdef COVER_SANITIZED
  for (int n : {2}) {
#else
  for (int n : {2, 4}) {
#endif
    const VoxelBounds b = m.voxel_bounds(n);  // the default cube of evaluate_cells
    const std::string label = "default n=" + std::to_string(n);
    EXPECT_FALSE(expect_valid_or_refused(mesh, {b.min, b.size, n}, volume, label)) << label;
  }
}

TEST(Cells, WallWithinUlpsOfABoxFaceGivesValidPiecesOrRefuses) {
  // The default cube's wall 1 lies within rounding of the result's lowest face (one cell of
  // margin): slivers of 1e-16 thickness. Each N either refuses (NotComputable) or gives pieces
  // and a glued mesh valid as written.
  const Model m = load(test::source_dir() / "tests" / "data" / "cells_wall_near_box_face.json");
  const PolygonMesh mesh = m.evaluate().mesh;
  const double volume = signed_volume(mesh);
  int refused = 0;
  for (int n = 2; n <= 8; ++n) {
    const VoxelBounds b = m.voxel_bounds(n);
    refused += expect_valid_or_refused(mesh, {b.min, b.size, n}, volume, "n=" + std::to_string(n));
  }
  EXPECT_LE(refused, 2);
}

TEST(Cells, MemoryEstimateCoversMeasuredUse) {
  // Measured peaks (/usr/bin/time -v, evaluate --cells): a box filling 60³ cells 396 MiB, a
  // sphere of 131k faces in 40³ cells 222 MiB, in 10³ cells 72 MiB.
  EXPECT_GE(brep::cells_memory_bytes(60, 12), 396.0 * (1 << 20));
  EXPECT_GE(brep::cells_memory_bytes(40, 131072), 222.0 * (1 << 20));
  EXPECT_GE(brep::cells_memory_bytes(10, 131072), 72.0 * (1 << 20));
  EXPECT_GT(brep::cells_memory_bytes(80), 600.0 * (1 << 20));  // --max-memory 600 refuses N = 80
  EXPECT_GT(brep::cells_memory_bytes(2000), 1e13);
  brep::CellsOptions o;
  o.max_memory_bytes = 1 << 20;
  EXPECT_THROW(brep::cut_cells(make_box({0, 0, 0}, {1, 1, 1}), grid({0, 0, 0}, 1, 8), o),
               InputError);
}

// ---- the facade and the CLI ----------------------------------------------------------------

TEST(Cells, ModelEvaluateCells) {
  const Model m = cover::box({0, 0, 0}, {1, 1, 1}) - cover::sphere({1, 1, 1}, 0.7, 24);
  const CellsEvaluation r = m.evaluate_cells(3);
  EXPECT_EQ(r.grid.n, 3);
  const VoxelBounds b = m.voxel_bounds(3);  // the cube voxelize uses
  EXPECT_EQ(r.grid.min, b.min);
  EXPECT_EQ(r.grid.size, b.size);
  test::expect_valid_cells(r.evaluated.mesh, r.grid, "box − sphere");
  const Model deep = cover::box({0, 0, 0}, {1, 1, 1}) - cover::sphere({1, 1, 1}, 0.9, 24);
  const CellsEvaluation given = deep.evaluate_cells(2, VoxelBounds{{0, 0, 0}, 1});
  EXPECT_EQ(given.cells.pieces.size(), 7u);  // the cell at (1,1,1) lies inside the sphere
  EXPECT_THROW(m.evaluate_cells(0), InputError);
  EXPECT_TRUE(Model().evaluate_cells(2).cells.pieces.empty());
}

TEST(CellsCli, PiecesFolder) {
  const auto dir = test::temp_dir("cells");
  test::write_file(dir / "s.json", R"({"difference": [
      {"box": {"min": [0, 0, 0], "max": [2, 2, 2]}},
      {"box": {"min": [1, 1, 1], "max": [3, 3, 3]}}]})");
  const std::string out = (dir / "out.off").string(), pieces = (dir / "p").string();
  const test::RunResult r =
      test::run_cover("evaluate '" + (dir / "s.json").string() + "' -o '" + out +
                      "' --cells 2 --bounds 0,0,0,2 --pieces '" + pieces + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["pieces"], 7);
  EXPECT_EQ(j["cells"], 2);
  EXPECT_DOUBLE_EQ(j["volume"].get<double>(), 7);
  EXPECT_EQ(j["genus"], 0);
  EXPECT_GT(j["cap_faces"].get<int>(), 0);
  for (const char* key : {"load", "kernel", "write", "evaluate", "cut", "glue"})
    EXPECT_TRUE(j["seconds_detail"].contains(key)) << key;
  const nlohmann::json index = nlohmann::json::parse(test::read_file(dir / "p" / "pieces.json"));
  ASSERT_EQ(index["pieces"].size(), 7u);
  double sum = 0;
  for (const auto& p : index["pieces"]) {
    EXPECT_NE(p["cell"], (nlohmann::json{1, 1, 1}));
    const PolygonMesh piece = read_mesh(dir / "p" / p["file"].get<std::string>());
    EXPECT_EQ(piece.face_count(), p["faces"].get<size_t>());
    EXPECT_DOUBLE_EQ(signed_volume(piece), p["volume"].get<double>());
    EXPECT_DOUBLE_EQ(p["volume"].get<double>(), 1);
    EXPECT_GT(p["cap_area"].get<double>(), 0);
    EXPECT_TRUE(p.contains("area"));
    sum += p["volume"].get<double>();
  }
  EXPECT_EQ(sum, 7);
  EXPECT_EQ(index["pieces"][0]["file"], "cell_0_0_0.off");
  const PolygonMesh glued = read_mesh(out);
  EXPECT_DOUBLE_EQ(signed_volume(glued), 7);
  std::filesystem::remove_all(dir);
}

TEST(CellsCli, BoundsNotContainingTheResultWriteResultInCube) {
  const auto dir = test::temp_dir("cells-cut");
  const std::string in = (test::source_dir() / "models" / "default.json").string();
  const std::string out = (dir / "out.off").string();
  const test::RunResult r = test::run_cover("evaluate '" + in + "' -o '" + out +
                                            "' --cells 3 --bounds=-1.5,-1.3,-1.1,2.5 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const PolygonMesh glued = read_mesh(out);
  EXPECT_EQ(test::cgal_verdict(glued), "");
  // Independently: the scene ∩ the cube, evaluated.
  const Model cube = cover::box({-1.5, -1.3, -1.1}, {1, 1.2, 1.4});
  const Model m = load(in) & cube;
  EXPECT_NEAR(signed_volume(glued), signed_volume(m.evaluate().mesh), 1e-9);
  std::filesystem::remove_all(dir);
}

TEST(CellsCli, MemoryEstimateRefusesEightyCellsUnder600MiB) {
  const auto dir = test::temp_dir("cells-memory");
  const std::string in = (test::source_dir() / "models" / "default.json").string();
  const std::string out = (dir / "out.off").string();
  const test::RunResult r =
      test::run_cover("evaluate '" + in + "' -o '" + out + "' --cells 80 --max-memory 600");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--max-memory 600"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

TEST(CellsCli, BadInputExitsTwo) {
  const auto dir = test::temp_dir("cells-bad");
  const std::string in = (test::source_dir() / "models" / "default.json").string();
  const std::string out = (dir / "out.off").string();
  auto run = [&](const std::string& extra) {
    return test::run_cover("evaluate '" + in + "' -o '" + out + "' " + extra);
  };
  test::RunResult r = run("--cells 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--cells"), std::string::npos) << r.err;
  r = run("--cells 100000");  // 10^15 cells: refused by the memory estimate
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--max-memory"), std::string::npos) << r.err;
  r = run("--cells 64 --max-memory 16");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--cells 64"), std::string::npos) << r.err;
  r = run("--pieces '" + (dir / "p").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("needs --cells"), std::string::npos) << r.err;
  r = run("--cells 2 --bounds 0,0,0,-1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--bounds"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
