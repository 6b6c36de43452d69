#include "cover/render/render.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <thread>

#include "cover/covering/ray.h"
#include "cover/render/object_order.h"
#include "cover/render/shading.h"
#include "cover/solid/errors.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

/// What a pixel's ray sees first.
struct Sample {
  bool hit = false;
  bool cap = false;
  double t = 0;
  Vec3 normal;  ///< unit, facing the camera
  uint32_t leaf = 0;
};

Vec3 unit(Vec3 v) {
  const double l = std::sqrt(dot(v, v));
  return l > 0 ? (1.0 / l) * v : v;
}

/// What a pixel shows, from its visible hit (`tri`: the triangle of v.enter when v.hit && !v.cap).
/// The normal: `shading`'s smooth one on the triangle (shading.h), flat where it is empty.
Sample to_sample(const VisibleHit& v, const Bvh::Tri* tri, const Ray& ray,
                 const std::optional<Plane>& section, const Solid& solid,
                 const ShadingNormals& shading) {
  Sample out;
  if (!v.hit) return out;
  out.hit = true;
  out.t = v.t;
  if (!v.cap) {
    const Vec3 n = smooth_normal(solid, shading, *tri, ray.origin + v.t * ray.dir);
    // Entering a leaf shows its outward normal; leaving one (a subtrahend) the reverse.
    out.normal = v.enter.sign < 0 ? n : -1.0 * n;
    out.leaf = v.enter.leaf;
  } else {
    out.cap = true;
    const Vec3 n = section ? unit(section->normal) : -1.0 * ray.dir;
    out.normal = dot(n, ray.dir) < 0 ? n : -1.0 * n;
  }
  return out;
}

/// `outside_in_result`: the expression's value with every leaf outside (once per frame).
/// `open`: the open leaves' trees (gwn.h), or nullptr when every leaf is closed; then spans
/// come from cast() and open_spans() (membership changes only at surface hits). Field and warp
/// leaves: from cast() and field_spans() (their normals from field_normal).
Sample sample(const Prepared& prepared, const Bvh& bvh, const Ray& ray,
              const std::optional<Plane>& section, bool outside_in_result, const GwnForest* open,
              const ShadingNormals& shading) {
  const Solid& solid = prepared.solid();
  const auto [lo, hi] = section_window(ray, section);
  if (lo > hi) return {};
  VisibleHit v;
  if (solid.has_implicit_leaf()) {
    RayResult r = cast(bvh, solid.tree, solid.leaves.size(), ray);
    field_spans(r, prepared, ray);
    v = first_visible(r, lo, hi);
    if (v.hit && !v.cap && v.enter.tri == Span::kNone) {  // a field's or a warp's surface
      Sample out;
      out.hit = true;
      out.t = v.t;
      const Vec3 n = unit(field_normal(prepared, v.enter, ray));
      out.normal = dot(n, ray.dir) <= 0 ? n : -1.0 * n;
      out.leaf = v.enter.leaf;
      return out;
    }
  } else if (open == nullptr) {
    v = first_visible(bvh, solid.tree, solid.leaves.size(), ray, lo, hi, outside_in_result);
  } else {
    RayResult r = cast(bvh, solid.tree, solid.leaves.size(), ray);
    open_spans(r, solid, *open, ray);
    v = first_visible(r, lo, hi);
  }
  if (!v.hit || v.cap) return to_sample(v, nullptr, ray, section, solid, shading);
  const Bvh::Tri t = bvh.triangle(v.enter.tri);
  return to_sample(v, &t, ray, section, solid, shading);
}

/// `v` as n copies of `value`, written 16 MiB at a time with step() after each.
template <typename Vector>
void fill_in_steps(Vector& v, size_t n, typename Vector::value_type value,
                   const std::function<void()>& step) {
  constexpr size_t kStepBytes = size_t{16} << 20;
  const size_t per_step = std::max<size_t>(1, kStepBytes / sizeof(value));
  v.clear();
  reserve_huge(v, n);
  while (v.size() < n) {
    v.resize(std::min(n, v.size() + per_step), value);
    step();
  }
}

