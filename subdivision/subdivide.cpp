// subdivide(): per level, the half-edge view of the previous level (detail/topology.h), the new
// points (detail/evaluate.h: faces, then edges, then vertices, each a parallel loop) and the
// new faces (one parallel loop over the old faces or edges, each writing its own slots).
// Notation as in detail/topology.h; V, E, F, H, B: vertices, edges, faces, corners, border
// edges of the previous level.
#include "cover/subdivision/subdivide.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/subdivision/detail/attributes.h"
#include "cover/subdivision/detail/evaluate.h"
#include "cover/subdivision/detail/sqrt3.h"

namespace cover {

namespace {

using subdivision_detail::build_topology;
using subdivision_detail::kNone;
using subdivision_detail::Layout;
using subdivision_detail::P3;
using subdivision_detail::Topology;

constexpr size_t kGrain = 4096;

/// Per-level counts (upper bounds where a scheme's exact count needs the topology).
struct Counts {
  uint64_t v, e, f, h;
};

Counts next_counts(Scheme s, const Counts& c) {
  switch (s) {
    case Scheme::kCatmullClark:
      return {c.v + c.e + c.f, 2 * c.e + c.h, c.h, 4 * c.h};
    case Scheme::kLoop:
      return {c.v + c.e, 2 * c.e + 3 * c.f, 4 * c.f, 4 * c.h};
    case Scheme::kDooSabin:
      return {c.h, c.h + 2 * c.e, c.f + c.e + c.v, 2 * c.h + 4 * c.e};
    case Scheme::kSqrt3:
      return {c.v + 2 * c.f, c.e + 6 * c.f, 3 * c.f, 9 * c.f};
  }
  return c;
}

/// Refuses levels whose output would exceed kMaxSubdivisionEntries, before allocating.
void check_size(const Topology& t, const SubdivideOptions& o) {
  const PolygonMesh& m = *t.mesh;
  Counts c{m.vertices.size(), t.edge_count(), m.face_count(), m.face_vertices.size()};
  for (int level = 1; level <= o.levels; ++level) {
    c = next_counts(o.scheme, c);
    if (c.v > kMaxSubdivisionEntries || c.h > kMaxSubdivisionEntries)
      throw InputError(parameter("levels") + ": " + std::to_string(o.levels) + " levels give " +
                       "more than 2^30 vertices or face entries at level " + std::to_string(level) +
                       " (kMaxSubdivisionEntries)");
  }
}

/// Sets out's faces to n-gons: `count` faces of `n` vertices, filled by fill(i, dst).
template <class Fill>
void uniform_faces(PolygonMesh& out, size_t count, uint32_t n, size_t grain, const Fill& fill) {
  out.face_start.resize(count + 1);
  out.face_vertices.resize(count * n);
  parallel_for(count + 1, kGrain, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) out.face_start[i] = static_cast<uint32_t>(i * n);
  });
  parallel_for(count / grain + 1, 64, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c)
      for (size_t i = c * grain; i < std::min(count, (c + 1) * grain); ++i)
        fill(i, out.face_vertices.data() + i * n);
  });
}

void catmull_clark_faces(const Topology& t, const Layout& l, PolygonMesh& out) {
  uniform_faces(out, t.face_of.size(), 4, 1024, [&](size_t h, uint32_t* q) {
    const auto c = static_cast<uint32_t>(h);
    q[0] = t.vertex(c);
    q[1] = l.edge_base + t.edge_of[c];
    q[2] = l.face_base + t.face_of[c];
    q[3] = l.edge_base + t.edge_of[t.prev(c)];
  });
}

void loop_faces(const Topology& t, const Layout& l, PolygonMesh& out) {
  uniform_faces(out, 4 * t.mesh->face_count(), 3, 1024, [&](size_t i, uint32_t* tri) {
    const auto f = static_cast<uint32_t>(i / 4);
    const uint32_t h = t.mesh->face_start[f];
    const uint32_t e0 = l.edge_base + t.edge_of[h], e1 = l.edge_base + t.edge_of[h + 1],
                   e2 = l.edge_base + t.edge_of[h + 2];
    const uint32_t corner[3][3] = {
        {t.vertex(h), e0, e2}, {t.vertex(h + 1), e1, e0}, {t.vertex(h + 2), e2, e1}};
    const uint32_t k = static_cast<uint32_t>(i % 4);
    for (int j = 0; j < 3; ++j) tri[j] = k < 3 ? corner[k][j] : (j == 0 ? e0 : j == 1 ? e1 : e2);
  });
}

