// The viewer's server (view/viewer.h) through an HTTP client (cpp-httplib's): frames against
// Model::render + the PNG file writer, picks against classify, hidden leaves against the scene
// without them, reloads, and refusals. The browser side: python/tests/test_viewer.py.
#include "cover/view/viewer.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "cover/covering/classify.h"
#include "cover/io/png.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "helpers.h"

namespace cover {
namespace {

using json = nlohmann::json;

/// A copy of the default scene and its torus in a fresh folder.
std::filesystem::path scene_copy() {
  const std::filesystem::path dir = test::temp_dir("view");
  std::filesystem::copy_file(test::source_dir() / "models" / "default.json", dir / "scene.json");
  std::filesystem::copy_file(test::source_dir() / "models" / "torus.off", dir / "torus.off");
  return dir / "scene.json";
}

struct Served {
  explicit Served(const std::filesystem::path& input, ViewerOptions o = {})
      : viewer(input, o), client("127.0.0.1", viewer.port()) {}
  httplib::Result get(const std::string& path, bool token = true) {
    const std::string sep = path.find('?') == std::string::npos ? "?" : "&";
    return client.Get(token ? path + sep + "t=" + viewer.token() : path);
  }
  Viewer viewer;
  httplib::Client client;
};

std::string file_png(const Image& image) {
  const std::filesystem::path p = test::temp_dir("png") / "f.png";
  write_png_rgb(p, image.width, image.height, image.rgb);
  return test::read_file(p);
}

TEST(Viewer, FramesAreTheRenderersPngBytes) {
  const std::filesystem::path scene = scene_copy();
  Served s(scene);
  const Model model = load(scene);
  CameraOptions co;
  co.width = 240;
  co.height = 170;
  co.azimuth_degrees = 25;
  co.elevation_degrees = 20;
  co.zoom = 1.3;
  co.pan = {0.1, -0.2};
  RenderOptions ro;
  ro.section = Plane{{0, 0, 1}, 0.5};
  const Image want = model.render(co, ro);
  auto r = s.get(
      "/frame?w=240&h=170&azimuth=25&elevation=20&zoom=1.3&pan=0.1,-0.2"
      "&section=0,0,1,0.5");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "image/png");
  EXPECT_TRUE(r->body == file_png(want));
  const std::vector<uint8_t> mem = encode_png_rgb(want.width, want.height, want.rgb);
  EXPECT_TRUE(r->body == std::string(mem.begin(), mem.end()));
}

TEST(Viewer, RefusesRequestsWithoutTheTokenOrFromOtherHosts) {
  Served s(scene_copy());
  auto r = s.get("/frame?w=10&h=10", false);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403);
  r = s.client.Get("/info?t=" + s.viewer.token() + "0");
  EXPECT_EQ(r->status, 403);
  // DNS rebinding: a page of evil.example resolving to 127.0.0.1 sends its own Host.
  r = s.client.Get("/info?t=" + s.viewer.token(), {{"Host", "evil.example"}});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 403);
  r = s.get("/info");
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(s.viewer.url().find("t=" + s.viewer.token()), std::string::npos);
}

TEST(Viewer, BadParametersGetOneLineMessages) {
  Served s(scene_copy());
  for (const char* q : {"w=0&h=10", "w=10&h=99999", "w=10&h=10&samples=9", "w=10&h=10&zoom=-1",
                        "w=10&h=10&view=sideways", "w=10&h=10&section=0,0,0,1",
                        "w=10&h=10&section=1,2", "w=10&h=10&pan=nan,0", "w=10&h=10&hidden=a",
                        "w=10&h=10&fit=1", "w=10&h=10&up=w", "w=10&h=10&elevation=91"}) {
    auto r = s.get(std::string("/frame?") + q);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << q;
    EXPECT_EQ(r->body.find('\n'), r->body.size() - 1) << q << ": " << r->body;
  }
  ViewerOptions big;
  big.max_memory_bytes = 1 << 20;
  Served small(scene_copy(), big);
  EXPECT_EQ(small.get("/frame?w=1000&h=1000")->status, 400);
}

