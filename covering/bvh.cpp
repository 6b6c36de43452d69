#include "covering/bvh.h"

#include <algorithm>
#include <cmath>

#include "covering/predicates.h"
#include "solid/parallel.h"

namespace cover {
namespace {

/// Nodes of a subtree over n triangles (median split, leaves of at most leaf_size).
uint32_t subtree_nodes(uint32_t n, uint32_t leaf_size) {
  if (n <= leaf_size) return 1;
  return 1 + subtree_nodes(n / 2, leaf_size) + subtree_nodes(n - n / 2, leaf_size);
}

/// The largest float <= v and the smallest float >= v (for doubles beyond the float range:
/// ±infinity, still conservative).
float round_down(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double v) {
  float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, INFINITY) : f;
}

/// What the build moves around (40 bytes instead of a 104-byte triangle): the triangle's box as
/// outward-rounded floats (already widened by the margin, see Bvh::Node), its centroid, and its
/// input position (the tie-breaker that keeps splits deterministic).
struct Ref {
  float lo[3], hi[3], c[3];
  uint32_t index;
};

struct Builder {
  std::vector<Ref>& refs;
  std::vector<Bvh::Node>& nodes;
  const BvhOptions& options;

  /// Builds the subtree of refs[begin, end) into nodes[slot ...].
  void build(uint32_t slot, uint32_t begin, uint32_t end) {
    const uint32_t n = end - begin;
    Bvh::Node& node = nodes[slot];
    float clo[3], chi[3];
    for (int a = 0; a < 3; ++a) {
      node.lo[a] = clo[a] = INFINITY;
      node.hi[a] = chi[a] = -INFINITY;
    }
    for (uint32_t i = begin; i < end; ++i)
      for (int a = 0; a < 3; ++a) {
        node.lo[a] = std::min(node.lo[a], refs[i].lo[a]);
        node.hi[a] = std::max(node.hi[a], refs[i].hi[a]);
        clo[a] = std::min(clo[a], refs[i].c[a]);
        chi[a] = std::max(chi[a], refs[i].c[a]);
      }
    if (n <= options.leaf_size) {
      node.first = begin;
      node.count = n;
      return;
    }
    const float ex = chi[0] - clo[0], ey = chi[1] - clo[1], ez = chi[2] - clo[2];
    const int axis = ex >= ey && ex >= ez ? 0 : (ey >= ez ? 1 : 2);
    const uint32_t mid = begin + n / 2;
    std::nth_element(refs.begin() + begin, refs.begin() + mid, refs.begin() + end,
                     [axis](const Ref& l, const Ref& r) {
                       return l.c[axis] < r.c[axis] || (l.c[axis] == r.c[axis] && l.index < r.index);
                     });
    const uint32_t left = slot + 1;
    const uint32_t right = left + subtree_nodes(n / 2, options.leaf_size);
    node.first = right;
    node.count = 0;
    if (n >= options.parallel_threshold) {
      parallel_invoke([&] { build(left, begin, mid); }, [&] { build(right, mid, end); });
    } else {
      build(left, begin, mid);
      build(right, mid, end);
    }
  }
};

}  // namespace

std::vector<Bvh::Tri> leaf_triangles(const Solid& solid) {
  const size_t faces = solid.face_count();
  // Covering triangles per face, counted first so faces can be processed in parallel.
  std::vector<uint32_t> start(faces + 1, 0);
  for (size_t f = 0; f < faces; ++f) {
    const size_t k = solid.face(f).size();
    start[f + 1] = start[f] + static_cast<uint32_t>(k >= 3 ? k - 2 : 0);
  }
  std::vector<Bvh::Tri> all(start[faces]);
  std::vector<uint8_t> keep(all.size(), 0);
  parallel_for(faces, 1024, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      auto face = solid.face(f);
      const bool rev = solid.face_sign[f] < 0;  // back to the leaf's own orientation
      auto vtx = [&](size_t i) { return solid.vertices[face[rev ? face.size() - 1 - i : i]]; };
      for (size_t i = 1; i + 1 < face.size(); ++i) {
        Bvh::Tri t{vtx(0), vtx(i), vtx(i + 1), solid.face_leaf[f], static_cast<uint32_t>(f)};
        const size_t slot = start[f] + i - 1;
        keep[slot] = orient2d(t.a, t.b, t.c, 0) != 0 || orient2d(t.a, t.b, t.c, 1) != 0 ||
                     orient2d(t.a, t.b, t.c, 2) != 0;
        all[slot] = t;
      }
    }
  });
  size_t kept = 0;
  for (size_t i = 0; i < all.size(); ++i)
    if (keep[i]) all[kept++] = all[i];
  all.resize(kept);
  return all;
}

Bvh::Bvh(const Solid& solid, const BvhOptions& options) {
  const size_t faces = solid.face_count();
  planes_.resize(faces);
  parallel_for(faces, 1024, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      auto face = solid.face(f);
      if (face.size() < 3) continue;
      const bool rev = solid.face_sign[f] < 0;
      auto vtx = [&](size_t i) { return solid.vertices[face[rev ? face.size() - 1 - i : i]]; };
      Vec3 n{};
      for (size_t i = 1; i + 1 < face.size(); ++i) n = n + cross(vtx(i) - vtx(0), vtx(i + 1) - vtx(0));
      planes_[f] = {vtx(0), n};
    }
  });
  const std::vector<Tri> all = leaf_triangles(solid);
  leaf_bounds_.resize(solid.leaves.size());
  if (all.empty()) return;
  // Widen node bounds by 1e-9 of the scene's scale: a ray slab test in doubles then errs far less
  // than the widening, so it can drop no box the exact ray meets (ray.cpp needs no padding).
  for (const Tri& t : all) {
    Bbox& leaf = leaf_bounds_[t.leaf];
    leaf.add(t.a);
    leaf.add(t.b);
    leaf.add(t.c);
  }
  for (const Bbox& b : leaf_bounds_)
    if (!b.empty()) {
      bounds_.add(b.min);
      bounds_.add(b.max);
    }
  double scale = 0;
  for (int a = 0; a < 3; ++a)
    scale = std::max({scale, std::abs(bounds_.min[a]), std::abs(bounds_.max[a])});
  const double margin = 1e-9 * scale;
  std::vector<Ref> refs(all.size());
  parallel_for(all.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Tri& t = all[i];
      Ref& r = refs[i];
      for (int a = 0; a < 3; ++a) {
        r.lo[a] = round_down(std::min({t.a[a], t.b[a], t.c[a]}) - margin);
        r.hi[a] = round_up(std::max({t.a[a], t.b[a], t.c[a]}) + margin);
        r.c[a] = static_cast<float>((t.a[a] + t.b[a] + t.c[a]) / 3);
      }
      r.index = static_cast<uint32_t>(i);
    }
  });
  BvhOptions o = options;
  o.leaf_size = std::max<uint32_t>(1, o.leaf_size);
  const auto n = static_cast<uint32_t>(refs.size());
  nodes_.resize(subtree_nodes(n, o.leaf_size));
  Builder{refs, nodes_, o}.build(0, 0, n);
  tris_.resize(n);
  parallel_for(n, 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) tris_[i] = all[refs[i].index];
  });
  for (const Node& node : nodes_) leaves_ += node.count > 0;
}

size_t Bvh::memory_bytes() const {
  return tris_.capacity() * sizeof(Tri) + nodes_.capacity() * sizeof(Node) +
         planes_.capacity() * sizeof(FacePlane);
}

}  // namespace cover
