// object_order_visible() (render/object_order.h). Notation:
//   fan triangle g   (v0, v_k, v_k+1) of face f in its leaf's own orientation, k = g − start[f] +
//   1,
//                    numbered face by face (every one, degenerate ones included: a collinear
//                    triangle is never crossed by a perturbed ray, ray.h)
//   (sx, sy)         a point's image coordinates in pixels: dot(p − eye, right) / pixel_size and
//                    dot(p − eye, up) / pixel_size; pixel (px, py)'s ray starts at
//                    eye + sx·right + sy·up (times pixel_size) with sx = px + ½ − w/2,
//                    sy = h/2 − py − ½ (render/camera.cpp), direction `forward`
//   candidates       the pixels whose (sx, sy) lie in a triangle's projected box widened by the
//                    margin m below; tiles hold the triangles whose candidates meet them

#include "cover/render/object_order.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "cover/covering/ray_steps.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"

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
/// The same, stored per triangle between the passes (images are at most 16384 pixels a side;
/// an empty rectangle is stored as x0 = 1, x1 = 0).
struct SmallRect {
  uint16_t x0, x1, y0, y1;
};

/// The expression's value for every inside-leaf mask (bit l: leaf l inside), for up to
/// kTableLeaves leaves: one lookup per interval instead of a walk of the tree (which would be
/// about 9% of a frame's samples).
constexpr size_t kTableLeaves = 16;

/// first_visible(r, lo, hi) of r = the hits swept as detail::sweep_spans() does (windings from
/// the sum of signs, the expression evaluated after the last hit at each t), stopping at the first
/// span in view. `hits` are sorted here (detail::hit_before); `winding`: scratch of #leaves.
VisibleHit resolve(std::span<RayHit> hits, const std::vector<uint8_t>& table,
                   std::vector<int>& winding, double lo, double hi) {
  std::sort(hits.begin(), hits.end(), detail::hit_before);
  for (const RayHit& h : hits) winding[h.leaf] = 0;
  for (const RayHit& h : hits) winding[h.leaf] += h.sign;
  uint32_t mask = 0;
  for (const RayHit& h : hits)
    if (winding[h.leaf] != 0) mask |= uint32_t{1} << h.leaf;
  bool in = table[mask] != 0;
  double t0 = 0;  // the open span's start: the origin, or hit `enter`
  uint32_t enter = Span::kNone;
  auto shown = [&](double t1, VisibleHit& v) {  // the span [t0, t1] in view?
    const double a = std::max(t0, lo), b = std::min(t1, hi);
    if (!(a < b)) return false;
    v.hit = true;
    v.t = a;
    v.cap = !(a == t0 && enter != Span::kNone);
    if (!v.cap) v.enter = hits[enter];
    return true;
  };
  VisibleHit v;
  for (size_t i = 0; i < hits.size(); ++i) {
    const RayHit& h = hits[i];
    const int wl = winding[h.leaf] -= h.sign;
    mask = wl != 0 ? mask | (uint32_t{1} << h.leaf) : mask & ~(uint32_t{1} << h.leaf);
    if (i + 1 < hits.size() && hits[i + 1].t == h.t) continue;
    const bool now = table[mask] != 0;
    if (now == in) continue;
    in = now;
    if (now) {
      t0 = h.t;
      enter = static_cast<uint32_t>(i);
    } else if (h.t > t0) {  // a non-empty span ends
      if (shown(h.t, v)) return v;
      if (t0 >= hi) return v;  // later spans start later still: none in view
    }
  }
  if (in) shown(INFINITY, v);
  return v;
}

}  // namespace

