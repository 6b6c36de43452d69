// Corner attributes through one subdivision level (subdivide.h "CornerAttributes" states the
// rules). Notation as in detail/topology.h; A(h) is the old value at corner h, mean(f) the mean
// over face f's corners. Every new corner's value is an affine combination of the corners of one
// old face, computed in a parallel loop over the new faces (or the old corners for Doo–Sabin),
// each writing its own slots: the values do not depend on the thread count.

#include "cover/subdivision/detail/attributes.h"

#include <cmath>
#include <numbers>

#include "cover/subdivision/detail/sqrt3.h"

namespace cover::subdivision_detail {

namespace {

constexpr size_t kGrain = 2048;

/// Writes into dst (dims values) Σ w_k · A(corner_k).
struct Values {
  const CornerAttributes& in;
  size_t dims() const { return static_cast<size_t>(in.dims); }
  const double* at(uint32_t h) const { return in.values.data() + h * dims(); }
  void copy(uint32_t h, double* dst) const {
    for (size_t d = 0; d < dims(); ++d) dst[d] = at(h)[d];
  }
  void mid(uint32_t a, uint32_t b, double* dst) const {
    for (size_t d = 0; d < dims(); ++d) dst[d] = (at(a)[d] + at(b)[d]) / 2;
  }
  void mean(const Topology& t, uint32_t f, double* dst) const {
    const uint32_t b = t.mesh->face_start[f], e = t.mesh->face_start[f + 1];
    for (size_t d = 0; d < dims(); ++d) {
      double s = 0;
      for (uint32_t h = b; h < e; ++h) s += at(h)[d];
      dst[d] = s / static_cast<double>(e - b);
    }
  }
};

void catmull_clark(const Topology& t, const Values& a, double* out) {
  const size_t k = a.dims(), corners = t.face_of.size();
  parallel_for(corners, kGrain, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c) {
      const auto h = static_cast<uint32_t>(c);
      double* q = out + 4 * k * c;  // the quad (vertex h, edge h, face point, edge prev(h))
      a.copy(h, q);
      a.mid(h, t.next(h), q + k);
      a.mean(t, t.face_of[h], q + 2 * k);
      a.mid(t.prev(h), h, q + 3 * k);
    }
  });
}

void loop(const Topology& t, const Values& a, double* out) {
  const size_t k = a.dims(), nf = t.mesh->face_count();
  parallel_for(nf, kGrain, [&](size_t b, size_t e) {
    for (size_t f = b; f < e; ++f) {
      const uint32_t h = t.mesh->face_start[f];
      double* tri = out + 12 * k * f;  // (a, e0, e2), (b, e1, e0), (c, e2, e1), (e0, e1, e2)
      for (uint32_t c = 0; c < 3; ++c) {
        a.copy(h + c, tri + (3 * c) * k);
        a.mid(h + c, h + (c + 1) % 3, tri + (3 * c + 1) * k);
        a.mid(h + (c + 2) % 3, h + c, tri + (3 * c + 2) * k);
      }
      for (uint32_t c = 0; c < 3; ++c) a.mid(h + c, h + (c + 1) % 3, tri + (9 + c) * k);
    }
  });
}

/// Doo–Sabin: the value of corner point h (new vertex h) is the scheme's mask over h's face.
void doo_sabin(const Topology& t, const Values& a, const PolygonMesh& out, double* dst) {
  const size_t k = a.dims(), corners = t.face_of.size();
  std::vector<double> point(corners * k);
  parallel_for(corners, kGrain, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c) {
      uint32_t h = static_cast<uint32_t>(c);
      const uint32_t n = t.face_size(t.face_of[h]);
      double* p = point.data() + c * k;
      for (size_t d = 0; d < k; ++d) p[d] = 0;
      for (uint32_t j = 0; j < n; ++j, h = t.next(h)) {
        const double w = n == 4 ? (j == 0   ? 9
                                   : j == 2 ? 1
                                            : 3) /
                                      16.0
                         : j == 0 ? ((5.0 / n) + 1) / 4
                                  : (3 + 2 * std::cos(2 * j * std::numbers::pi / n)) / n / 4;
        for (size_t d = 0; d < k; ++d) p[d] += w * a.at(h)[d];
      }
    }
  });
  parallel_for(out.face_vertices.size(), kGrain, [&](size_t b, size_t e) {
    for (size_t c = b; c < e; ++c)
      for (size_t d = 0; d < k; ++d) dst[c * k + d] = point[out.face_vertices[c] * k + d];
  });
}

void sqrt3(const Topology& t, const Layout& l, const Values& a, double* out) {
  const size_t k = a.dims();
  const std::vector<uint32_t> first = sqrt3_first_triangles(t);
  parallel_for(first.back(), kGrain, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      Sqrt3Corner c[3];
      sqrt3_triangle(t, l, first, i, c);
      for (int j = 0; j < 3; ++j) {
        double* dst = out + (3 * i + j) * k;
        const uint32_t h = c[j].corner;
        if (!c[j].apex) {
          a.copy(h, dst);
          continue;
        }
        const uint32_t f = t.face_of[h];
        const uint32_t r = l.refine_border ? l.refined[f] : kNone;
        if (r == kNone) {
          a.mean(t, f, dst);
          continue;
        }
        // The border points of r (a → b): (2a + b)/3 near a, (a + 2b)/3 near b.
        const double wa = sqrt3_apex_which(t, l, h) == 0 ? 2.0 / 3 : 1.0 / 3;
        for (size_t d = 0; d < k; ++d) dst[d] = wa * a.at(r)[d] + (1 - wa) * a.at(t.next(r))[d];
      }
    }
  });
}

}  // namespace

void refine_attributes(const Topology& t, const Layout& l, const PolygonMesh& out,
                       const CornerAttributes& in, CornerAttributes& result) {
  result.dims = in.dims;
  result.values.assign(out.face_vertices.size() * static_cast<size_t>(in.dims), 0.0);
  const Values a{in};
  switch (l.scheme) {
    case Scheme::kCatmullClark:
      catmull_clark(t, a, result.values.data());
      break;
    case Scheme::kLoop:
      loop(t, a, result.values.data());
      break;
    case Scheme::kDooSabin:
      doo_sabin(t, a, out, result.values.data());
      break;
    case Scheme::kSqrt3:
      sqrt3(t, l, a, result.values.data());
      break;
  }
}

}  // namespace cover::subdivision_detail
