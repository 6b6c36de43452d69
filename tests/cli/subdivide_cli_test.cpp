// `cover subdivide` end to end (docs/cli.md): the written mesh equals cover::subdivide of the
// same input read independently, in every mesh format; counts per scheme follow from the input's
// V, E, F and face degrees; genus is preserved; bad input exits 2 with one line naming the
// problem and writes nothing.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "cover/solid/primitives.h"
#include "cover/subdivision/subdivide.h"
#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;
using test::run_cover;

std::string q(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::filesystem::path model(const std::string& name) {
  return test::source_dir() / "models" / name;
}

/// The command's --json for IN → OUT with `args`, after checking exit 0.
json subdivide_json(const std::filesystem::path& in, const std::filesystem::path& out,
                    const std::string& args) {
  const auto r = run_cover("subdivide " + q(in) + " -o " + q(out) + " " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(r.out) : json::object();
}

void expect_same_mesh(const PolygonMesh& a, const PolygonMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (size_t v = 0; v < a.vertices.size(); ++v) ASSERT_EQ(a.vertices[v], b.vertices[v]) << v;
  EXPECT_EQ(a.face_start, b.face_start);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
}

TEST(SubdivideCli, OutputEqualsTheLibraryForEveryScheme) {
  const auto dir = test::temp_dir("subdivide");
  write_mesh(dir / "box.obj", make_box({0, 0, 0}, {1, 2, 3}));
  const auto input = [&](const std::string& name) {
    return name == "box.obj" ? dir / name : model(name);
  };
  struct Case {
    const char* model;
    const char* scheme;
    Scheme expected;
    int levels;
    const char* ext;
    bool exact;
  };
  for (const Case& c :
       {Case{"torus.off", "catmull-clark", Scheme::kCatmullClark, 2, ".off", false},
        Case{"torus.off", "doo-sabin", Scheme::kDooSabin, 1, ".ply", false},
        Case{"knot.off", "loop", Scheme::kLoop, 1, ".obj", false},
        Case{"knot.off", "sqrt3", Scheme::kSqrt3, 2, ".off", true},
        Case{"box.obj", "doo-sabin", Scheme::kDooSabin, 2, ".ply", true},
        Case{"torus.off", "catmull-clark", Scheme::kCatmullClark, 0, ".off", false}}) {
    const auto out = dir / (std::string(c.scheme) + std::to_string(c.levels) + c.ext);
    const json j =
        subdivide_json(input(c.model), out,
                       std::string("--scheme ") + c.scheme + " --levels " +
                           std::to_string(c.levels) + (c.exact ? " --exact-rounding" : ""));
    SubdivideOptions o;
    o.scheme = c.expected;
    o.levels = c.levels;
    o.exact_rounding = c.exact;
    const PolygonMesh expected = subdivide(read_mesh(input(c.model)), o);
    SCOPED_TRACE(std::string(c.model) + " " + c.scheme);
    expect_same_mesh(read_mesh(out), expected);
    EXPECT_EQ(j["vertices"].get<size_t>(), expected.vertices.size());
    EXPECT_EQ(j["faces"].get<size_t>(), expected.face_count());
    EXPECT_EQ(j["scheme"], c.scheme);
    EXPECT_EQ(j["levels"], c.levels);
    EXPECT_EQ(j["exact_rounding"], c.exact);
  }
  std::filesystem::remove_all(dir);
}

TEST(SubdivideCli, CountsFollowTheSchemesAndGenusIsPreserved) {
  const auto dir = test::temp_dir("subdivide");
  for (const char* name : {"torus.off", "knot.off"}) {
    const PolygonMesh in = read_mesh(model(name));
    const MeshReport r = validate_mesh(in, {.check_self_intersection = false});
    ASSERT_EQ(r.genus, 1);
    const size_t v = in.vertices.size(), e = static_cast<size_t>(r.edges), f = in.face_count();
    const size_t h = in.face_vertices.size();
    const bool triangles = h == 3 * f;
    struct Expected {
      const char* scheme;
      size_t vertices, edges, faces;
    };
    std::vector<Expected> cases = {{"catmull-clark", v + e + f, 2 * e + h, h},
                                   {"doo-sabin", h, h + 2 * e, f + e + v}};
    if (triangles) {
      cases.push_back({"loop", v + e, 2 * e + 3 * f, 4 * f});
      cases.push_back({"sqrt3", v + f, e + 3 * f, 3 * f});
    }
    for (const Expected& x : cases) {
      SCOPED_TRACE(std::string(name) + " " + x.scheme);
      const json j = subdivide_json(model(name), dir / "out.off",
                                    std::string("--scheme ") + x.scheme + " --levels 1");
      EXPECT_EQ(j["vertices"].get<size_t>(), x.vertices);
      EXPECT_EQ(j["edges"].get<size_t>(), x.edges);
      EXPECT_EQ(j["faces"].get<size_t>(), x.faces);
      EXPECT_EQ(j["genus"], 1);
      EXPECT_EQ(j["components"], 1);
      EXPECT_EQ(j["closed"], true);
      EXPECT_EQ(j["boundary_edges"], 0);
      EXPECT_EQ(j["self_intersecting"], false);
      EXPECT_TRUE(j["seconds"].is_number());
      for (const char* phase : {"load", "kernel", "write"})
        EXPECT_TRUE(j["seconds_detail"][phase].is_number());
      // Euler: V − E + F = 2 − 2g on the written mesh too.
      const PolygonMesh out = read_mesh(dir / "out.off");
      const MeshReport ro = validate_mesh(out, {.check_self_intersection = false});
      EXPECT_EQ(ro.genus, 1);
      EXPECT_EQ(static_cast<int64_t>(out.vertices.size()) - ro.edges +
                    static_cast<int64_t>(out.face_count()),
                0);
    }
  }
  // Catmull–Clark twice: the second level's counts follow from the first's (all quads).
  const json j1 = subdivide_json(model("torus.off"), dir / "a.off", "--levels 1");
  const json j2 = subdivide_json(model("torus.off"), dir / "b.off", "--levels 2");
  EXPECT_EQ(j2["vertices"],
            j1["vertices"].get<size_t>() + j1["edges"].get<size_t>() + j1["faces"].get<size_t>());
  EXPECT_EQ(j2["faces"], 4 * j1["faces"].get<size_t>());
  EXPECT_EQ(j2["genus"], 1);
  std::filesystem::remove_all(dir);
}

TEST(SubdivideCli, CarriesAnObjsTextureCoordinates) {
  const auto dir = test::temp_dir("subdivide");
  const auto in = dir / "cube.obj", out = dir / "out.obj";
  // A cube with a seam: face 6 names its own vt at vertex 4.
  std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                       "f 1/1 4/2 3/3 2/4\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\n"
                       "f 2/1 3/2 7/3 6/4\nf 3/1 4/2 8/3 7/4\nf 4/5 1/-4 5/-3 8/-2\n";
  for (const char* scheme : {"catmull-clark", "doo-sabin"}) {
    SCOPED_TRACE(scheme);
    const json j = subdivide_json(in, out, std::string("--scheme ") + scheme + " --levels 2");
    EXPECT_EQ(j["texture_coordinates"], true);
    std::vector<double> uvs, written;
    const PolygonMesh mesh = read_mesh_with_uvs(in, uvs);
    ASSERT_EQ(uvs.size(), 48u);
    EXPECT_EQ(uvs[40], 0.5);  // face 6's first corner: vt 5
    EXPECT_EQ(uvs[42], 1.0);  // its second: vt -4 = vt 2 (1, 0)
    CornerAttributes a{2, uvs};
    const PolygonMesh expected = subdivide(mesh, {*scheme_from_string(scheme), 2}, a);
    const PolygonMesh got = read_mesh_with_uvs(out, written);
    expect_same_mesh(got, expected);
    EXPECT_EQ(written, a.values);
  }
  // Another output format drops them with a warning; bad references are one-line errors.
  const auto r = run_cover("subdivide " + q(in) + " -o " + q(dir / "out.off"));
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.err.find("texture coordinates dropped"), std::string::npos) << r.err;
  const std::pair<const char*, const char*> bad[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3\n", "bad.obj:5: a face corner without"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/4\n", "bad.obj:5: texture index 4 out"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/0 3/1\n", "bad.obj:5: texture index 0"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 x\nf 1/1 2/1 3/1\n", "bad.obj:4: "}};
  for (const auto& [text, message] : bad) {
    std::ofstream(dir / "bad.obj") << text;
    const auto e = run_cover("subdivide " + q(dir / "bad.obj") + " -o " + q(dir / "b.obj"));
    EXPECT_EQ(e.status, 2) << text;
    EXPECT_NE(e.err.find(message), std::string::npos) << e.err;
    EXPECT_EQ(std::count(e.err.begin(), e.err.end(), '\n'), 1) << e.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "b.obj"));
  }
  std::filesystem::remove_all(dir);
}

