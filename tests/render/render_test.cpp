// Ray-cast rendering (render/render.h): invariants against analytic geometry, not golden images.
#include "cover/render/render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/io/mesh_io.h"
#include "cover/io/png.h"
#include "cover/io/scene.h"
#include "cover/render/shading.h"
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
  // Tiles of 16: 7 × 5 for one ray per pixel; with samples 2, those of the 200 × 140 sub-pixel
  // image (13 × 9), which the pixel-centre pass reports as done.
  for (const auto& [samples, tiles] : {std::pair{1, size_t{35}}, std::pair{2, size_t{117}}}) {
    RenderOptions o;
    o.tile = 16;
    o.samples = samples;
    std::vector<std::pair<size_t, size_t>> calls;
    Image with, without;
    {
      ThreadLimit limit(2);
      without = draw(s, cam, o);
      o.progress = [&calls](size_t done, size_t total) { calls.emplace_back(done, total); };
      with = draw(s, cam, o);
    }
    ASSERT_FALSE(calls.empty());
    EXPECT_EQ(calls.back(), (std::pair<size_t, size_t>{tiles, tiles}));
    for (size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].second, tiles);
    for (size_t i = 1; i < calls.size(); ++i) EXPECT_LE(calls[i - 1].first, calls[i].first);
    EXPECT_EQ(with.rgb, without.rgb);
    EXPECT_EQ(with.ids, without.ids);
  }
}

// Issue 46 (camera): up axis, elevation, zoom, tight box framing, turntable framing, section box.

/// The occupied rows and columns of an image (pixels with a leaf or cap): max − min + 1 each.
struct Span {
  int rows = 0, cols = 0;
};
Span silhouette(const Image& img) {
  int x0 = img.width, x1 = -1, y0 = img.height, y1 = -1;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (img.ids[at(img, x, y)] != Image::kBackgroundId) {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
  return x1 < 0 ? Span{} : Span{y1 - y0 + 1, x1 - x0 + 1};
}

/// (sx, sy): where a point lands in pixels from the image centre (right, up).
std::pair<double, double> project(const Camera& c, Vec3 p) {
  const Vec3 d = p - c.eye;
  if (!c.perspective) return {dot(d, c.right) / c.pixel_size, dot(d, c.up) / c.pixel_size};
  const double scale = 2 * c.tan_half_fov / std::min(c.width, c.height);
  const double depth = dot(d, c.forward);
  return {dot(d, c.right) / (depth * scale), dot(d, c.up) / (depth * scale)};
}

std::vector<Vec3> corners(const Bbox& b) {
  std::vector<Vec3> out;
  for (int k = 0; k < 8; ++k)
    out.push_back(
        {k & 1 ? b.max.x : b.min.x, k & 2 ? b.max.y : b.min.y, k & 4 ? b.max.z : b.min.z});
  return out;
}

double box_support_of(const Bbox& b, Vec3 d) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += std::max(d[k] * b.min[k], d[k] * b.max[k]);
  return s;
}

Bbox make_bbox(Vec3 lo, Vec3 hi) {
  Bbox b;
  b.add(lo);
  b.add(hi);
  return b;
}

TEST(Camera, DefaultIsoLooksAlongTheDiagonalWithZUp) {
  const Camera c = frame_camera(unit_frame(), {});
  const double k = 1 / std::sqrt(3.0);
  EXPECT_NEAR(c.forward.x, -k, 1e-15);
  EXPECT_NEAR(c.forward.y, k, 1e-15);
  EXPECT_NEAR(c.forward.z, -k, 1e-15);
  EXPECT_EQ(c.right.z, 0);
  EXPECT_GT(c.up.z, 0);
  EXPECT_NEAR(view_elevation_degrees(View::kIso), std::asin(k) * 180 / M_PI, 1e-12);
  // The same direction from an explicit elevation, within rounding.
  CameraOptions co;
  co.elevation_degrees = view_elevation_degrees(View::kIso);
  const Camera e = frame_camera(unit_frame(), co);
  EXPECT_NEAR(dot(e.forward, c.forward), 1, 1e-15);
  EXPECT_NEAR(dot(e.up, c.up), 1, 1e-15);
}