/// Doo–Sabin: [F face-faces | interior edge quads | interior vertex faces].
void doo_sabin_faces(const Topology& t, PolygonMesh& out) {
  const PolygonMesh& m = *t.mesh;
  const size_t nf = m.face_count(), ne = t.edge_count(), nv = m.vertices.size();
  std::vector<uint32_t> interior_edges, interior_vertices;
  for (uint32_t e = 0; e < ne; ++e)
    if (t.opposite[t.edge_half[e]] != kNone) interior_edges.push_back(e);
  for (uint32_t v = 0; v < nv; ++v)
    if (!t.border[v] && t.ring_start[v + 1] > t.ring_start[v]) interior_vertices.push_back(v);
  const size_t nq = interior_edges.size(), nvf = interior_vertices.size();
  out.face_start.assign(nf + nq + nvf + 1, 0);
  for (size_t f = 0; f <= nf; ++f) out.face_start[f] = m.face_start[f];
  for (size_t i = 0; i < nq; ++i) out.face_start[nf + 1 + i] = out.face_start[nf + i] + 4;
  for (size_t i = 0; i < nvf; ++i) {
    const uint32_t v = interior_vertices[i];
    out.face_start[nf + nq + 1 + i] =
        out.face_start[nf + nq + i] + (t.ring_start[v + 1] - t.ring_start[v]);
  }
  out.face_vertices.resize(out.face_start.back());
  uint32_t* fv = out.face_vertices.data();
  parallel_for(m.face_vertices.size(), kGrain, [&](size_t b, size_t e) {
    for (size_t h = b; h < e; ++h) fv[h] = static_cast<uint32_t>(h);
  });
  parallel_for(nq, kGrain, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      const uint32_t h = t.edge_half[interior_edges[i]], o = t.opposite[h];
      uint32_t* q = fv + out.face_start[nf + i];
      q[0] = t.next(h), q[1] = h, q[2] = t.next(o), q[3] = o;
    }
  });
  parallel_for(nvf, kGrain, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      const uint32_t v = interior_vertices[i];
      uint32_t* p = fv + out.face_start[nf + nq + i];
      for (uint32_t k = t.ring_start[v]; k < t.ring_start[v + 1]; ++k) *p++ = t.ring[k];
    }
  });
}

/// √3: per edge, the flipped pair (A_f, x, A_g), (A_g, y, A_f), or the border triangle
/// (detail/sqrt3.h).
void sqrt3_faces(const Topology& t, const Layout& l, PolygonMesh& out) {
  const std::vector<uint32_t> first = subdivision_detail::sqrt3_first_triangles(t);
  uniform_faces(out, first.back(), 3, 1024, [&](size_t i, uint32_t* tri) {
    subdivision_detail::Sqrt3Corner c[3];
    subdivision_detail::sqrt3_triangle(t, l, first, i, c);
    for (int j = 0; j < 3; ++j)
      tri[j] = c[j].apex ? l.face_slot[t.face_of[c[j].corner]] +
                               subdivision_detail::sqrt3_apex_which(t, l, c[j].corner)
                         : t.vertex(c[j].corner);
  });
}