TEST(SubdivideCli, TextOutputStatesTheFacts) {
  const auto dir = test::temp_dir("subdivide");
  const auto r = run_cover("subdivide " + q(model("torus.off")) + " -o " + q(dir / "t.obj"));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("catmull-clark"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2048 vertices, 4096 edges, 2048 faces, 1 components, genus 1"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("self-intersecting no"), std::string::npos) << r.out;
  std::filesystem::remove_all(dir);
}

TEST(SubdivideCli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const auto dir = test::temp_dir("subdivide");
  const auto torus = model("torus.off");
  // Three triangles on one edge: a non-manifold edge.
  test::write_file(dir / "fin.off",
                   "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const auto out = dir / "out.off";
  struct Bad {
    std::string args;
    std::string says;  ///< a part of the message
  };
  for (const Bad& b : std::vector<Bad>{
           {q(dir / "missing.off"), "missing.off"},
           {q(torus) + " --scheme butterfly", "--scheme"},
           {q(torus) + " --levels -1", "--levels"},
           {q(torus) + " --levels 31", "--levels"},
           {q(torus) + " --levels 14", "torus.off: --levels: 14 levels"},
           {q(torus) + " --scheme loop", "torus.off"},
           {q(torus) + " --scheme sqrt3", "torus.off"},
           {q(dir / "fin.off"), "fin.off"},
           {q(dir / "fin.off") + " --scheme loop", "fin.off"},
           {q(model("default.json")), "default.json"},
       }) {
    const auto r = run_cover("subdivide " + b.args + " -o " + q(out));
    EXPECT_EQ(r.status, 2) << b.args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("cover: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(b.says), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << b.args;
  }
  const auto r = run_cover("subdivide " + q(torus) + " -o " + q(dir / "out.xyz"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("out.xyz"), std::string::npos) << r.err;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);  // fin.off only
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
