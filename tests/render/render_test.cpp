// Ray-cast rendering (render/render.h): invariants against analytic geometry, not golden images.
#include "cover/render/render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

#include "cover/covering/ray.h"
#include "cover/io/mesh_io.h"
#include "cover/io/png.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

Solid box_solid(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

Image draw(const Solid& s, const Camera& cam, const RenderOptions& o = {}) {
  return render(Prepared(s), cam, o);
}

/// The cube [−1, 1]³: every test frames the same region, so pixel sizes are known.
Bbox unit_frame() {
  Bbox b;
  b.add(Vec3{-1, -1, -1});
  b.add(Vec3{1, 1, 1});
  return b;
}

Camera front(const Bbox& frame, int w, int h) {
  CameraOptions co;
  co.view = View::kFront;
  co.width = w;
  co.height = h;
  return frame_camera(frame, co);
}

size_t at(const Image& img, int x, int y) { return static_cast<size_t>(y) * img.width + x; }

TEST(Render, BoxSilhouetteMatchesProjectionPixelForPixel) {
  // Box bounds chosen off pixel centres; the camera looks along +y, so a pixel shows the box
  // iff its ray origin projects strictly inside [lo.x, hi.x] × [lo.z, hi.z].
  const Vec3 lo{-0.731, -0.4, -0.512}, hi{0.613, 0.9, 0.377};
  const Solid s = box_solid(lo, hi);
  const Bbox frame = unit_frame();
  const Camera cam = front(frame, 97, 83);
  const Image img = draw(s, cam);
  int inside = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Ray r = cam.ray(x, y);
      ASSERT_EQ(r.dir, (Vec3{0, 1, 0}));
      const bool expected =
          r.origin.x > lo.x && r.origin.x < hi.x && r.origin.z > lo.z && r.origin.z < hi.z;
      inside += expected;
      ASSERT_EQ(img.ids[at(img, x, y)] == 1, expected) << x << "," << y;
      ASSERT_EQ(img.ids[at(img, x, y)] == Image::kBackgroundId, !expected);
    }
  EXPECT_GT(inside, 400);
}

TEST(Render, SphereSilhouetteWithinPolygonApproximation) {
  const Vec3 c{0.1, 0.2, -0.05};
  const double r = 0.8;
  const int segments = 64;  // 64 slices, 32 stacks
  const Solid s = make_leaf(make_sphere(c, r, segments), "sphere");
  // The polyhedron lies between the circumscribed sphere r and an inscribed one: every face's
  // vertices are within angle sqrt((π/64)² + (π/64)²) of its centre direction.
  const double r_in = r * std::cos(std::hypot(M_PI / 64, M_PI / 64) * 1.01);
  const Bbox frame = unit_frame();
  const Camera cam = front(frame, 120, 120);
  const Image img = draw(s, cam);
  int checked = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Ray ray = cam.ray(x, y);
      const double d = std::hypot(ray.origin.x - c.x, ray.origin.z - c.z);
      const bool hit = img.ids[at(img, x, y)] == 1;
      if (d < r_in) {
        ASSERT_TRUE(hit) << x << "," << y;
      }
      if (d > r) {
        ASSERT_FALSE(hit) << x << "," << y;
      }
      checked += d < r_in || d > r;
    }
  EXPECT_GT(checked, 120 * 120 * 9 / 10);
}

TEST(Render, SectionCapExactlyWhereTheCutIs) {
  // Remove y < 0.25 (n = (0,−1,0), d = −0.25): seen from the front, every ray through the box's
  // projection meets the cap at y = 0.25; its depth is analytic.
  const Vec3 lo{-0.6, -0.5, -0.45}, hi{0.55, 0.7, 0.38};
  const Solid s = box_solid(lo, hi);
  const Bbox frame = unit_frame();
  const Camera cam = front(frame, 90, 70);
  RenderOptions o;
  o.section = Plane{{0, -1, 0}, -0.25};
  const Image img = draw(s, cam, o);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Ray r = cam.ray(x, y);
      const bool in =
          r.origin.x > lo.x && r.origin.x < hi.x && r.origin.z > lo.z && r.origin.z < hi.z;
      ASSERT_EQ(img.ids[at(img, x, y)], in ? Image::kCapId : Image::kBackgroundId) << x << "," << y;
      if (in) {
        EXPECT_GT(img.rgb[3 * at(img, x, y)], img.rgb[3 * at(img, x, y) + 1]);  // reddish cap
      }
    }
  // A section plane that misses the solid leaves it untouched; one that removes all of it leaves
  // nothing.
  o.section = Plane{{0, 1, 0}, 5};
  EXPECT_EQ(draw(s, cam, o).ids, draw(s, cam).ids);
  o.section = Plane{{0, 1, 0}, -5};
  for (uint16_t id : draw(s, cam, o).ids) ASSERT_EQ(id, Image::kBackgroundId);
}