void object_order_visible(const Solid& solid, const Camera& cam,
                          const std::optional<Plane>& section, int tile, const VisibleSink& sink,
                          const std::function<void(size_t)>& tile_done) {
  const int w = cam.width, h = cam.height;
  tile = std::max(1, tile);
  const int tiles_x = (w + tile - 1) / tile, tiles_y = (h + tile - 1) / tile;
  const size_t tiles = static_cast<size_t>(tiles_x) * tiles_y;
  const Triangles tri(solid);
  const size_t n = tri.tris.size();

  // Image coordinates of every vertex, and δ, a bound in pixels on how far a computed (sx, sy)
  // — of a vertex, or of a pixel ray's actual origin — can lie from the exact projection along
  // `forward` of that point: rounding (a few ulps of |eye|, |p| and the image extent, far below
  // 1e-9 of `reach`), plus t·e for the frame's departure e from orthogonality (forward·right,
  // forward·up; t ≤ |p − eye|₁ ≤ reach), over the pixel size. A ray crossing a triangle exactly
  // has its origin's projection in the triangle's, so the candidates (the projected box widened
  // by m = δ + 1e-3 pixel) hold every pixel whose ray crosses it: culling only, as the BVH's
  // widened boxes; the exact test decides.
  //
  // Perspective cameras: a point p is seen at (sx, sy) = (d·right, d·up) / (d·forward · scale),
  // d = p − eye, scale = 2·tan(fov/2)/min(w, h) (the pixel rays' directions are
  // forward + sx·scale·right + sy·scale·up, normalized). A triangle whose corners all lie ahead
  // within about 89° of forward (d·forward ≥ |d|₁/100) projects to the triangle of its projected
  // corners; rounding (of the projections and of the pixel rays' directions, magnified at most
  // ~10⁴ times by the division at those angles: about 10⁻¹²/scale pixels) and the frame's skew
  // (at most ~10⁴·skew/scale) stay far below m = 1e-3 + (1e-9 + 10⁵·skew)/scale pixels. A corner
  // behind the eye plane by that much on every corner: no candidates; any other triangle: every
  // pixel is a candidate (the exact test decides). The 2D prefilter and the inside shortcut below
  // are for orthographic cameras only.
  const bool persp = cam.perspective;
  const double ps = cam.pixel_size;
  const double scale = persp ? 2 * cam.tan_half_fov / std::min(w, h) : 0.0;
  constexpr double kAhead = 0.01, kUnbounded = std::numeric_limits<double>::infinity();
  LargeVector<double> sx(solid.vertices.size()), sy(solid.vertices.size());
  parallel_for(solid.vertices.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      const Vec3 d = solid.vertices[v] - cam.eye;
      if (!persp) {
        sx[v] = dot(d, cam.right) / ps;
        sy[v] = dot(d, cam.up) / ps;
        continue;
      }
      const double z = dot(d, cam.forward), l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
      if (z >= kAhead * l1 && z > 0) {
        sx[v] = dot(d, cam.right) / (z * scale);
        sy[v] = dot(d, cam.up) / (z * scale);
      } else {  // NaN marks "behind the eye plane", ±∞ "beside or barely ahead: unbounded"
        sx[v] = z < -kAhead * l1 ? std::numeric_limits<double>::quiet_NaN() : kUnbounded;
        sy[v] = sx[v];
      }
    }
  });
  double largest = 0;  // max |p|₁ over the vertices
  for (const Vec3& p : solid.vertices)
    largest = std::max(largest, std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
  const double reach = std::abs(cam.eye.x) + std::abs(cam.eye.y) + std::abs(cam.eye.z) + largest +
                       std::abs(cam.far) + (static_cast<double>(w) + h) * ps;
  const double skew =
      std::max(std::abs(dot(cam.forward, cam.right)), std::abs(dot(cam.forward, cam.up))) + 1e-15;
  const double delta = (1e-9 + 2 * skew) * reach / ps;
  const double m = persp ? 1e-3 + (1e-9 + 1e5 * skew) / scale : 1e-3 + delta;
  // The orientation of the image frame, (right × up)·forward: −1 for frame_camera's cameras
  // (camera.h); 0 (no shortcut below) for a frame too far from orthonormal to be sure, and for
  // perspective cameras.
  const double hand = dot(cross(cam.right, cam.up), cam.forward);
  const int handed = persp ? 0 : (hand < -0.5 ? -1 : (hand > 0.5 ? 1 : 0));
  // The 2D prefilter of a candidate: its pixel centre c strictly outside an edge line of the
  // projected triangle by more than that edge function's error bound (δ on each of the three
  // points, plus the rounding of the formula) cannot have an exactly crossing ray; only
  // triangles whose projected orientation is itself certain are filtered. Saves the exact test
  // (three perturbed triple products) for most of the candidates that miss.
  auto edge_tolerance = [&](double dx, double dy, double ex, double ey) {
    const double l = std::abs(dx) + std::abs(dy);
    return 4 * delta * l + 4 * delta * delta + 1e-14 * l * (std::abs(ex) + std::abs(ey) + 1);
  };
  auto rect = [&](const FanTri& t) {
    if (persp) {
      const bool behind[3] = {std::isnan(sx[t.v[0]]), std::isnan(sx[t.v[1]]),
                              std::isnan(sx[t.v[2]])};
      if (behind[0] && behind[1] && behind[2]) return Rect{1, 0, 1, 0};
      for (uint32_t v : t.v)
        if (!std::isfinite(sx[v])) return Rect{0, w - 1, 0, h - 1};
    }
    double x0 = sx[t.v[0]], x1 = x0, y0 = sy[t.v[0]], y1 = y0;
    for (int i = 1; i < 3; ++i) {
      x0 = std::min(x0, sx[t.v[i]]), x1 = std::max(x1, sx[t.v[i]]);
      y0 = std::min(y0, sy[t.v[i]]), y1 = std::max(y1, sy[t.v[i]]);
    }
    // px = sx − ½ + w/2; py = h/2 − ½ − sy. Clamped before the conversion to int.
    auto lo = [](double v, int limit) {
      return static_cast<int>(std::clamp(std::ceil(v), -1.0, static_cast<double>(limit)));
    };
    auto hi = [](double v, int limit) {
      return static_cast<int>(std::clamp(std::floor(v), -1.0, static_cast<double>(limit)));
    };
    Rect r{lo(x0 - 0.5 + 0.5 * w - m, w), hi(x1 - 0.5 + 0.5 * w + m, w),
           lo(0.5 * h - 0.5 - y1 - m, h), hi(0.5 * h - 0.5 - y0 + m, h)};
    r.x0 = std::max(r.x0, 0), r.y0 = std::max(r.y0, 0);
    r.x1 = std::min(r.x1, w - 1), r.y1 = std::min(r.y1, h - 1);
    return r;
  };

  // Tile lists: per chunk of triangles its count per tile, then every tile's list in triangle
  // order (chunks in order), so the lists do not depend on the threads.
  // Chunks of at least 16384 triangles, fewer when the counts (chunks × tiles) would pass 2^21
  // entries (a 16384² image has 262,144 tiles): memory stays bounded for any mesh and image.
  const size_t chunk_size = std::max<size_t>(
      16384, static_cast<size_t>(std::ceil(static_cast<double>(n) * tiles / (size_t{1} << 21))));
  const size_t chunks = std::max<size_t>(1, (n + chunk_size - 1) / chunk_size);
  std::vector<uint32_t> count(chunks * tiles, 0);
  auto for_tiles = [&](const Rect& r, auto&& f) {
    if (r.x0 > r.x1 || r.y0 > r.y1) return;
    for (int ty = r.y0 / tile; ty <= r.y1 / tile; ++ty)
      for (int tx = r.x0 / tile; tx <= r.x1 / tile; ++tx) f(static_cast<size_t>(ty) * tiles_x + tx);
  };
  LargeVector<SmallRect> rects(n);
  auto stored = [&](size_t g) {
    const SmallRect& r = rects[g];
    return Rect{r.x0, r.x1, r.y0, r.y1};
  };
  parallel_for(chunks, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c)
      for (size_t g = c * chunk_size; g < std::min(n, (c + 1) * chunk_size); ++g) {
        Rect r = rect(tri.tris[g]);
        if (r.x0 > r.x1 || r.y0 > r.y1) r = {1, 0, 1, 0};
        rects[g] = {static_cast<uint16_t>(r.x0), static_cast<uint16_t>(r.x1),
                    static_cast<uint16_t>(r.y0), static_cast<uint16_t>(r.y1)};
        for_tiles(r, [&](size_t t) { ++count[c * tiles + t]; });
      }
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
      for (size_t g = c * chunk_size; g < std::min(n, (c + 1) * chunk_size); ++g)
        for_tiles(stored(g), [&](size_t t) { list[fill[t]++] = static_cast<uint32_t>(g); });
    }
  });

  // Per tile: the exact crossings of its candidates, bucketed by pixel, then each pixel's hits
  // sorted and swept into spans as cast() does (covering/ray_steps.h).
  const detail::Axes ortho_axes = detail::axes_for(cam.forward);
  const size_t leaves = solid.leaves.size();
  // A ray without hits is outside every leaf all along: inside the result iff the expression
  // holds the all-outside point (then its one span [0, ∞) shows a cap at the window's start).
  const bool outside_in_result =
      !solid.tree.nodes.empty() && solid.tree.evaluate(std::vector<uint8_t>(leaves, 0));
  const bool use_table = !solid.tree.nodes.empty() && leaves <= kTableLeaves;
  const std::vector<uint8_t> table =
      use_table ? solid.tree.truth_table(leaves) : std::vector<uint8_t>{};
  parallel_for(tiles, 1, [&](size_t t0, size_t t1) {
    std::vector<Ray> rays;
    std::vector<detail::Axes> axes;  // per ray (perspective: each direction its own)
    std::vector<std::pair<double, double>> win;
    std::vector<std::pair<uint32_t, RayHit>> found;
    std::vector<uint32_t> first;
    std::vector<RayHit> sorted;
    std::vector<int> winding(leaves, 0);
    RayResult result;
    for (size_t t = t0; t < t1; ++t) {
      const int x0 = static_cast<int>(t % tiles_x) * tile,
                y0 = static_cast<int>(t / tiles_x) * tile;
      const int tw = std::min(w, x0 + tile) - x0, th = std::min(h, y0 + tile) - y0;
      rays.resize(static_cast<size_t>(tw) * th);
      win.resize(rays.size());
      axes.resize(rays.size());
      for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x) {
          const size_t k = static_cast<size_t>(y) * tw + x;
          rays[k] = cam.ray(x0 + x, y0 + y);
          win[k] = section_window(rays[k], section);
          axes[k] = persp ? detail::axes_for(rays[k].dir) : ortho_axes;
        }
      found.clear();
      for (size_t e = offset[t * chunks]; e < offset[(t + 1) * chunks]; ++e) {
        const uint32_t g = list[e];
        const Rect r = stored(g);
        const Bvh::Tri tr = tri.get(solid, g);
        const Bvh::FacePlane* plane = tri.plane(tr.face);
        const FanTri& ft = tri.tris[g];
        const double qx[3] = {sx[ft.v[0]], sx[ft.v[1]], sx[ft.v[2]]};
        const double qy[3] = {sy[ft.v[0]], sy[ft.v[1]], sy[ft.v[2]]};
        const double area = (qx[1] - qx[0]) * (qy[2] - qy[0]) - (qy[1] - qy[0]) * (qx[2] - qx[0]);
        const double orient =
            !persp && std::abs(area) > edge_tolerance(qx[1] - qx[0], qy[1] - qy[0], qx[2] - qx[0],
                                                      qy[2] - qy[0])
                ? (area > 0 ? 1.0 : -1.0)
                : 0.0;  // 0: no prefilter
        for (int py = std::max(r.y0, y0); py <= std::min(r.y1, y0 + th - 1); ++py)
          for (int px = std::max(r.x0, x0); px <= std::min(r.x1, x0 + tw - 1); ++px) {
            const uint32_t k = static_cast<uint32_t>((py - y0) * tw + (px - x0));
            if (win[k].first > win[k].second) continue;
            int sign;
            int inside = 0;  // edges the centre is certainly inside of
            if (orient != 0) {
              const double cx = px + 0.5 - 0.5 * w, cy = 0.5 * h - py - 0.5;
              bool out = false;
              for (int e = 0; e < 3 && !out; ++e) {
                const int f = e == 2 ? 0 : e + 1;
                const double dx = qx[f] - qx[e], dy = qy[f] - qy[e];
                const double ex = cx - qx[e], ey = cy - qy[e];
                const double v = orient * (dx * ey - dy * ex), tol = edge_tolerance(dx, dy, ex, ey);
                out = v < -tol;
                inside += v > tol;
              }
              if (out) continue;
            }
            if (inside == 3 && handed != 0) {
              // Certainly inside all three edges: the exact line crosses t's interior, so the
              // perturbed side tests all give sign(E)·handed (E the projected edge functions:
              // ((a − o) × (b − o))·forward = E·((right × up)·forward) for the projections);
              // only "ahead" remains to decide exactly.
              sign = static_cast<int>(orient) * handed;
              if (!detail::ahead(tr, rays[k], axes[k], sign)) continue;
            } else if (!detail::crosses(tr, rays[k], axes[k], sign)) {
              continue;
            }
            found.push_back({k,
                             {detail::hit_t(plane, tr, rays[k]), g, tr.leaf, tr.face,
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
          const auto [lo, hi] = win[k];
          if (lo <= hi && first[k] == first[k + 1]) {
            if (outside_in_result && lo < hi) v = {true, true, lo, {}};
          } else if (lo <= hi && use_table) {
            v = resolve(std::span<RayHit>(sorted.data() + first[k], first[k + 1] - first[k]), table,
                        winding, lo, hi);
          } else if (lo <= hi && !solid.tree.nodes.empty()) {
            result.hits.assign(sorted.begin() + first[k], sorted.begin() + first[k + 1]);
            result.spans.clear();
            detail::sweep_spans(result, solid.tree, leaves);
            v = first_visible(result, lo, hi);
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