TEST(Camera, ElevationAndUpAxisSetTheDirection) {
  for (UpAxis up : {UpAxis::kZ, UpAxis::kY, UpAxis::kX})
    for (View view : {View::kIso, View::kFront, View::kLeft, View::kTop})
      for (double elevation : {-90.0, -30.0, 0.0, 20.0, 60.0, 90.0}) {
        CameraOptions co;
        co.view = view;
        co.up = up;
        co.elevation_degrees = elevation;
        co.azimuth_degrees = 25;
        const Camera c = frame_camera(unit_frame(), co);
        const double from_up = -c.forward[static_cast<int>(up == UpAxis::kX   ? 0
                                                           : up == UpAxis::kY ? 1
                                                                              : 2)];
        EXPECT_NEAR(std::asin(std::clamp(from_up, -1.0, 1.0)) * 180 / M_PI, elevation, 1e-9)
            << to_string(up) << " " << to_string(view) << " " << elevation;
        EXPECT_NEAR(dot(c.right, c.up), 0, 1e-15);
        EXPECT_NEAR(dot(c.forward, c.up), 0, 1e-15);
      }
  // Elevation 90 from the front is the top view; exact axes for the named views.
  CameraOptions co;
  co.view = View::kFront;
  co.elevation_degrees = 90;
  const Camera top = frame_camera(unit_frame(), co);
  EXPECT_EQ(top.forward, (Vec3{0, 0, -1}));
  EXPECT_EQ(top.up, (Vec3{0, 1, 0}));
  co = {};
  co.view = View::kFront;
  co.up = UpAxis::kY;  // the Y-up convention: front from +z, right +x
  const Camera front_y = frame_camera(unit_frame(), co);
  EXPECT_EQ(front_y.forward, (Vec3{0, 0, -1}));
  EXPECT_EQ(front_y.right, (Vec3{1, 0, 0}));
  EXPECT_EQ(front_y.up, (Vec3{0, 1, 0}));
}

TEST(Camera, YUpModelStandsUprightWithUpY) {
  // A tall thin box along y: upright (taller than wide) with up y, lying with the default z.
  const Solid s = box_solid({-0.2, -1, -0.2}, {0.2, 1, 0.2});
  for (bool perspective : {false, true})
    for (View view : {View::kIso, View::kFront, View::kLeft}) {
      CameraOptions co;
      co.view = view;
      co.perspective = perspective;
      co.width = 120;
      co.height = 90;
      co.up = UpAxis::kY;
      const Span upright = silhouette(draw(s, frame_camera(s.bbox(), co)));
      EXPECT_GT(upright.rows, 2 * upright.cols) << to_string(view) << perspective;
      co.up = UpAxis::kZ;
      if (view == View::kFront) continue;  // from −y with z up the box is seen end-on
      const Span lying = silhouette(draw(s, frame_camera(s.bbox(), co)));
      EXPECT_GT(lying.cols, lying.rows) << to_string(view) << perspective;
    }
}

TEST(Camera, BoxCornersFitTheFrameTightly) {
  const std::vector<Bbox> boxes = {unit_frame(), make_bbox({-2, -1, 0}, {5, 1, 0.5}),
                                   make_bbox({0, 0, 0}, {1, 1, 0}),  // flat
                                   make_bbox({1, 2, 3}, {1.5, 9, 3.25})};
  for (const Bbox& box : boxes)
    for (View view : {View::kIso, View::kFront, View::kRight, View::kTop, View::kBottom})
      for (bool perspective : {false, true})
        for (const auto& [w, h] : {std::pair{80, 60}, std::pair{50, 90}}) {
          CameraOptions co;
          co.view = view;
          co.perspective = perspective;
          co.width = w;
          co.height = h;
          co.azimuth_degrees = view == View::kRight ? 20 : 0;
          const Camera c = frame_camera(box, co);
          double fill = 0;  // the largest share of the half image a corner reaches
          for (const Vec3& p : corners(box)) {
            const auto [sx, sy] = project(c, p);
            ASSERT_LE(std::abs(sx), 0.5 * w / 1.08 + 1e-9);
            ASSERT_LE(std::abs(sy), 0.5 * h / 1.08 + 1e-9);
            fill = std::max({fill, std::abs(sx) / (0.5 * w), std::abs(sy) / (0.5 * h)});
            // near..far holds the corner's t along its pixel ray (a distance).
            const double t =
                perspective ? std::sqrt(dot(p - c.eye, p - c.eye)) : dot(p - c.eye, c.forward);
            EXPECT_GE(t, c.near);
            EXPECT_LE(t, c.far);
          }
          EXPECT_NEAR(fill, 1 / 1.08, 1e-9) << to_string(view) << perspective << w;
          EXPECT_GT(c.near, 0);
          EXPECT_LT(c.near, c.far);
        }
}