/// One level; with `attributes`, also replaces them by the new corners' values.
PolygonMesh step(const PolygonMesh& in, const Topology& t, const SubdivideOptions& o, int level,
                 CornerAttributes* attributes) {
  const size_t nv = in.vertices.size(), nf = in.face_count(), ne = t.edge_count();
  Layout l;
  l.scheme = o.scheme;
  size_t out_v = 0;
  switch (o.scheme) {
    case Scheme::kCatmullClark:
      l.edge_base = static_cast<uint32_t>(nv);
      l.face_base = static_cast<uint32_t>(nv + ne);
      out_v = nv + ne + nf;
      break;
    case Scheme::kLoop:
      l.edge_base = static_cast<uint32_t>(nv);
      out_v = nv + ne;
      break;
    case Scheme::kDooSabin:
      out_v = in.face_vertices.size();
      break;
    case Scheme::kSqrt3: {
      // CGAL splits border edges on every second level (its step index i odd).
      l.refine_border = level % 2 == 0;
      l.face_base = static_cast<uint32_t>(nv);
      l.face_slot.resize(nf);
      if (l.refine_border) l.refined.assign(nf, kNone);
      uint32_t slot = l.face_base;
      for (uint32_t f = 0; f < nf; ++f) {
        l.face_slot[f] = slot++;
        if (!l.refine_border) continue;
        for (uint32_t h = in.face_start[f]; h < in.face_start[f + 1]; ++h)
          if (t.opposite[h] == kNone) {
            l.refined[f] = h;
            ++slot;
            break;
          }
      }
      out_v = slot;
      break;
    }
  }
  PolygonMesh out;
  out.vertices.resize(out_v);
  if (o.exact_rounding) {
    subdivision_detail::exact_points(t, l, out.vertices);
  } else {
    subdivision_detail::evaluate_points<double>(t, l, out.vertices, [](const P3<double>& p) {
      return Vec3{p.x, p.y, p.z};
    });
  }
  switch (o.scheme) {
    case Scheme::kCatmullClark:
      catmull_clark_faces(t, l, out);
      break;
    case Scheme::kLoop:
      loop_faces(t, l, out);
      break;
    case Scheme::kDooSabin:
      doo_sabin_faces(t, out);
      break;
    case Scheme::kSqrt3:
      sqrt3_faces(t, l, out);
      break;
  }
  if (attributes) {
    CornerAttributes refined;
    subdivision_detail::refine_attributes(t, l, out, *attributes, refined);
    *attributes = std::move(refined);
  }
  return out;
}

const char* scheme_name(Scheme s) {
  switch (s) {
    case Scheme::kCatmullClark:
      return "Catmull-Clark";
    case Scheme::kLoop:
      return "Loop";
    case Scheme::kDooSabin:
      return "Doo-Sabin";
    case Scheme::kSqrt3:
      return "sqrt(3)";
  }
  return "";
}

}  // namespace

std::string_view to_string(Scheme scheme) {
  switch (scheme) {
    case Scheme::kCatmullClark:
      return "catmull-clark";
    case Scheme::kLoop:
      return "loop";
    case Scheme::kDooSabin:
      return "doo-sabin";
    case Scheme::kSqrt3:
      return "sqrt3";
  }
  return "";
}

std::optional<Scheme> scheme_from_string(std::string_view name) {
  for (Scheme s : {Scheme::kCatmullClark, Scheme::kLoop, Scheme::kDooSabin, Scheme::kSqrt3})
    if (to_string(s) == name) return s;
  return std::nullopt;
}

namespace {

void check_attributes(const PolygonMesh& mesh, const CornerAttributes& a) {
  if (a.dims < 1)
    throw InputError("corner attributes: " + std::to_string(a.dims) + " values per corner");
  const uint64_t expected = uint64_t(a.dims) * mesh.face_vertices.size();
  if (a.values.size() != expected)
    throw InputError("corner attributes: " + std::to_string(a.values.size()) + " values for " +
                     std::to_string(mesh.face_vertices.size()) + " corners of " +
                     std::to_string(a.dims));
  for (size_t i = 0; i < a.values.size(); ++i)
    if (!std::isfinite(a.values[i]))
      throw InputError("corner attributes: value " + std::to_string(i % a.dims) + " of corner " +
                       std::to_string(i / a.dims) + " is not finite");
}

PolygonMesh subdivide(const PolygonMesh& mesh, const SubdivideOptions& options,
                      CornerAttributes* attributes) {
  if (options.levels < 0)
    throw InputError(parameter("levels") + ": must be >= 0, got " + std::to_string(options.levels));
  if (options.scheme == Scheme::kLoop || options.scheme == Scheme::kSqrt3)
    subdivision_detail::require_triangles(mesh, scheme_name(options.scheme));
  if (attributes) check_attributes(mesh, *attributes);
  Topology t = build_topology(mesh);
  if (mesh.face_count() == 0) return mesh;
  check_size(t, options);
  PolygonMesh current;
  const PolygonMesh* in = &mesh;
  for (int level = 1; level <= options.levels; ++level) {
    if (level > 1) t = build_topology(*in);
    current = step(*in, t, options, level, attributes);
    in = &current;
  }
  if (options.levels == 0) return mesh;
  return current;
}

}  // namespace

PolygonMesh subdivide(const PolygonMesh& mesh, const SubdivideOptions& options) {
  return subdivide(mesh, options, nullptr);
}

PolygonMesh subdivide(const PolygonMesh& mesh, const SubdivideOptions& options,
                      CornerAttributes& attributes) {
  return subdivide(mesh, options, &attributes);
}

}  // namespace cover