TEST(Render, DepthMatchesAnalyticDepthOnABox) {
  const Vec3 lo{-0.5, -0.3, -0.5}, hi{0.5, 0.6, 0.5};
  const Solid s = box_solid(lo, hi);
  const Bbox frame = unit_frame();
  const Camera cam = front(frame, 64, 64);
  const Image img = draw(s, cam);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Ray r = cam.ray(x, y);
      if (img.ids[at(img, x, y)] != 1) continue;
      const double t = lo.y - r.origin.y;  // the front face y = lo.y
      const double expected = (t - cam.near) / (cam.far - cam.near) * 65534;
      ASSERT_NEAR(img.depth[at(img, x, y)], expected, 0.5 + 1e-9) << x << "," << y;
    }
}

TEST(Render, DifferenceShowsTheSubtrahendOnCarvedSurfaces) {
  // A box with a spherical bite out of its front face: the bite shows leaf 2 (B), the rest of the
  // front face leaf 1 (A).
  const Solid a = box_solid({-0.8, -0.5, -0.8}, {0.8, 0.5, 0.8});
  const Solid b = make_leaf(make_sphere({0, -0.5, 0}, 0.45, 48), "bite");
  const Solid d = subtract({a, b});
  const Bbox frame = unit_frame();
  const Camera cam = front(frame, 101, 101);
  const Image img = draw(d, cam);
  int carved = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Ray r = cam.ray(x, y);
      const double rad = std::hypot(r.origin.x, r.origin.z);
      const uint16_t id = img.ids[at(img, x, y)];
      if (rad < 0.45 * 0.98) {
        ASSERT_EQ(id, 2) << x << "," << y;
        ++carved;
      } else if (rad > 0.46 && std::abs(r.origin.x) < 0.79 && std::abs(r.origin.z) < 0.79) {
        ASSERT_EQ(id, 1) << x << "," << y;
      }
    }
  EXPECT_GT(carved, 300);
}