TEST(Viewer, PicksReportTheExactClassOfThePointAndItsLeaf) {
  const std::filesystem::path scene = scene_copy();
  Served s(scene);
  const Model model = load(scene);
  CameraOptions co;
  co.width = 64;
  co.height = 48;
  const Camera cam = model.camera(co);
  const Image image = model.render(cam, RenderOptions{.samples = 1});
  int hits = 0;
  for (int y = 0; y < 48; y += 5)
    for (int x = 0; x < 64; x += 5) {
      auto r = s.get("/pick?w=64&h=48&x=" + std::to_string(x) + "&y=" + std::to_string(y));
      ASSERT_EQ(r->status, 200);
      const json j = json::parse(r->body);
      const uint16_t id = image.ids[static_cast<size_t>(y) * 64 + x];
      ASSERT_EQ(j["hit"].get<bool>(), id != Image::kBackgroundId) << x << "," << y;
      if (!j["hit"]) continue;
      ++hits;
      const Vec3 p{j["point"][0], j["point"][1], j["point"][2]};
      EXPECT_EQ(j["class"], std::string(to_string(model.classify(std::vector<Vec3>{p})[0])));
      EXPECT_EQ(j["leaf_index"].get<uint32_t>() + 1, id);  // the renderer's leaf there
      // The point is on the pixel's ray, at the first span's start.
      const Ray ray = cam.ray(x, y);
      const std::vector<RayResult> rr = model.cast(std::vector<Ray>{ray});
      const double t = rr[0].spans.at(0).t0;
      EXPECT_EQ(p.x, ray.origin.x + t * ray.dir.x);
    }
  EXPECT_GT(hits, 20);
  // With a section: the cut faces are reported as the cap where the renderer draws the cap.
  RenderOptions cut;
  cut.samples = 1;
  cut.section = Plane{{0, -1, 0}, 0};
  co.view = View::kFront;
  const Image capped = model.render(model.camera(co, cut.section), cut);
  int caps = 0;
  for (int y = 0; y < 48; y += 3)
    for (int x = 0; x < 64; x += 3) {
      auto r = s.get("/pick?w=64&h=48&view=front&section=0,-1,0,0&x=" + std::to_string(x) +
                     "&y=" + std::to_string(y));
      const json j = json::parse(r->body);
      const uint16_t id = capped.ids[static_cast<size_t>(y) * 64 + x];
      ASSERT_EQ(j["hit"].get<bool>(), id != Image::kBackgroundId) << x << "," << y;
      if (!j["hit"]) continue;
      EXPECT_EQ(j["leaf"] == "section cap", id == Image::kCapId) << x << "," << y;
      caps += id == Image::kCapId;
    }
  EXPECT_GT(caps, 10);
}

