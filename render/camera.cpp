#include "cover/render/camera.h"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <vector>

#include "cover/solid/errors.h"

namespace cover {
namespace {

Vec3 unit(Vec3 v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

/// The box spans 1/kMargin of the image along its limiting direction (about 4% free at each end).
constexpr double kMargin = 1.08;

/// cos and sin of `degrees`, exact (0, ±1) at multiples of 90°.
std::array<double, 2> cos_sin_degrees(double degrees) {
  const double quarters = degrees / 90;
  if (quarters == std::floor(quarters) && std::abs(quarters) < 1e9) {
    const long long q = static_cast<long long>(quarters) % 4;
    switch ((q + 4) % 4) {
      case 0:
        return {1, 0};
      case 1:
        return {0, 1};
      case 2:
        return {-1, 0};
      default:
        return {0, -1};
    }
  }
  const double a = degrees * std::numbers::pi / 180.0;
  return {std::cos(a), std::sin(a)};
}

struct ViewFrame {
  Vec3 from;  ///< direction from the target to the eye (z-up frame)
  Vec3 up;    ///< up on screen (z-up frame)
};

ViewFrame frame_of(View v) {
  switch (v) {
    case View::kFront:
      return {{0, -1, 0}, {0, 0, 1}};
    case View::kBack:
      return {{0, 1, 0}, {0, 0, 1}};
    case View::kLeft:
      return {{-1, 0, 0}, {0, 0, 1}};
    case View::kRight:
      return {{1, 0, 0}, {0, 0, 1}};
    case View::kTop:
      return {{0, 0, 1}, {0, 1, 0}};
    case View::kBottom:
      return {{0, 0, -1}, {0, 1, 0}};
    case View::kIso:
      return {{1, -1, 1}, {0, 0, 1}};
  }
  return {{1, -1, 1}, {0, 0, 1}};
}

/// The view's heading: the angle of its eye direction in the horizontal plane, counter-clockwise
/// from +x (top: front's, bottom: back's, so that their screen up stays +y).
double view_heading_degrees(View v) {
  switch (v) {
    case View::kFront:
    case View::kTop:
      return -90;
    case View::kBack:
    case View::kBottom:
      return 90;
    case View::kLeft:
      return 180;
    case View::kRight:
      return 0;
    case View::kIso:
      return -45;
  }
  return -45;
}

/// The z-up frame's vector v on the world axes for up axis `a` (camera.h).
Vec3 to_world(Vec3 v, UpAxis a) {
  switch (a) {
    case UpAxis::kZ:
      return v;
    case UpAxis::kY:
      return {v.x, v.z, -v.y};
    case UpAxis::kX:
      return {v.z, v.x, v.y};
  }
  return v;
}

int up_index(UpAxis a) { return a == UpAxis::kX ? 0 : (a == UpAxis::kY ? 1 : 2); }

std::string shown(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

View parse_view(const std::string& name) {
  for (View v : {View::kIso, View::kFront, View::kBack, View::kLeft, View::kRight, View::kTop,
                 View::kBottom})
    if (name == to_string(v)) return v;
  throw InputError(parameter("view") + ": unknown view '" + name +
                   "' (expected iso, front, back, left, right, top, bottom)");
}

const char* to_string(View v) {
  switch (v) {
    case View::kIso:
      return "iso";
    case View::kFront:
      return "front";
    case View::kBack:
      return "back";
    case View::kLeft:
      return "left";
    case View::kRight:
      return "right";
    case View::kTop:
      return "top";
    case View::kBottom:
      return "bottom";
  }
  return "iso";
}

UpAxis parse_up(const std::string& name) {
  for (UpAxis a : {UpAxis::kZ, UpAxis::kY, UpAxis::kX})
    if (name == to_string(a)) return a;
  std::string text = name;
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  throw InputError(parameter("up") + ": expected x, y or z, got '" + text + "'");
}

const char* to_string(UpAxis a) {
  switch (a) {
    case UpAxis::kZ:
      return "z";
    case UpAxis::kY:
      return "y";
    case UpAxis::kX:
      return "x";
  }
  return "z";
}

double view_elevation_degrees(View v) {
  switch (v) {
    case View::kIso:
      return std::atan(std::numbers::sqrt2 / 2) * 180 / std::numbers::pi;
    case View::kTop:
      return 90;
    case View::kBottom:
      return -90;
    default:
      return 0;
  }
}

namespace {

/// max d·p over the box.
double box_support(const Bbox& box, Vec3 d) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += std::max(d[k] * box.min[k], d[k] * box.max[k]);
  return s;
}

/// Support bound of a CSG node as covering/bounds.cpp bounds its box: `cobounded` is the node's
/// membership at infinity; `value` bounds max d·p over the node's set N (cobounded: over ∁N).
struct NodeSupport {
  bool cobounded = false;
  double value = -std::numeric_limits<double>::infinity();  ///< the empty set's
};

/// ∩ of the parts, those from `first_negated` on complemented: the bounded ones' least bound;
/// with none bounded, the complement is ∪ of the complements: their greatest bound.
NodeSupport intersect_support(const std::vector<NodeSupport>& parts, size_t first_negated) {
  NodeSupport out;
  bool any_bounded = false;
  double meet = std::numeric_limits<double>::infinity();
  double hull = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].cobounded == (i >= first_negated)) {  // a bounded part
      meet = std::min(meet, parts[i].value);
      any_bounded = true;
    } else {
      hull = std::max(hull, parts[i].value);
    }
  }
  out.cobounded = !any_bounded;
  out.value = any_bounded ? meet : hull;
  return out;
}

NodeSupport node_support(const Solid& s, uint32_t node, Vec3 d) {
  const CsgNode& n = s.tree.nodes[node];
  if (n.op == CsgOp::kLeaf) {
    const Leaf& leaf = s.leaves[n.leaf];
    // A mesh leaf's set (nonzero or generalized winding number) lies in its vertices' hull.
    if (leaf.bbox.empty()) return {};
    if (leaf.is_implicit() || leaf.vertex_count == 0) return {false, box_support(leaf.bbox, d)};
    double m = -std::numeric_limits<double>::infinity();
    for (uint32_t v = leaf.first_vertex; v < leaf.first_vertex + leaf.vertex_count; ++v)
      m = std::max(m, dot(d, s.vertices[v]));
    return {false, m};
  }
  std::vector<NodeSupport> parts;
  for (uint32_t c : n.children) parts.push_back(node_support(s, c, d));
  switch (n.op) {
    case CsgOp::kComplement:
      return {!parts[0].cobounded, parts[0].value};
    case CsgOp::kIntersection:
      return intersect_support(parts, parts.size());
    case CsgOp::kDifference:
      return intersect_support(parts, 1);
    case CsgOp::kUnion: {  // ∪ X = ∁ ∩ ∁X
      NodeSupport inner = intersect_support(parts, 0);
      inner.cobounded = !inner.cobounded;
      return inner;
    }
    case CsgOp::kLeaf:
      break;
  }
  return {};
}

}  // namespace