TEST(Render, SameImageWithOneAndTwoThreadsAndPngRoundTrip) {
  const Solid s = unite(
      {subtract({box_solid({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "s")}),
       make_leaf(make_cylinder({0, 0, -1}, {0, 0, 3}, 0.6, 20), "c")});
  const Bbox frame = s.bbox();
  for (bool perspective : {false, true}) {
    CameraOptions co;
    co.perspective = perspective;
    co.width = 160;
    co.height = 120;
    const Camera cam = frame_camera(frame, co);
    RenderOptions o;
    o.section = Plane{{1, 1, 0}, 2.5};
    Image one, two;
    {
      ThreadLimit limit(1);
      one = draw(s, cam, o);
    }
    {
      ThreadLimit limit(2);
      two = draw(s, cam, o);
    }
    EXPECT_EQ(one.rgb, two.rgb);
    EXPECT_EQ(one.depth, two.depth);
    EXPECT_EQ(one.ids, two.ids);
    const auto dir = test::temp_dir("png");
    write_png_rgb(dir / "c.png", one.width, one.height, one.rgb);
    write_png_gray16(dir / "d.png", one.width, one.height, one.depth);
    const PngImage c = read_png(dir / "c.png"), d = read_png(dir / "d.png");
    EXPECT_EQ(c.width, 160);
    EXPECT_EQ(std::vector<uint16_t>(one.rgb.begin(), one.rgb.end()), c.values);
    EXPECT_EQ(d.values, std::vector<uint16_t>(one.depth.begin(), one.depth.end()));
    std::filesystem::remove_all(dir);
  }
}

// Issue 24: the frame's front-to-back path (first_visible over the BVH, prefetching, tiles) must
// give every pixel exactly what the full cast() of its ray gives (all hits, CSG spans), the
// independent path of covering/ray.h: same leaf id, same depth, caps where the section cuts.
TEST(Render, EveryPixelIsTheVisiblePointOfTheFullCast) {
  const Solid s = unite(
      {subtract({box_solid({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "s")}),
       intersect({make_leaf(make_cylinder({0, 0, -1}, {0, 0, 3}, 0.6, 20), "c"),
                  box_solid({-1, -1, 0.5}, {1, 1, 2.5})}),
       make_leaf(make_sphere({1, 1, 1}, 0.3, 12), "inner")});  // hidden inside the box
  const Prepared prepared(s);
  const Bvh& bvh = prepared.bvh();
  for (bool perspective : {false, true})
    for (bool cut : {false, true}) {
      CameraOptions co;
      co.perspective = perspective;
      co.width = 96;
      co.height = 80;
      const Camera cam = frame_camera(s.bbox(), co);
      RenderOptions o;
      if (cut) o.section = Plane{{1, -1, 1}, 1.2};  // faces the iso eye: caps on the box
      const Image img = render(prepared, cam, o);
      int surface = 0, caps = 0;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
          const Ray ray = cam.ray(x, y);
          double lo = 0, hi = INFINITY;  // render.cpp allowed(): the ray outside n·x > d
          if (cut) {
            const double sd = dot(o.section->normal, ray.dir);
            const double v0 = dot(o.section->normal, ray.origin) - o.section->offset;
            if (sd == 0 && v0 > 0) lo = 1, hi = 0;
            if (sd > 0) hi = -v0 / sd;
            if (sd < 0) lo = std::max(0.0, -v0 / sd);
          }
          const VisibleHit v = lo > hi
                                   ? VisibleHit{}
                                   : first_visible(cast(bvh, s.tree, s.leaves.size(), ray), lo, hi);
          const uint16_t want = !v.hit  ? Image::kBackgroundId
                                : v.cap ? Image::kCapId
                                        : static_cast<uint16_t>(v.enter.leaf + 1);
          ASSERT_EQ(img.ids[at(img, x, y)], want) << x << "," << y;
          if (!v.hit) continue;
          surface += !v.cap;
          caps += v.cap;
          const double f = (v.t - cam.near) / (cam.far - cam.near);
          ASSERT_EQ(img.depth[at(img, x, y)], std::lround(std::clamp(f, 0.0, 1.0) * 65534))
              << x << "," << y;
        }
      EXPECT_GT(surface, cut ? 100 : 500);
      if (cut) {
        EXPECT_GT(caps, 20);
      }
    }
}

// The object-order path (render/object_order.h) against the BVH walk per ray: the same bytes in
// every buffer, over CSG with caps, a complement at the root, a real mesh, polygon faces, pixel
// centres exactly on box edges and vertices (the perturbation decides), odd sizes and tiles.
TEST(Render, ObjectOrderEqualsRaysByteForByte) {
  const Solid csg = unite(
      {subtract({box_solid({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "s")}),
       intersect({make_leaf(make_cylinder({0, 0, -1}, {0, 0, 3}, 0.6, 20), "c"),
                  box_solid({-1, -1, 0.5}, {1, 1, 2.5})}),
       make_leaf(make_sphere({1, 1, 1}, 0.3, 12), "inner")});
  // Unit boxes on a grid of the pixel size: the front view of the unit frame at 64² has pixel
  // centres on ±k/32·(frame size), so some rays run exactly along faces, edges and vertices.
  const Solid grid = subtract({box_solid({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}),
                               box_solid({-0.25, -1, -0.25}, {0.25, 0.25, 0.25}),
                               box_solid({0, 0, 0}, {0.75, 0.75, 0.75})});
  const Solid outside = complement(box_solid({-0.3, -0.3, -0.3}, {0.3, 0.3, 0.3}));
  const Solid bunny = subtract({make_leaf(read_mesh(test::cgal_mesh("bunny00.off")), "bunny"),
                                make_leaf(make_sphere({0, 0, 0}, 0.04, 32), "ball")});
  struct Case {
    const Solid* solid;
    Bbox frame;
  };
  const std::vector<Case> cases = {
      {&csg, csg.bbox()}, {&grid, unit_frame()}, {&outside, unit_frame()}, {&bunny, bunny.bbox()}};
  int compared = 0;
  for (const Case& c : cases) {
    const Prepared prepared(*c.solid);
    for (View view : {View::kIso, View::kFront, View::kTop, View::kLeft})
      for (const auto& [w, h, az] : {std::tuple{64, 64, 0.0}, std::tuple{97, 61, 30.0}})
        for (bool cut : {false, true}) {
          CameraOptions co;
          co.view = view;
          co.width = w;
          co.height = h;
          co.azimuth_degrees = az;
          co.perspective = w == 97;  // the odd size in perspective
          const Camera cam = frame_camera(c.frame, co);
          RenderOptions rays, objects;
          rays.method = RenderMethod::kRays;
          objects.method = RenderMethod::kObjectOrder;
          objects.tile = w == 64 ? 32 : 7;
          if (cut) rays.section = objects.section = Plane{{1, -1, 1}, 0.1};
          const Image a = render(prepared, cam, rays);
          const Image b = render(prepared, cam, objects);
          ASSERT_TRUE(a.ids == b.ids) << to_string(view) << " " << w << " " << cut;
          ASSERT_TRUE(a.depth == b.depth) << to_string(view) << " " << w << " " << cut;
          ASSERT_TRUE(a.rgb == b.rgb) << to_string(view) << " " << w << " " << cut;
          compared += static_cast<int>(std::count_if(
              a.ids.begin(), a.ids.end(), [](uint16_t id) { return id != Image::kBackgroundId; }));
        }
  }
  EXPECT_GT(compared, 50000);
  // Box faces, edges and corners exactly on pixel rays: boxes spanned by ray origins of the front
  // view (direction +y), so those rays graze faces and pass through edges and vertices.
  const Camera cam = front(unit_frame(), 64, 64);
  auto o = [&](int x, int y) { return cam.ray(x, y).origin; };
  auto span = [&](Vec3 a, Vec3 b, double y0, double y1) {
    return box_solid({std::min(a.x, b.x), y0, std::min(a.z, b.z)},
                     {std::max(a.x, b.x), y1, std::max(a.z, b.z)});
  };
  const Solid aligned = unite(
      {subtract({span(o(10, 50), o(40, 20), -0.5, 0.5), span(o(25, 35), o(45, 10), -0.6, 0.2)}),
       span(o(40, 20), o(55, 5), 0.1, 0.3)});  // touches at o(40, 20)
  const Prepared prepared(aligned);
  for (bool cut : {false, true}) {
    RenderOptions rays, objects;
    rays.method = RenderMethod::kRays;
    objects.method = RenderMethod::kObjectOrder;
    if (cut) rays.section = objects.section = Plane{{0, 1, 0}, 0};
    const Image a = render(prepared, cam, rays);
    const Image b = render(prepared, cam, objects);
    ASSERT_TRUE(a.ids == b.ids && a.depth == b.depth && a.rgb == b.rgb) << cut;
    EXPECT_NE(a.ids[at(a, 10, 35)], Image::kBackgroundId);  // on the big box's face x = lo.x
  }
  // A perspective eye inside the scene (triangles behind it, beside it and across its plane)
  // and looking along an axis (rays along faces).
  for (const Vec3& eye : {Vec3{1, 1, 1}, Vec3{0.5, -3, 0.25}}) {
    CameraOptions co;
    co.perspective = true;
    co.width = 80;
    co.height = 60;
    Camera cam = frame_camera(csg.bbox(), co);
    cam.eye = eye;
    if (eye.y < 0) cam.forward = {0, 1, 0}, cam.right = {1, 0, 0}, cam.up = {0, 0, 1};
    RenderOptions rays, objects;
    rays.method = RenderMethod::kRays;
    objects.method = RenderMethod::kObjectOrder;
    const Prepared prepared(csg);
    const Image a = render(prepared, cam, rays);
    const Image b = render(prepared, cam, objects);
    ASSERT_TRUE(a.ids == b.ids && a.depth == b.depth && a.rgb == b.rgb) << eye.y;
    EXPECT_GT(std::count_if(a.ids.begin(), a.ids.end(),
                            [](uint16_t id) { return id != Image::kBackgroundId; }),
              100);
  }
  // Where it does not apply it says so: an open leaf.
  PolygonMesh open = make_box({0, 0, 0}, {1, 1, 1});
  open.face_start.pop_back();
  open.face_vertices.resize(open.face_start.back());
  LoadOptions lenient;
  lenient.require_closed = false;
  std::vector<std::string> warnings;
  const Solid open_solid = prepare_leaf(open, "open", "open", lenient, warnings);
  ASSERT_TRUE(open_solid.has_open_leaf());
  RenderOptions objects;
  objects.method = RenderMethod::kObjectOrder;
  EXPECT_THROW(render(Prepared(open_solid), frame_camera(open_solid.bbox(), {}), objects),
               InputError);
}

// Issue 17, group 8: long renders showed no progress bar; the callback drives it.
TEST(Render, ReportsProgressWithoutChangingTheImage) {
  const Solid s =
      subtract({box_solid({-1, -1, -1}, {1, 1, 1}), make_leaf(make_sphere({1, 1, 1}, 1, 16), "s")});
  const Camera cam = front(unit_frame(), 100, 70);
  RenderOptions o;
  o.tile = 16;  // 7 × 5 tiles
  std::vector<std::pair<size_t, size_t>> calls;
  Image with, without;
  {
    ThreadLimit limit(2);
    without = draw(s, cam, o);
    o.progress = [&calls](size_t done, size_t total) { calls.emplace_back(done, total); };
    with = draw(s, cam, o);
  }
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls.back(), (std::pair<size_t, size_t>{35, 35}));
  for (size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].second, 35u);
  for (size_t i = 1; i < calls.size(); ++i) EXPECT_LE(calls[i - 1].first, calls[i].first);
  EXPECT_EQ(with.rgb, without.rgb);
  EXPECT_EQ(with.ids, without.ids);
}

}  // namespace
}  // namespace cover