TEST(Camera, ZoomMagnifiesAboutTheCentre) {
  const Solid s = subtract({box_solid({-1, -0.5, -0.7}, {1.2, 0.5, 0.7}),
                            make_leaf(make_sphere({1, 0, 0}, 0.6, 24), "s")});
  for (bool perspective : {false, true})
    for (double zoom : {0.25, 0.5}) {  // zoom and 2·zoom both fit the frame
      CameraOptions co;
      co.perspective = perspective;
      co.width = 160;
      co.height = 120;
      co.zoom = zoom;
      const Span one = silhouette(draw(s, frame_camera(s.bbox(), co)));
      co.zoom = 2 * zoom;
      const Span two = silhouette(draw(s, frame_camera(s.bbox(), co)));
      EXPECT_NEAR(two.rows, 2 * one.rows, 2) << perspective << zoom;
      EXPECT_NEAR(two.cols, 2 * one.cols, 2) << perspective << zoom;
      EXPECT_GT(one.cols, 20);
    }
}

TEST(Camera, TurntableKeepsOneFramingForEveryAzimuth) {
  const Bbox box = make_bbox({-3, -1, 0}, {4, 0.5, 2});  // an uneven footprint
  for (bool perspective : {false, true}) {
    CameraOptions co;
    co.perspective = perspective;
    co.turntable = true;
    const Camera first = frame_camera(box, co);
    for (int k = 1; k < 12; ++k) {
      co.azimuth_degrees = 30.0 * k;
      const Camera c = frame_camera(box, co);
      EXPECT_NEAR(c.pixel_size, first.pixel_size, 1e-12 * first.pixel_size);
      EXPECT_NEAR(c.tan_half_fov, first.tan_half_fov, 1e-15);
      EXPECT_NEAR(std::sqrt(dot(c.eye - c.target, c.eye - c.target)),
                  std::sqrt(dot(first.eye - first.target, first.eye - first.target)), 1e-9);
      EXPECT_NEAR(c.near, first.near, 1e-9);
      EXPECT_NEAR(c.far, first.far, 1e-9);
      for (const Vec3& p : corners(box)) {
        const auto [sx, sy] = project(c, p);
        EXPECT_LE(std::abs(sx), 0.5 * c.width);
        EXPECT_LE(std::abs(sy), 0.5 * c.height);
      }
    }
  }
}

TEST(Camera, SectionBoxHoldsTheKeptPartTightly) {
  const Bbox box = make_bbox({-1, -2, -3}, {1, 2, 3});
  Bbox kept = section_box(box, Plane{{0, 0, 1}, 0.5});  // keeps z ≤ 0.5
  EXPECT_EQ(kept.min, box.min);
  EXPECT_EQ(kept.max.x, 1);
  EXPECT_EQ(kept.max.y, 2);
  EXPECT_NEAR(kept.max.z, 0.5, 1e-9);
  EXPECT_GE(kept.max.z, 0.5);
  kept = section_box(box, Plane{{-1, -1, 0}, -2.5});  // keeps x + y ≥ 2.5
  EXPECT_NEAR(kept.min.x, 0.5, 1e-9);
  EXPECT_NEAR(kept.min.y, 1.5, 1e-9);
  EXPECT_LE(kept.min.x, 0.5);
  EXPECT_EQ(kept.max, box.max);
  EXPECT_TRUE(section_box(box, Plane{{1, 1, 1}, -7}).empty());    // x + y + z ≥ −6 in the box
  EXPECT_EQ(section_box(box, Plane{{1, 0, 0}, 5}).min, box.min);  // keeps it all
  // Sound: random points of the box on the kept side lie in the section box.
  std::mt19937_64 rng(46);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Plane p{{u(rng), u(rng), u(rng)}, 2 * u(rng)};
    const Bbox k = section_box(box, p);
    for (int i = 0; i < 200; ++i) {
      const Vec3 x{u(rng), 2 * u(rng), 3 * u(rng)};
      if (dot(p.normal, x) <= p.offset) {
        ASSERT_FALSE(k.empty());
        ASSERT_TRUE(k.contains(x)) << trial;
      }
    }
  }
}

