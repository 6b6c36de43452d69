// object_order_visible() (raster/object_order.h). Notation:
//   fan triangle g   (v0, v_k, v_k+1) of face f in its leaf's own orientation, k = g − start[f] + 1,
//                    numbered face by face (every one, degenerate ones included: a collinear
//                    triangle is never crossed by a perturbed ray, ray.h)
//   (sx, sy)         a point's image coordinates in pixels: dot(p − eye, right) / pixel_size and
//                    dot(p − eye, up) / pixel_size; pixel (px, py)'s ray starts at
//                    eye + sx·right + sy·up (times pixel_size) with sx = px + ½ − w/2,
//                    sy = h/2 − py − ½ (raster/camera.cpp), direction `forward`
//   candidates       the pixels whose (sx, sy) lie in a triangle's projected box widened by the
//                    margin m below; tiles hold the triangles whose candidates meet them

#include "raster/object_order.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "covering/detail/ray_detail.h"
#include "solid/large_vector.h"
#include "solid/parallel.h"

namespace cover {
namespace {

struct FanTri {
  uint32_t v[3];  ///< vertex indices, leaf orientation
  uint32_t face;
};

/// Every fan triangle of the solid, and the face planes of its polygons exactly as Bvh stores them
/// (first vertex, Newell normal summed in fan order), so hit_t gives the same t.
struct Triangles {
  LargeVector<FanTri> tris;
  std::vector<Bvh::FacePlane> planes;
  std::vector<uint32_t> plane_of;  ///< per face; UINT32_MAX: a triangle; empty: no polygon at all