TEST(Viewer, HiddenLeavesAreLeftOutOfTheScene) {
  const std::filesystem::path scene = scene_copy();
  Served s(scene);
  // Leaves: 0 box, 1 sphere (the intersection), 2..4 cylinders (subtracted), 5 torus.
  // Hiding 2, 3, 4 and 5: the intersection alone. Hiding 0 and 1: the intersection goes, and the
  // difference's first operand left is its base. Hiding 3 and 4: a difference of two.
  const std::string dir = scene.parent_path().string();
  const std::string box = R"({"box": {"min": [-2, -2, -2], "max": [2, 2, 2]}})";
  const std::string sphere = R"({"sphere": {"center": [0, 0, 0], "radius": 2.65, "segments": 64}})";
  const std::string cx = R"({"cylinder": {"base": [-3, 0, 0], "top": [3, 0, 0], "radius": 1,
                             "segments": 48}})";
  const std::string cy = R"({"cylinder": {"base": [0, -3, 0], "top": [0, 3, 0], "radius": 1,
                             "segments": 48}})";
  const std::string cz = R"({"cylinder": {"base": [0, 0, -3], "top": [0, 0, 3], "radius": 1,
                             "segments": 48}})";
  const std::string torus = R"({"mesh": "torus.off", "transform":
      {"rotate": {"axis": [1, 0, 0], "degrees": 90}, "translate": [3.2, 0, 0]}})";
  const std::string both = R"({"intersection": [)" + box + "," + sphere + "]}";
  test::write_file(dir + "/a.json", both);
  test::write_file(dir + "/b.json", R"({"union": [{"difference": [)" + cx + "," + cy + "," + cz +
                                        "]}," + torus + "]}");
  test::write_file(dir + "/c.json",
                   R"({"union": [{"difference": [)" + both + "," + cx + "]}," + torus + "]}");
  CameraOptions co;
  co.width = 120;
  co.height = 90;
  const Image a = load(dir + "/a.json").render(co);
  EXPECT_TRUE(s.get("/frame?w=120&h=90&hidden=5,3,2,4")->body == file_png(a));
  // The other leaves keep their colours (those of their indices in the whole scene).
  RenderOptions ro;
  ro.leaf_colours = {leaf_colour(2), leaf_colour(3), leaf_colour(4), leaf_colour(5)};
  const Image b = load(dir + "/b.json").render(co, ro);
  EXPECT_TRUE(s.get("/frame?w=120&h=90&hidden=0,1")->body == file_png(b));
  EXPECT_TRUE(file_png(b) != file_png(load(dir + "/b.json").render(co)));
  ro.leaf_colours = {leaf_colour(0), leaf_colour(1), leaf_colour(2), leaf_colour(5)};
  const Image c = load(dir + "/c.json").render(co, ro);
  EXPECT_TRUE(s.get("/frame?w=120&h=90&hidden=3,4")->body == file_png(c));
  // Everything hidden: the background.
  const Image none = Model().render(co);
  EXPECT_TRUE(s.get("/frame?w=120&h=90&hidden=0,1,2,3,4,5")->body == file_png(none));
  // A mesh input: its one leaf.
  Served m(dir + "/torus.off");
  EXPECT_TRUE(m.get("/frame?w=120&h=90&hidden=0")->body == file_png(none));
}

TEST(Viewer, ReloadsWhenTheSceneOrAMeshChangesAndKeepsTheLastGoodOne) {
  const std::filesystem::path scene = scene_copy();
  ViewerOptions o;
  o.poll_seconds = 3600;  // the test calls check_files itself
  Served s(scene, o);
  EXPECT_FALSE(s.viewer.check_files());
  const std::string original = test::read_file(scene);
  const auto later = [&](const std::filesystem::path& p) {
    std::filesystem::last_write_time(p,
                                     std::filesystem::last_write_time(p) + std::chrono::seconds(2));
  };
  test::write_file(scene, "{\"union\": [");
  later(scene);
  EXPECT_TRUE(s.viewer.check_files());
  EXPECT_EQ(s.viewer.state().version, 1u);
  EXPECT_NE(s.viewer.state().error.find("scene.json"), std::string::npos);
  EXPECT_EQ(s.get("/frame?w=20&h=20")->status, 200);  // the last good model
  EXPECT_FALSE(s.viewer.check_files());               // the same broken file: not again
  test::write_file(scene, original);
  later(scene);
  EXPECT_TRUE(s.viewer.check_files());
  EXPECT_EQ(s.viewer.state().version, 2u);
  EXPECT_EQ(s.viewer.state().error, "");
  // A mesh the scene names.
  const std::filesystem::path torus = scene.parent_path() / "torus.off";
  std::string text = test::read_file(torus);
  test::write_file(torus, text + "\n");
  later(torus);
  EXPECT_TRUE(s.viewer.check_files());
  EXPECT_EQ(s.viewer.state().version, 3u);
  EXPECT_EQ(json::parse(s.get("/info")->body)["version"], 3);
}

TEST(Viewer, RefusesInputsThatDoNotLoadAndPortsInUse) {
  const std::filesystem::path dir = test::temp_dir("view-bad");
  EXPECT_THROW(Viewer(dir / "missing.json"), InputError);
  Served s(scene_copy());
  ViewerOptions o;
  o.port = s.viewer.port();
  try {
    Viewer second(scene_copy(), o);
    FAIL() << "bound a port in use";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(o.port)), std::string::npos);
  }
}

TEST(ViewerCli, BadInputExitsTwoWithOneLine) {
  const test::RunResult r = test::run_cover("view /nonexistent/scene.json");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("scene.json"), std::string::npos);
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1);
  EXPECT_EQ(test::run_cover("view '" + (test::source_dir() / "models" / "default.json").string() +
                            "' --port 70000")
                .status,
            2);
}

}  // namespace
}  // namespace cover