std::array<uint8_t, 3> hsv(double h, double s, double v) {
  const double c = v * s, x = c * (1 - std::abs(std::fmod(h * 6, 2.0) - 1)), m = v - c;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h * 6) % 6) {
    case 0:
      r = c, g = x;
      break;
    case 1:
      r = x, g = c;
      break;
    case 2:
      g = c, b = x;
      break;
    case 3:
      g = x, b = c;
      break;
    case 4:
      r = x, b = c;
      break;
    default:
      r = c, b = x;
      break;
  }
  auto byte = [](double f) {
    return static_cast<uint8_t>(std::lround(std::clamp(f, 0.0, 1.0) * 255));
  };
  return {byte(r + m), byte(g + m), byte(b + m)};
}

}  // namespace

std::array<uint8_t, 3> leaf_colour(uint32_t leaf) {
  // Golden-ratio hue steps from a blue start: neighbouring leaf ids get distant hues.
  const double h = std::fmod(0.58 + 0.6180339887498949 * leaf, 1.0);
  return hsv(h, 0.55, 0.95);
}

std::array<uint8_t, 3> cap_colour() { return {214, 48, 49}; }

std::array<uint8_t, 3> display_colour(const Solid& solid, uint32_t l) {
  if (l < solid.leaves.size() && solid.leaves[l].colour) return *solid.leaves[l].colour;
  return leaf_colour(l);
}

double render_bytes(int width, int height, int samples) {
  constexpr size_t kPerPixel = 3 * sizeof(uint8_t) + 2 * sizeof(uint16_t) + sizeof(Vec3);
  const double pixels = static_cast<double>(width) * height;
  return pixels * kPerPixel * (samples > 1 ? 1.0 + double(samples) * samples : 1.0);
}

bool renders_in_object_order(const Solid& solid, const Camera& /*camera*/, const RenderOptions& o) {
  const bool applies = !solid.has_open_leaf() && !solid.has_implicit_leaf();
  if (o.method == RenderMethod::kObjectOrder && !applies)
    throw InputError("render: the object-order method needs closed mesh leaves");
  return o.method == RenderMethod::kObjectOrder || (o.method == RenderMethod::kAuto && applies);
}

