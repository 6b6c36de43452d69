#include "covering/classify.h"

#include "covering/detail/local.h"
#include "covering/detail/triangles.h"
#include "covering/predicates.h"
#include "solid/parallel.h"

namespace cover {
namespace {

using detail::CoverTri;
using detail::LeafTriangles;

/// Sign of the (y, z) orientation of (a, b, q) with q perturbed to q + (0, ε, ε²).
int perturbed_orient_yz(const Vec3& a, const Vec3& b, const Vec3& q) {
  const int o = orient2d(a, b, q, 0);
  if (o != 0) return o;
  // o(q + (0,ε,ε²)) = o(q) − (b.z − a.z)·ε + (b.y − a.y)·ε²
  if (a.z != b.z) return a.z > b.z ? 1 : -1;
  if (a.y != b.y) return b.y > a.y ? 1 : -1;
  return 0;
}

/// Adds the crossing of the +x ray from q with t to `winding`; returns true when q lies on t.
bool visit(const CoverTri& t, const Vec3& q, int& winding) {
  if (q.y < t.box.min.y || q.y > t.box.max.y || q.z < t.box.min.z || q.z > t.box.max.z ||
      q.x > t.box.max.x)
    return false;
  const int o3 = orient3d(t.a, t.b, t.c, q);  // sign of n·(q − a)
  if (o3 == 0) return detail::on_triangle(t, q);
  const int nx = orient2d(t.a, t.b, t.c, 0);  // sign of the normal's x component
  // The ray meets the plane at t > 0 iff q is behind the plane as seen along +x.
  if (nx == 0 || o3 != -nx) return false;
  if (perturbed_orient_yz(t.a, t.b, q) == nx && perturbed_orient_yz(t.b, t.c, q) == nx &&
      perturbed_orient_yz(t.c, t.a, q) == nx)
    winding += nx;  // leaving through an outward face (+1) or entering (−1)
  return false;
}

void windings(const LeafTriangles& lt, const Vec3& q, std::vector<int>& winding,
              std::vector<uint8_t>& on_surface) {
  const size_t leaves = lt.leaf_start.size() - 1;
  winding.assign(leaves, 0);
  on_surface.assign(leaves, 0);
  for (size_t l = 0; l < leaves; ++l) {
    int w = 0;
    bool on = false;
    for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i) on |= visit(lt.tris[i], q, w);
    winding[l] = w;
    on_surface[l] = on;
  }
}

PointClass classify_point(const LeafTriangles& lt, const CsgTree& tree, const Vec3& q,
                          std::vector<int>& winding, std::vector<uint8_t>& on_surface,
                          std::vector<uint8_t>& inside) {
  windings(lt, q, winding, on_surface);
  inside.resize(winding.size());
  bool any_on = false;
  for (size_t l = 0; l < winding.size(); ++l) {
    inside[l] = winding[l] != 0;
    any_on |= on_surface[l] != 0;
  }
  if (!any_on) return tree.evaluate(inside) ? PointClass::kInside : PointClass::kOutside;
  return detail::classify_on_surface(lt, tree, q, on_surface, inside);
}

}  // namespace

std::string_view to_string(PointClass c) {
  switch (c) {
    case PointClass::kOutside: return "outside";
    case PointClass::kInside: return "inside";
    case PointClass::kFace: return "face";
    case PointClass::kEdge: return "edge";
    case PointClass::kVertex: return "vertex";
  }
  return "?";
}

std::vector<PointClass> classify(const Solid& solid, std::span<const Vec3> points,
                                 const ClassifyOptions& options) {
  const LeafTriangles lt = detail::covering_triangles(solid);
  std::vector<PointClass> out(points.size());
  parallel_for(points.size(), options.grain, [&](size_t begin, size_t end) {
    std::vector<int> winding;
    std::vector<uint8_t> on_surface, inside;
    for (size_t i = begin; i < end; ++i)
      out[i] = classify_point(lt, solid.tree, points[i], winding, on_surface, inside);
  });
  return out;
}

void leaf_windings(const Solid& solid, const Vec3& q, std::vector<int>& winding,
                   std::vector<uint8_t>& on_surface) {
  windings(detail::covering_triangles(solid), q, winding, on_surface);
}

}  // namespace cover