TEST(Camera, ResultSupportBoundsTheResultThroughTheTree) {
  const Solid a = box_solid({-1, -1, -1}, {1, 1, 1});
  const Solid ball = make_leaf(make_sphere({3, 0, 0}, 0.5, 16), "ball");
  const Solid small = box_solid({0.2, 0.2, 0.2}, {0.4, 0.3, 0.6});
  const Vec3 x{1, 0, 0}, mx{-1, 0, 0}, diag{1, 1, 1};
  const Solid u = unite({a, ball});
  EXPECT_NEAR(result_support(u, x), 3.5, 1e-12);  // the ball's pole vertex
  EXPECT_EQ(result_support(u, mx), 1);
  EXPECT_NEAR(result_support(intersect({a, small}), diag), 1.3, 1e-15);  // the least of two
  EXPECT_EQ(result_support(subtract({small, a}), x), 0.4);               // A − B within A
  EXPECT_EQ(result_support(complement(a), x), INFINITY);
  EXPECT_EQ(result_support(subtract({a, complement(small)}), x), 0.4);  // A ∩ small
  // Sound on a CSG scene: points classified inside never pass the bound.
  const Solid csg = unite(
      {subtract({box_solid({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "s")}),
       intersect({make_leaf(make_cylinder({0, 0, -1}, {0, 0, 3}, 0.6, 20), "c"),
                  box_solid({-1, -1, 0.5}, {1, 1, 2.5})})});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-1, 3), direction(-1, 1);
  std::vector<Vec3> points(20000);
  for (Vec3& p : points) p = {coordinate(rng), coordinate(rng), coordinate(rng)};
  const std::vector<PointClass> classes = classify(csg, points);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 d{direction(rng), direction(rng), direction(rng)};
    const double bound = result_support(csg, d);
    double reached = -INFINITY;
    for (size_t i = 0; i < points.size(); ++i)
      if (classes[i] != PointClass::kOutside) reached = std::max(reached, dot(d, points[i]));
    EXPECT_LE(reached, bound) << trial;
    EXPECT_LE(bound, box_support_of(csg.bbox(), d) + 1e-12) << trial;
  }
}

TEST(Camera, SupportFramesTheSilhouetteInsideTheImage) {
  // A ball in a corner of a tall box's box: framed on the leaves' vertices, the silhouette
  // fills 1/1.08 of the limiting side (less the facets' rounding) and stays inside.
  const Solid s = unite({make_leaf(make_sphere({0, 0, 0}, 1, 32), "ball"),
                         make_leaf(make_cylinder({2, 2, -1}, {2, 2, 3}, 0.1, 12), "rod")});
  const Bbox box = s.bbox();
  const Support support = [&](Vec3 d) { return result_support(s, d); };
  for (bool perspective : {false, true})
    for (View view : {View::kIso, View::kFront, View::kTop}) {
      CameraOptions co;
      co.view = view;
      co.perspective = perspective;
      co.width = 120;
      co.height = 90;
      const Camera cam = frame_camera(box, co, support);
      const Image img = draw(s, cam);
      const Span sp = silhouette(img);
      EXPECT_GE(std::max(sp.rows / 90.0, sp.cols / 120.0), 0.85) << to_string(view) << perspective;
      for (int x = 0; x < img.width; ++x)
        ASSERT_TRUE(img.ids[at(img, x, 0)] == 0 && img.ids[at(img, x, img.height - 1)] == 0);
      for (int y = 0; y < img.height; ++y)
        ASSERT_TRUE(img.ids[at(img, 0, y)] == 0 && img.ids[at(img, img.width - 1, y)] == 0);
      // near..far holds the solid (orthographic: the whole box).
      auto t_of = [&](Vec3 p) {
        return perspective ? std::sqrt(dot(p - cam.eye, p - cam.eye))
                           : dot(p - cam.eye, cam.forward);
      };
      for (const Vec3& p : s.vertices) {
        EXPECT_GE(t_of(p), cam.near);
        EXPECT_LE(t_of(p), cam.far);
      }
      for (const Vec3& p : corners(box)) {
        EXPECT_LE(t_of(p), cam.far);
        if (!perspective) EXPECT_GE(t_of(p), cam.near);
      }
      EXPECT_GT(cam.near, 0);
    }
}

