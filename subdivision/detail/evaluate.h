#pragma once
// One level's output vertex slots (the order subdivide.h documents) and the phases that fill
// them: a template over the number type, instantiated with double (subdivide.cpp) and with
// exact rationals (exact.cpp). Each phase is a parallel loop in which every slot is written by
// one iteration from the previous level's positions only, so any thread count gives the same
// doubles.

#include <cstdint>
#include <type_traits>
#include <vector>

#include "cover/solid/parallel.h"
#include "cover/subdivision/detail/stencils.h"
#include "cover/subdivision/subdivide.h"

namespace cover::subdivision_detail {

/// Where each kind of new point goes.
struct Layout {
  Scheme scheme = Scheme::kCatmullClark;
  uint32_t edge_base = 0;           ///< CC, Loop: first edge point (= #V)
  uint32_t face_base = 0;           ///< CC: first face point; √3: first face slot (= #V)
  bool refine_border = false;       ///< √3: this level splits border edges in three
  std::vector<uint32_t> refined;    ///< √3: #F the face's refined border corner or kNone
  std::vector<uint32_t> face_slot;  ///< √3: #F the face's first vertex slot
};

inline constexpr size_t kPointGrain = 2048;

/// Fills out (sized to the level's vertex count) with the new points; round(P3<T>) -> Vec3.
template <class T, class Round>
void evaluate_points(const Topology& t, const Layout& l, std::vector<Vec3>& out,
                     const Round& round) {
  const PolygonMesh& m = *t.mesh;
  const size_t nv = m.vertices.size(), nf = m.face_count(), ne = t.edge_count();
  const auto referenced = [&](size_t v) { return t.ring_start[v + 1] > t.ring_start[v]; };
  switch (l.scheme) {
    case Scheme::kCatmullClark: {
      const auto face_point = [&](uint32_t f) {
        if constexpr (std::is_same_v<T, double>) {
          const Vec3& c = out[l.face_base + f];
          return P3<double>{c.x, c.y, c.z};
        } else {
          return centroid<T>(t, f);
        }
      };
      parallel_for(nf, kPointGrain, [&](size_t b, size_t e) {
        for (size_t f = b; f < e; ++f)
          out[l.face_base + f] = round(centroid<T>(t, static_cast<uint32_t>(f)));
      });
      parallel_for(ne, kPointGrain, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
          out[l.edge_base + i] = round(cc_edge_point<T>(t, static_cast<uint32_t>(i), face_point));
      });
      parallel_for(nv, kPointGrain, [&](size_t b, size_t e) {
        for (size_t v = b; v < e; ++v)
          out[v] = referenced(v)
                       ? round(cc_vertex_point<T>(t, static_cast<uint32_t>(v), face_point))
                       : m.vertices[v];
      });
      break;
    }
    case Scheme::kLoop:
      parallel_for(ne, kPointGrain, [&](size_t b, size_t e) {
        for (size_t i = b; i < e; ++i)
          out[l.edge_base + i] = round(loop_edge_point<T>(t, static_cast<uint32_t>(i)));
      });
      parallel_for(nv, kPointGrain, [&](size_t b, size_t e) {
        for (size_t v = b; v < e; ++v)
          out[v] = referenced(v) ? round(loop_vertex_point<T>(t, static_cast<uint32_t>(v)))
                                 : m.vertices[v];
      });
      break;
    case Scheme::kDooSabin:
      parallel_for(m.face_vertices.size(), kPointGrain, [&](size_t b, size_t e) {
        for (size_t h = b; h < e; ++h)
          out[h] = round(doo_sabin_point<T>(t, static_cast<uint32_t>(h)));
      });
      break;
    case Scheme::kSqrt3:
      parallel_for(nf, kPointGrain, [&](size_t b, size_t e) {
        for (size_t f = b; f < e; ++f) {
          const uint32_t r = l.refined.empty() ? kNone : l.refined[f];
          if (r == kNone) {
            out[l.face_slot[f]] = round(centroid<T>(t, static_cast<uint32_t>(f)));
          } else {
            out[l.face_slot[f]] = round(sqrt3_border_point<T>(t, r, 0));
            out[l.face_slot[f] + 1] = round(sqrt3_border_point<T>(t, r, 1));
          }
        }
      });
      parallel_for(nv, kPointGrain, [&](size_t b, size_t e) {
        for (size_t v = b; v < e; ++v) {
          if (!referenced(v)) {
            out[v] = m.vertices[v];
          } else if (!t.border[v]) {
            out[v] = round(sqrt3_vertex_point<T>(t, static_cast<uint32_t>(v)));
          } else {
            // A border vertex moves when the border corner arriving at it was refined.
            const uint32_t in = t.prev(t.ring[t.ring_start[v + 1] - 1]);
            const bool moves = l.refine_border && l.refined[t.face_of[in]] == in;
            out[v] = moves ? round(sqrt3_border_point<T>(t, in, 2)) : m.vertices[v];
          }
        }
      });
      break;
  }
}

/// The new points evaluated exactly and correctly rounded (exact.cpp).
void exact_points(const Topology& t, const Layout& l, std::vector<Vec3>& out);

}  // namespace cover::subdivision_detail