  explicit Triangles(const Solid& solid) {
    const size_t faces = solid.face_count();
    std::vector<uint32_t> start(faces + 1, 0);
    size_t polygons = 0;
    for (size_t f = 0; f < faces; ++f) {
      const size_t k = solid.face(f).size();
      start[f + 1] = start[f] + static_cast<uint32_t>(k >= 3 ? k - 2 : 0);
      polygons += k > 3;
    }
    if (polygons > 0) {
      plane_of.assign(faces, UINT32_MAX);
      uint32_t next = 0;
      for (size_t f = 0; f < faces; ++f)
        if (solid.face(f).size() > 3) plane_of[f] = next++;
      planes.resize(polygons);
    }
    tris.resize(start[faces]);
    parallel_for(faces, 4096, [&](size_t begin, size_t end) {
      for (size_t f = begin; f < end; ++f) {
        const auto face = solid.face(f);
        const bool rev = solid.face_sign[f] < 0;  // back to the leaf's own orientation
        auto at = [&](size_t i) { return face[rev ? face.size() - 1 - i : i]; };
        Vec3 n{};
        for (uint32_t g = start[f]; g < start[f + 1]; ++g) {
          const size_t k = g - start[f] + 1;
          tris[g] = {{at(0), at(k), at(k + 1)}, static_cast<uint32_t>(f)};
          const Vec3 &a = solid.vertices[at(0)], &b = solid.vertices[at(k)],
                     &c = solid.vertices[at(k + 1)];
          n = n + cross(b - a, c - a);
        }
        if (!plane_of.empty() && plane_of[f] != UINT32_MAX)
          planes[plane_of[f]] = {solid.vertices[at(0)], n};
      }
    });
  }
  Bvh::Tri get(const Solid& s, uint32_t g) const {
    const FanTri& t = tris[g];
    return {s.vertices[t.v[0]], s.vertices[t.v[1]], s.vertices[t.v[2]], s.face_leaf[t.face],
            t.face};
  }
  const Bvh::FacePlane* plane(uint32_t face) const {
    if (plane_of.empty() || plane_of[face] == UINT32_MAX) return nullptr;
    return &planes[plane_of[face]];
  }
};

/// A triangle's candidate pixels, inclusive; empty when x0 > x1 or y0 > y1.
struct Rect {
  int x0, x1, y0, y1;
};

}  // namespace

void object_order_visible(const Solid& solid, const Camera& cam, const RayWindow& window, int tile,
                          const VisibleSink& sink, const std::function<void(size_t)>& tile_done) {
  const int w = cam.width, h = cam.height;
  tile = std::max(1, tile);
  const int tiles_x = (w + tile - 1) / tile, tiles_y = (h + tile - 1) / tile;
  const size_t tiles = static_cast<size_t>(tiles_x) * tiles_y;
  const Triangles tri(solid);
  const size_t n = tri.tris.size();

  // Image coordinates of every vertex, and the candidate margin m in pixels. The computed (sx, sy)
  // of a vertex and of a pixel ray's actual origin are each within a few ulps of the magnitudes
  // involved (|eye|, |p|, the image extent, and t·|forward·right| ≤ far·2⁻⁵⁰ for the not exactly
  // orthogonal frame) of the exact projections, divided by the pixel size: far below
  // 1e-9 · (|eye|₁ + max|p|₁ + far + (w + h)·pixel_size) / pixel_size, which m exceeds (plus
  // 1e-3 pixel). A ray that crosses a triangle exactly has its origin's exact projection in the
  // triangle's, so its pixel is a candidate: culling only, as the BVH's widened boxes.
  const double ps = cam.pixel_size;
  LargeVector<double> sx(solid.vertices.size()), sy(solid.vertices.size());
  parallel_for(solid.vertices.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      const Vec3 d = solid.vertices[v] - cam.eye;
      sx[v] = dot(d, cam.right) / ps;
      sy[v] = dot(d, cam.up) / ps;
    }
  });
  double largest = 0;  // max |p|₁ over the vertices
  for (const Vec3& p : solid.vertices)
    largest = std::max(largest, std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
  const double reach = std::abs(cam.eye.x) + std::abs(cam.eye.y) + std::abs(cam.eye.z) + largest +
                       std::abs(cam.far) + (static_cast<double>(w) + h) * ps;
  const double m = 1e-3 + 1e-9 * reach / ps;
  auto rect = [&](const FanTri& t) {
    double x0 = sx[t.v[0]], x1 = x0, y0 = sy[t.v[0]], y1 = y0;
    for (int i = 1; i < 3; ++i) {
      x0 = std::min(x0, sx[t.v[i]]), x1 = std::max(x1, sx[t.v[i]]);
      y0 = std::min(y0, sy[t.v[i]]), y1 = std::max(y1, sy[t.v[i]]);
    }
    // px = sx − ½ + w/2; py = h/2 − ½ − sy. Clamped before the conversion to int.
    auto lo = [](double v, int limit) { return static_cast<int>(std::clamp(std::ceil(v), -1.0, static_cast<double>(limit))); };
    auto hi = [](double v, int limit) { return static_cast<int>(std::clamp(std::floor(v), -1.0, static_cast<double>(limit))); };
    Rect r{lo(x0 - 0.5 + 0.5 * w - m, w), hi(x1 - 0.5 + 0.5 * w + m, w),
           lo(0.5 * h - 0.5 - y1 - m, h), hi(0.5 * h - 0.5 - y0 + m, h)};
    r.x0 = std::max(r.x0, 0), r.y0 = std::max(r.y0, 0);
    r.x1 = std::min(r.x1, w - 1), r.y1 = std::min(r.y1, h - 1);
    return r;
  };

  // Tile lists: per chunk of triangles its count per tile, then every tile's list in triangle
  // order (chunks in order), so the lists do not depend on the threads.
  constexpr size_t kChunk = 16384;
  const size_t chunks = std::max<size_t>(1, (n + kChunk - 1) / kChunk);
  std::vector<uint32_t> count(chunks * tiles, 0);
  auto for_tiles = [&](const Rect& r, auto&& f) {
    if (r.x0 > r.x1 || r.y0 > r.y1) return;
    for (int ty = r.y0 / tile; ty <= r.y1 / tile; ++ty)
      for (int tx = r.x0 / tile; tx <= r.x1 / tile; ++tx) f(static_cast<size_t>(ty) * tiles_x + tx);
  };
  parallel_for(chunks, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c)
      for (size_t g = c * kChunk; g < std::min(n, (c + 1) * kChunk); ++g)
        for_tiles(rect(tri.tris[g]), [&](size_t t) { ++count[c * tiles + t]; });
  });
  std::vector<size_t> offset(chunks * tiles + 1, 0);  // tile-major: (tile, chunk)
  {
    size_t at = 0;
    for (size_t t = 0; t < tiles; ++t)
      for (size_t c = 0; c < chunks; ++c) {
        offset[t * chunks + c] = at;
        at += count[c * tiles + t];
      }
    offset[tiles * chunks] = at;
  }
  LargeVector<uint32_t> list(offset[tiles * chunks]);
  parallel_for(chunks, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c) {
      std::vector<size_t> fill(tiles);
      for (size_t t = 0; t < tiles; ++t) fill[t] = offset[t * chunks + c];
      for (size_t g = c * kChunk; g < std::min(n, (c + 1) * kChunk); ++g)
        for_tiles(rect(tri.tris[g]), [&](size_t t) { list[fill[t]++] = static_cast<uint32_t>(g); });
    }
  });

  // Per tile: the exact crossings of its candidates, bucketed by pixel, then each pixel's hits
  // sorted and swept into spans as cast() does (covering/detail/ray_detail.h).
  const detail::Axes ax = detail::axes_for(cam.forward);
  const size_t leaves = solid.leaves.size();
  parallel_for(tiles, 1, [&](size_t t0, size_t t1) {
    std::vector<Ray> rays;
    std::vector<std::pair<double, double>> win;
    std::vector<std::pair<uint32_t, RayHit>> found;
    std::vector<uint32_t> first;
    std::vector<RayHit> sorted;
    RayResult result;
    for (size_t t = t0; t < t1; ++t) {
      const int x0 = static_cast<int>(t % tiles_x) * tile, y0 = static_cast<int>(t / tiles_x) * tile;
      const int tw = std::min(w, x0 + tile) - x0, th = std::min(h, y0 + tile) - y0;
      rays.resize(static_cast<size_t>(tw) * th);
      win.resize(rays.size());
      for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x) {
          const size_t k = static_cast<size_t>(y) * tw + x;
          rays[k] = cam.ray(x0 + x, y0 + y);
          win[k] = window(rays[k]);
        }
      found.clear();
      for (size_t e = offset[t * chunks]; e < offset[(t + 1) * chunks]; ++e) {
        const uint32_t g = list[e];
        const Rect r = rect(tri.tris[g]);
        const Bvh::Tri tr = tri.get(solid, g);
        const Bvh::FacePlane* plane = tri.plane(tr.face);
        for (int py = std::max(r.y0, y0); py <= std::min(r.y1, y0 + th - 1); ++py)
          for (int px = std::max(r.x0, x0); px <= std::min(r.x1, x0 + tw - 1); ++px) {
            const uint32_t k = static_cast<uint32_t>((py - y0) * tw + (px - x0));
            if (win[k].first > win[k].second) continue;
            int sign;
            if (!detail::crosses(tr, rays[k], ax, sign)) continue;
            found.push_back({k, {detail::hit_t(plane, tr, rays[k]), g, tr.leaf, tr.face,
                                 static_cast<int8_t>(sign)}});
          }
      }
      // Counting sort by pixel (stable: the hits' own order is settled by sweep_spans's sort).
      first.assign(rays.size() + 1, 0);
      for (const auto& f : found) ++first[f.first + 1];
      for (size_t k = 0; k < rays.size(); ++k) first[k + 1] += first[k];
      sorted.resize(found.size());
      {
        std::vector<uint32_t> at(first.begin(), first.end() - 1);
        for (const auto& f : found) sorted[at[f.first]++] = f.second;
      }
      for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x) {
          const size_t k = static_cast<size_t>(y) * tw + x;
          const size_t pixel = static_cast<size_t>(y0 + y) * w + (x0 + x);
          VisibleHit v;
          if (win[k].first <= win[k].second && !solid.tree.nodes.empty()) {
            result.hits.assign(sorted.begin() + first[k], sorted.begin() + first[k + 1]);
            result.spans.clear();
            detail::sweep_spans(result, solid.tree, leaves);
            v = first_visible(result, win[k].first, win[k].second);
          }
          if (v.hit && !v.cap) {
            const Bvh::Tri hit_tri = tri.get(solid, v.enter.tri);
            sink(pixel, rays[k], v, &hit_tri);
          } else {
            sink(pixel, rays[k], v, nullptr);
          }
        }
      if (tile_done) tile_done(1);
    }
  });
}

}  // namespace cover