TEST(Camera, BadOptionsAreInputErrorsNamingTheParameter) {
  auto message = [](const CameraOptions& co) {
    try {
      frame_camera(unit_frame(), co);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  for (double zoom : {0.0, -1.0, double(NAN), double(INFINITY)}) {
    CameraOptions co;
    co.zoom = zoom;
    EXPECT_EQ(message(co).rfind("zoom: expected a positive number", 0), 0u) << message(co);
  }
  CameraOptions co;
  co.elevation_degrees = 91;
  EXPECT_EQ(message(co), "elevation: expected a number from -90 to 90, got 91");
  co = {};
  co.azimuth_degrees = double(NAN);
  EXPECT_EQ(message(co).rfind("azimuth: expected a finite number", 0), 0u);
  EXPECT_EQ(parse_up("y"), UpAxis::kY);
  try {
    parse_up("w");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "up: expected x, y or z, got 'w'");
  }
}

TEST(Camera, SameImageWithOneAndTwoThreadsForEveryOption) {
  const Solid s = subtract({box_solid({-1, -0.5, -0.7}, {1.2, 0.5, 0.7}),
                            make_leaf(make_sphere({1, 0, 0}, 0.6, 24), "s")});
  CameraOptions co;
  co.width = 96;
  co.height = 72;
  co.up = UpAxis::kY;
  co.elevation_degrees = 20;
  co.azimuth_degrees = 33;
  co.zoom = 1.7;
  for (bool perspective : {false, true}) {
    co.perspective = perspective;
    const Camera cam = frame_camera(s.bbox(), co);
    Image one, two;
    {
      ThreadLimit limit(1);
      one = draw(s, cam);
    }
    {
      ThreadLimit limit(2);
      two = draw(s, cam);
    }
    EXPECT_EQ(one.rgb, two.rgb);
    EXPECT_EQ(one.depth, two.depth);
    EXPECT_GT(silhouette(one).rows, 0);
  }
}

TEST(Render, AntiAliasingIsTheMeanOfTheSubPixelImage) {
  // samples S: the colour of each pixel is the rounded mean of an S-times-finer render's S×S
  // pixels (computed here from that render, one ray per pixel, outlines off); depth and ids are
  // the one-ray render's; any thread count gives the same bytes; silhouettes get in-between
  // colours a one-ray image does not have.
  const Solid s = subtract({make_leaf(make_box({-0.8, -0.7, -0.6}, {0.7, 0.8, 0.5}), "box"),
                            make_leaf(make_sphere({0.3, -0.2, 0.4}, 0.55, 24), "ball")});
  for (const bool perspective : {false, true})
    for (const int samples : {2, 3}) {
      CameraOptions co;
      co.perspective = perspective;
      co.width = 61;
      co.height = 47;
      const Camera cam = frame_camera(unit_frame(), co);
      RenderOptions plain;
      plain.outline = false;
      plain.samples = 1;
      RenderOptions aa = plain;
      aa.samples = samples;
      const Image one = draw(s, cam, plain), img = draw(s, cam, aa);
      Camera fine = cam;
      fine.width *= samples;
      fine.height *= samples;
      fine.pixel_size /= samples;
      const Image sub = draw(s, fine, plain);
      EXPECT_EQ(img.ids, one.ids);
      EXPECT_EQ(img.depth, one.depth);
      int mismatches = 0;
      for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x)
          for (int ch = 0; ch < 3; ++ch) {
            int sum = 0;
            for (int b = 0; b < samples; ++b)
              for (int a = 0; a < samples; ++a)
                sum += sub.rgb[3 * at(sub, samples * x + a, samples * y + b) + ch];
            const int n = samples * samples;
            mismatches += img.rgb[3 * at(img, x, y) + ch] != (sum + n / 2) / n;
          }
      EXPECT_EQ(mismatches, 0) << perspective << " " << samples;
      auto colours = [](const Image& i) {
        std::vector<uint32_t> c;
        for (size_t p = 0; p < i.rgb.size(); p += 3)
          c.push_back(i.rgb[p] << 16 | i.rgb[p + 1] << 8 | i.rgb[p + 2]);
        std::sort(c.begin(), c.end());
        return std::unique(c.begin(), c.end()) - c.begin();
      };
      EXPECT_GT(colours(img), colours(one) + 20) << perspective << " " << samples;
      RenderOptions outlined;
      outlined.samples = samples;
      Image a, b;
      {
        ThreadLimit limit(1);
        a = draw(s, cam, outlined);
      }
      {
        ThreadLimit limit(2);
        b = draw(s, cam, outlined);
      }
      EXPECT_TRUE(a.rgb == b.rgb && a.ids == b.ids && a.depth == b.depth);
      EXPECT_EQ(a.ids, one.ids);
    }
  RenderOptions bad;
  bad.samples = kMaxRenderSamples + 1;
  EXPECT_THROW(draw(s, front(unit_frame(), 8, 8), bad), PreconditionError);
}

}  // namespace
}  // namespace cover