double result_support(const Solid& solid, Vec3 d) {
  if (solid.leaves.empty() || solid.tree.nodes.empty())
    return -std::numeric_limits<double>::infinity();
  const NodeSupport r = node_support(solid, solid.tree.root, d);
  return r.cobounded ? std::numeric_limits<double>::infinity() : r.value;
}

Camera frame_camera(const Bbox& box, const CameraOptions& o) { return frame_camera(box, o, {}); }

Camera frame_camera(const Bbox& box, const CameraOptions& o, const Support& support) {
  if (!(o.zoom > 0) || !std::isfinite(o.zoom))
    throw InputError(parameter("zoom") + ": expected a positive number, got " + shown(o.zoom));
  if (o.elevation_degrees && !(*o.elevation_degrees >= -90 && *o.elevation_degrees <= 90))
    throw InputError(parameter("elevation") + ": expected a number from -90 to 90, got " +
                     shown(*o.elevation_degrees));
  if (!std::isfinite(o.pan[0]) || !std::isfinite(o.pan[1]))
    throw InputError(parameter("pan") + ": expected finite numbers, got " + shown(o.pan[0]) + "," +
                     shown(o.pan[1]));
  if (!std::isfinite(o.azimuth_degrees))
    throw InputError(parameter("azimuth") + ": expected a finite number, got " +
                     shown(o.azimuth_degrees));
  Camera c;
  c.perspective = o.perspective;
  c.width = o.width;
  c.height = o.height;
  // The framed box: its centre and half extents (an empty or single-point box: the unit cube).
  Vec3 centre{}, half{0.5, 0.5, 0.5};
  if (!box.empty()) {
    centre = 0.5 * (box.min + box.max);
    const Vec3 h = 0.5 * (box.max - box.min);
    if (dot(h, h) > 0) half = h;
  }
  const double radius = std::sqrt(dot(half, half));

  // The eye's direction and screen up in the z-up frame, turned by `azimuth`, then on the world
  // axes.
  struct Basis {
    Vec3 forward, right, up;
  };
  auto orient = [&](double azimuth) {
    ViewFrame f = frame_of(o.view);
    if (o.elevation_degrees) {
      const auto [ch, sh] = cos_sin_degrees(view_heading_degrees(o.view));
      const auto [ce, se] = cos_sin_degrees(*o.elevation_degrees);
      f = {{ce * ch, ce * sh, se}, {-se * ch, -se * sh, ce}};
    }
    if (azimuth != 0) {
      const auto [ca, sa] = cos_sin_degrees(azimuth);
      auto turn = [&](Vec3 v) { return Vec3{ca * v.x - sa * v.y, sa * v.x + ca * v.y, v.z}; };
      f = {turn(f.from), turn(f.up)};
    }
    f = {to_world(f.from, o.up), to_world(f.up, o.up)};
    Basis b;
    b.forward = unit(-1.0 * f.from);
    b.right = unit(cross(b.forward, f.up));
    b.up = cross(b.right, b.forward);
    return b;
  };
  const Basis view = orient(o.azimuth_degrees);
  c.forward = view.forward;
  c.right = view.right;
  c.up = view.up;
  // The frame the fit is computed in: the view's own, or for a turntable the unturned view's
  // (the prism below turns with it, so every azimuth gets the same numbers).
  const Basis fr = o.turntable ? orient(0) : view;

  // s(d): a bound on max d·(p − centre) over the framed set. The box's, tightened by `support`;
  // for a turntable, the corners of a 16-sided prism about the up axis around the circle
  // through the footprint's corners, a side facing the camera (it holds the box at every
  // azimuth).
  std::vector<Vec3> prism;
  if (o.turntable) {
    const int u = up_index(o.up), a = (u + 1) % 3, b = (u + 2) % 3;
    Vec3 axis;
    (u == 0 ? axis.x : (u == 1 ? axis.y : axis.z)) = 1;
    const Vec3 across = cross(axis, fr.right);  // horizontal, perpendicular to right
    constexpr int kSides = 16;
    const double r = std::hypot(half[a], half[b]) / std::cos(std::numbers::pi / kSides);
    for (int k = 0; k < kSides; ++k) {
      const double phi = std::numbers::pi * (2 * k + 1) / kSides;
      for (double sign : {-1.0, 1.0})
        prism.push_back(r * std::cos(phi) * fr.right + r * std::sin(phi) * across +
                        sign * half[u] * axis);
    }
  }
  auto box_s = [&](Vec3 d) {
    return std::abs(d.x) * half.x + std::abs(d.y) * half.y + std::abs(d.z) * half.z;
  };
  auto s = [&](Vec3 d) {
    if (o.turntable) {
      double m = -std::numeric_limits<double>::infinity();
      for (const Vec3& p : prism) m = std::max(m, dot(d, p));
      return m;
    }
    const double b = box_s(d);
    return support ? std::min(b, support(d) - dot(d, centre)) : b;
  };
  // The framed set's extent along the frame's axes: [−s(−v), s(v)] for v = right, up, forward.
  // Where the bounds cross (an empty set), the box's.
  auto interval = [&](Vec3 v) {
    const double hi = s(v), lo = -s(-1.0 * v);
    if (!(lo <= hi)) return std::array<double, 2>{-box_s(v), box_s(v)};
    return std::array<double, 2>{lo, hi};
  };
  const auto depth = interval(fr.forward);  // relative to the centre's depth
  // The box's corners relative to the centre (the prism's for a turntable): far holds them.
  std::vector<Vec3> hull = prism;
  if (!o.turntable)
    for (int k = 0; k < 8; ++k)
      hull.push_back(
          {(k & 1 ? 1 : -1) * half.x, (k & 2 ? 1 : -1) * half.y, (k & 4 ? 1 : -1) * half.z});
  // Depth range padding: keeps near < far for a flat box seen edge-on.
  const double pad = 0.02 * radius;
  const int shorter = std::min(o.width, o.height);
  double shift_r = 0, shift_u = 0;  // the target's offset from the centre along right and up
  if (o.perspective) {
    const double tan_half = std::tan(o.fov_degrees * std::numbers::pi / 360.0);
    const double tan_x = tan_half * o.width / shorter / kMargin;
    const double tan_y = tan_half * o.height / shorter / kMargin;
    // With the eye at centre + a·right − D·forward, the side plane of normal n± = ±right −
    // tan_x·forward bounds the set when s(n±) ≤ n±·eye = ±a + D·tan_x: both touch at
    // a = (s(n+) − s(n−))/2, D = (s(n+) + s(n−))/(2·tan_x); so for up. The larger D frames
    // both directions, and the eye stays in front of the set.
    auto fit = [&](Vec3 v, double tan_v, double& shift) {
      const double plus = s(v - tan_v * fr.forward), minus = s(-1.0 * v - tan_v * fr.forward);
      shift = 0.5 * (plus - minus);
      return (plus + minus) / (2 * tan_v);
    };
    const double distance =
        std::max({fit(fr.right, tan_x, shift_r), fit(fr.up, tan_y, shift_u), 2.5 * pad - depth[0]});
    c.tan_half_fov = tan_half / o.zoom;
    c.target = centre + shift_r * view.right + shift_u * view.up;
    c.eye = c.target - distance * c.forward;
    const Vec3 eye = shift_r * fr.right + shift_u * fr.up - distance * fr.forward;  // fit frame
    double farthest = 0;
    for (const Vec3& p : hull) farthest = std::max(farthest, std::sqrt(dot(p - eye, p - eye)));
    c.near = distance + depth[0] - pad;
    c.far = farthest + pad;
  } else {
    const auto across = interval(fr.right), upward = interval(fr.up);
    shift_r = 0.5 * (across[0] + across[1]);
    shift_u = 0.5 * (upward[0] + upward[1]);
    // World units per pixel that fit the extent; a set seen as a point (a segment end-on) gets
    // a shorter side of a tenth of the box's half diagonal.
    double size =
        kMargin * std::max((across[1] - across[0]) / o.width, (upward[1] - upward[0]) / o.height);
    size = std::max(size, 0.1 * radius / shorter);
    c.pixel_size = size / o.zoom;
    c.target = centre + shift_r * view.right + shift_u * view.up;
    // The image plane outside the box; near..far holds the box.
    double box_depth = 0;
    for (const Vec3& p : hull) box_depth = std::max(box_depth, std::abs(dot(p, fr.forward)));
    c.eye = c.target - (2 * radius) * c.forward;
    c.near = 2 * radius - box_depth - pad;
    c.far = 2 * radius + box_depth + pad;
  }
  if (o.pan[0] != 0 || o.pan[1] != 0) {
    // The image's extent in world units at the target's depth; eye and target move together.
    const double unit =
        o.perspective
            ? 2 * c.tan_half_fov * std::sqrt(dot(c.target - c.eye, c.target - c.eye)) / shorter
            : c.pixel_size;
    const Vec3 move = (o.pan[0] * o.width * unit) * c.right + (o.pan[1] * o.height * unit) * c.up;
    c.target = c.target + move;
    c.eye = c.eye + move;
    if (o.perspective) {  // the framed part's distances from the moved eye change by ≤ |move|
      const double m = std::sqrt(dot(move, move));
      c.near = std::max(c.near - m, 0.1 * c.near);
      c.far += m;
    }
  }
  return c;
}