namespace {

/// One ray per pixel of `cam`; outlines `band` pixels wide (the sub-pixel image of render()
/// draws them S wide, one pixel once averaged).
Image render_pass(const Prepared& prepared, const Camera& cam, const RenderOptions& o, int band,
                  const ShadingNormals& shading) {
  const Solid& solid = prepared.solid();
  const bool object_order = renders_in_object_order(solid, cam, o);
  Image img;
  img.width = cam.width;
  img.height = cam.height;
  const size_t n = static_cast<size_t>(cam.width) * cam.height;
  const int tile = std::max(1, o.tile);
  const int tiles_x = (cam.width + tile - 1) / tile, tiles_y = (cam.height + tile - 1) / tile;
  const size_t tiles = static_cast<size_t>(tiles_x) * tiles_y;
  // The buffers' first touch is seconds of page faults for a large image (7 bytes a pixel: about
  // 1 GiB at 12000², ~2.8 ms per MiB on a fresh VM page): filled in steps, with a progress call
  // (done 0) after each, so that a caller polling for an interrupt gets a say meanwhile.
  const auto step = [&] {
    if (o.progress) o.progress(0, tiles);
  };
  fill_in_steps(img.rgb, 3 * n, uint8_t{0}, step);
  fill_in_steps(img.depth, n, Image::kFarDepth, step);
  fill_in_steps(img.ids, n, Image::kBackgroundId, step);
  // Unit normals for the outline, written and read only at pixels with a surface (ids not
  // background): left unfilled, their pages are first touched by the tiles that write them.
  LargeBuffer<std::array<double, 3>> normals(n);
  auto normal = [&](size_t i) { return Vec3{normals[i][0], normals[i][1], normals[i][2]}; };
  // A key light from the upper left of the camera plus a headlight and ambient.
  const Vec3 key = unit(cam.forward - 0.6 * cam.up + 0.5 * cam.right);
  auto shade = [&](size_t i, const Ray& ray, const Sample& s) {
    std::array<uint8_t, 3> c = o.background;
    if (s.hit) {
      const std::array<uint8_t, 3> base = s.cap ? cap_colour()
                                          : s.leaf < o.leaf_colours.size()
                                              ? o.leaf_colours[s.leaf]
                                              : display_colour(solid, s.leaf);
      const double head = std::max(0.0, -dot(s.normal, ray.dir));
      const double lit = std::max(0.0, -dot(s.normal, key));
      const double k = 0.28 + 0.47 * head + 0.25 * lit;
      for (int ch = 0; ch < 3; ++ch)
        c[ch] = static_cast<uint8_t>(std::lround(std::min(255.0, base[ch] * k)));
      const double f = (s.t - cam.near) / (cam.far - cam.near);
      img.depth[i] = static_cast<uint16_t>(std::lround(std::clamp(f, 0.0, 1.0) * 65534));
      img.ids[i] =
          s.cap ? Image::kCapId : static_cast<uint16_t>(std::min<uint32_t>(s.leaf + 1, 65534));
      normals[i] = {s.normal.x, s.normal.y, s.normal.z};
    }
    std::copy(c.begin(), c.end(), img.rgb.begin() + 3 * i);
  };
  // Progress as in voxelize.cpp: a shared count, reported by the calling thread (which takes part
  // in the loop) after each of its tiles, so the callback never runs concurrently.
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<size_t> tiles_done{0};
  auto tile_done = [&](size_t count) {
    const size_t done = tiles_done.fetch_add(count) + count;
    if (o.progress && std::this_thread::get_id() == caller && done < tiles) o.progress(done, tiles);
  };
  if (object_order) {
    object_order_visible(
        solid, cam, o.section, tile,
        [&](size_t i, const Ray& ray, const VisibleHit& v, const Bvh::Tri* t) {
          shade(i, ray, to_sample(v, t, ray, o.section, solid, shading));
        },
        tile_done);
  } else {
    const Bvh& bvh = prepared.bvh();
    const GwnForest* open = prepared.gwn();
    const bool outside_in_result =
        !solid.tree.nodes.empty() &&
        solid.tree.evaluate(std::vector<uint8_t>(solid.leaves.size(), 0));
    parallel_for(tiles, 1, [&](size_t begin, size_t end) {
      for (size_t t = begin; t < end; ++t) {
        const int x0 = static_cast<int>(t % tiles_x) * tile,
                  y0 = static_cast<int>(t / tiles_x) * tile;
        for (int py = y0; py < std::min(cam.height, y0 + tile); ++py)
          for (int px = x0; px < std::min(cam.width, x0 + tile); ++px) {
            const Ray ray = cam.ray(px, py);
            shade(static_cast<size_t>(py) * cam.width + px, ray,
                  sample(prepared, bvh, ray, o.section, outside_in_result, open, shading));
          }
      }
      tile_done(end - begin);
    });
  }
  if (o.progress) o.progress(tiles, tiles);
  if (!o.outline) return img;
  // Outline: a pixel whose right or lower neighbour shows another leaf (or background) or a
  // normal more than ~35° apart (silhouettes, leaf boundaries, creases) is darkened; where one
  // of the two is background, the surface pixel is. As a pull per pixel (so rows run in
  // parallel, each writing only its own pixels): surface pixel p is darkened iff it differs from
  // its right or lower neighbour, or its left or upper neighbour is background.
  // With band k the neighbours are k pixels away, so the darkened strip is k pixels wide.
  auto differ = [&](size_t i, size_t j) {
    return img.ids[i] != img.ids[j] || dot(normal(i), normal(j)) < 0.82;
  };
  const int k = band;
  const size_t row = static_cast<size_t>(cam.width), down = static_cast<size_t>(k) * row;
  parallel_for(static_cast<size_t>(cam.height), 16, [&](size_t begin, size_t end) {
    if (o.progress && std::this_thread::get_id() == caller) o.progress(tiles, tiles);
    for (size_t py = begin; py < end; ++py)
      for (int px = 0; px < cam.width; ++px) {
        const size_t i = py * row + px;
        if (img.ids[i] == Image::kBackgroundId) continue;
        const bool edge =
            (px + k < cam.width && differ(i, i + k)) ||
            (py + k < static_cast<size_t>(cam.height) && differ(i, i + down)) ||
            (px >= k && img.ids[i - k] == Image::kBackgroundId) ||
            (py >= static_cast<size_t>(k) && img.ids[i - down] == Image::kBackgroundId);
        if (edge)
          for (int ch = 0; ch < 3; ++ch)
            img.rgb[3 * i + ch] = static_cast<uint8_t>(img.rgb[3 * i + ch] * 0.35);
      }
  });
  return img;
}

}  // namespace