namespace cover {
namespace {

TEST(Camera, PanMovesTheViewAcrossTheImagePlane) {
  const Bbox box{{-1, -2, 0}, {3, 1, 2}};
  for (bool perspective : {false, true}) {
    CameraOptions co;
    co.width = 128;
    co.height = 96;
    co.perspective = perspective;
    co.zoom = 1.5;
    const Camera c = frame_camera(box, co);
    co.pan = {16.0 / 128, -12.0 / 96};  // 16 pixels right, 12 down
    const Camera p = frame_camera(box, co);
    EXPECT_EQ(p.forward.x, c.forward.x);
    EXPECT_EQ(p.pixel_size, c.pixel_size);
    EXPECT_EQ(p.tan_half_fov, c.tan_half_fov);
    const double scale = perspective ? 1e-12 * std::sqrt(dot(c.eye - c.target, c.eye - c.target))
                                     : 1e-12 * c.pixel_size * 128;
    if (!perspective) {
      // Pixel (x, y) of the panned view is pixel (x + 16, y + 12) of the plain one.
      for (int y = 0; y + 12 < 96; y += 7)
        for (int x = 0; x + 16 < 128; x += 9) {
          const Ray a = p.ray(x, y), b = c.ray(x + 16, y + 12);
          EXPECT_LT(std::sqrt(dot(a.origin - b.origin, a.origin - b.origin)), scale);
        }
    } else {
      // Eye and target move together across the image plane by 16 and 12 pixels' worth of the
      // image at the target's depth (a pixel there: 2·tan(fov/2)·distance / 96).
      const double distance = std::sqrt(dot(c.target - c.eye, c.target - c.eye));
      const double unit = 2 * c.tan_half_fov * distance / 96;
      const Vec3 move = p.target - c.target, eye_move = p.eye - c.eye;
      EXPECT_NEAR(dot(move, c.right), 16 * unit, scale);
      EXPECT_NEAR(dot(move, c.up), -12 * unit, scale);
      EXPECT_NEAR(dot(move, c.forward), 0, scale);
      EXPECT_LT(std::sqrt(dot(eye_move - move, eye_move - move)), scale);
      EXPECT_GT(p.near, 0);
      EXPECT_GE(p.far, c.far);
    }
  }
  CameraOptions bad;
  bad.pan = {std::nan(""), 0};
  try {
    frame_camera(box, bad);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pan"), std::string::npos);
  }
}

}  // namespace
}  // namespace cover