Bbox section_box(const Bbox& box, const Plane& section) {
  if (box.empty()) return box;
  const Vec3 n = section.normal;
  const double d = section.offset;
  double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
  // n_k·x_k ≤ d − Σ_{j≠k} n_j·x_j over the box: the tightest bound on x_k takes the least sum.
  // Rounding error stays below a few ulps of `scale`; 1e-12·scale widens past it.
  for (int k = 0; k < 3; ++k) {
    if (n[k] == 0) continue;
    double least = 0, scale = std::abs(d);
    for (int j = 0; j < 3; ++j) {
      if (j == k) continue;
      least += std::min(n[j] * box.min[j], n[j] * box.max[j]);
      scale += std::max(std::abs(n[j] * box.min[j]), std::abs(n[j] * box.max[j]));
    }
    const double bound = (d - least) / n[k];
    const double widen = 1e-12 * scale / std::abs(n[k]) + std::numeric_limits<double>::denorm_min();
    if (!std::isfinite(bound) || !std::isfinite(widen)) continue;  // no bound: the box's own
    if (n[k] > 0)
      hi[k] = std::min(hi[k], bound + widen);
    else
      lo[k] = std::max(lo[k], bound - widen);
  }
  Bbox kept;
  if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) return kept;
  kept.add(Vec3{lo[0], lo[1], lo[2]});
  kept.add(Vec3{hi[0], hi[1], hi[2]});
  return kept;
}

}  // namespace cover