Image render(const Prepared& prepared, const Camera& cam, const RenderOptions& o) {
  const int s = o.samples;
  if (s < 1 || s > kMaxRenderSamples)
    throw PreconditionError("render: samples " + std::to_string(s) + " is not 1 to " +
                            std::to_string(kMaxRenderSamples));
  if (!(o.crease_degrees >= 0 && o.crease_degrees <= 180))
    throw PreconditionError("render: crease_degrees is not 0 to 180");
  const ShadingNormals shading = shading_normals(prepared.solid(), o.crease_degrees);
  if (s == 1) return render_pass(prepared, cam, o, 1, shading);
  // The sub-pixel image: the same view with S times the pixels per side (orthographic: S times
  // smaller pixels; perspective: the field of view spans S times the pixels), so sub-pixel
  // (S·px + a, S·py + b) is centred at (px + (a + ½)/S, py + (b + ½)/S) of pixel (px, py).
  Camera fine = cam;
  fine.width = s * cam.width;
  fine.height = s * cam.height;
  fine.pixel_size = cam.pixel_size / s;
  const int tile = std::max(1, o.tile);
  const size_t fine_tiles = static_cast<size_t>((fine.width + tile - 1) / tile) *
                            static_cast<size_t>((fine.height + tile - 1) / tile);
  Image sub = render_pass(prepared, fine, o, s, shading);
  // Depth and ids from the pixel-centre rays (no outline: its colour is replaced below).
  RenderOptions centre = o;
  centre.outline = false;
  centre.progress = [&](size_t, size_t) {
    if (o.progress) o.progress(fine_tiles, fine_tiles);
  };
  Image img = render_pass(prepared, cam, centre, 1, shading);
  // Box filter: each channel the rounded mean of the S² sub-pixels (integers: exact, so the
  // image does not depend on the thread count).
  const int s2 = s * s;
  parallel_for(static_cast<size_t>(cam.height), 16, [&](size_t begin, size_t end) {
    for (size_t py = begin; py < end; ++py)
      for (int px = 0; px < cam.width; ++px)
        for (int ch = 0; ch < 3; ++ch) {
          int sum = 0;
          for (int b = 0; b < s; ++b) {
            const size_t r = (py * s + b) * static_cast<size_t>(fine.width) + px * s;
            for (int a = 0; a < s; ++a) sum += sub.rgb[3 * (r + a) + ch];
          }
          img.rgb[3 * (py * cam.width + px) + ch] = static_cast<uint8_t>((sum + s2 / 2) / s2);
        }
  });
  return img;
}

}  // namespace cover