namespace cover {
namespace {

Vec3 unit_of(Vec3 v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

TEST(Shading, SmoothNormalsOfASphereAreCloserToItsNormalsThanItsFacets) {
  const Solid s = make_leaf(make_sphere({1, 2, 3}, 2.0, 32), "sphere");
  const ShadingNormals sn = shading_normals(s, 30);
  const Bvh bvh(s);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  double smooth_err = 0, flat_err = 0, worst = 0;
  for (int i = 0; i < 2000; ++i) {
    const Bvh::Tri t = bvh.triangle(static_cast<uint32_t>(rng() % bvh.triangle_count()));
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 p = t.a + a * (t.b - t.a) + b * (t.c - t.a);
    const Vec3 truth = unit_of(p - Vec3{1, 2, 3});
    const Vec3 n = smooth_normal(s, sn, t, p);
    const Vec3 flat = unit_of(cross(t.b - t.a, t.c - t.a));
    EXPECT_NEAR(dot(n, n), 1, 1e-6);
    const double e = std::acos(std::min(1.0, dot(n, truth))),
                 f = std::acos(std::min(1.0, dot(flat, truth)));
    smooth_err += e;
    flat_err += f;
    worst = std::max(worst, e);
  }
  EXPECT_LT(smooth_err, 0.5 * flat_err);
  EXPECT_LT(worst, 6 * M_PI / 180);  // 32 segments: facets 11.25° apart
  // Crease 0 or an empty table: the triangle's own normal.
  const Bvh::Tri t = bvh.triangle(0);
  const Vec3 c = (1.0 / 3) * (t.a + t.b + t.c);
  EXPECT_EQ(smooth_normal(s, shading_normals(s, 0), t, c), unit_of(cross(t.b - t.a, t.c - t.a)));
}

TEST(Shading, EdgesSharperThanTheCreaseStayFlat) {
  // A box's faces meet at 90°: every corner keeps its face's normal, so the render with
  // smooth shading is the flat one byte for byte.
  const Solid box = make_leaf(make_box({0, 0, 0}, {1, 2, 3}), "box");
  const ShadingNormals sn = shading_normals(box, 60);
  const Bvh bvh(box);
  for (uint32_t i = 0; i < bvh.triangle_count(); ++i) {
    const Bvh::Tri t = bvh.triangle(i);
    const Vec3 c = (1.0 / 3) * (t.a + t.b + t.c);
    const Vec3 flat = unit_of(cross(t.b - t.a, t.c - t.a));
    const Vec3 n = smooth_normal(box, sn, t, c);
    EXPECT_NEAR(dot(n, flat), 1, 1e-7);
  }
  const Prepared p(box);
  CameraOptions co;
  co.width = 90;
  co.height = 70;
  const Camera cam = frame_camera(box.bbox(), co);
  RenderOptions smooth, flat;
  flat.crease_degrees = 0;
  EXPECT_EQ(render(p, cam, smooth).rgb, render(p, cam, flat).rgb);
  // A sphere changes, and the smooth image is the same for 1 and 2 threads.
  const Solid ball = make_leaf(make_sphere({0, 0, 0}, 1.0, 24), "ball");
  const Prepared q(ball);
  const Camera bc = frame_camera(ball.bbox(), co);
  Image one, two;
  {
    ThreadLimit limit(1);
    one = render(q, bc, smooth);
  }
  {
    ThreadLimit limit(2);
    two = render(q, bc, smooth);
  }
  EXPECT_EQ(one.rgb, two.rgb);
  EXPECT_NE(one.rgb, render(q, bc, flat).rgb);
  EXPECT_EQ(one.ids, render(q, bc, flat).ids);  // geometry unchanged: the same pixels hit
}

}  // namespace
}  // namespace cover

namespace cover {
namespace {

TEST(Shading, SubtractedCylindersAreSmoothToo) {
  // The bore's faces are stored reversed (sign −1); the fan triangles are read in the leaf's
  // own orientation, and their corners are still found: the normal is not the facet's.
  const Solid bored = subtract({make_leaf(make_box({-2, -2, -2}, {2, 2, 2}), "box"),
                                make_leaf(make_cylinder({0, 0, -3}, {0, 0, 3}, 1, 24), "c")});
  const ShadingNormals sn = shading_normals(bored, 30);
  const Bvh bvh(bored);
  int checked = 0;
  for (uint32_t i = 0; i < bvh.triangle_count(); ++i) {
    const Bvh::Tri t = bvh.triangle(i);
    if (t.leaf != 1) continue;
    const Vec3 flat = unit_of(cross(t.b - t.a, t.c - t.a));
    if (std::abs(flat.z) > 0.5) continue;                          // a cap
    const Vec3 p = t.a + 0.05 * (t.b - t.a) + 0.05 * (t.c - t.a);  // near corner a
    const Vec3 radial = unit_of(Vec3{p.x, p.y, 0});
    const Vec3 n = smooth_normal(bored, sn, t, p);
    EXPECT_GT(std::abs(dot(n, radial)), std::abs(dot(flat, radial)) + 1e-6) << i;
    EXPECT_GT(dot(n, flat), 0);  // on the triangle's side
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

}  // namespace
}  // namespace cover
