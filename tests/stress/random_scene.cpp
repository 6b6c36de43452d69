#include "random_scene.h"

#include <algorithm>
#include <cstdio>
#include <random>

#include "cover/solid/transform.h"

namespace cover::stress {
namespace {

class Draw {
 public:
  explicit Draw(uint64_t seed) : rng_(seed) {}
  /// Uniform in [lo, hi) from 53 random bits.
  double real(double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng_() >> 11) * 0x1p-53);
  }
  /// Uniform integer in [0, n).
  int below(int n) { return static_cast<int>(rng_() % static_cast<uint64_t>(n)); }
  bool chance(int in, int of) { return below(of) < in; }

 private:
  std::mt19937_64 rng_;
};

std::string num(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string vec(double x, double y, double z) {
  return "[" + num(x) + ", " + num(y) + ", " + num(z) + "]";
}

/// A random unit-ish axis (never zero).
Vec3 axis(Draw& d) {
  for (;;) {
    // z, y, x: the order every recorded seed's scene was drawn in.
    const double z = d.real(-1, 1), y = d.real(-1, 1), x = d.real(-1, 1);
    const Vec3 a{x, y, z};
    if (std::sqrt(dot(a, a)) > 0.1) return a;
  }
}

struct Leaf {
  std::string json, name;
};

Leaf box_leaf(Draw& d) {
  if (d.chance(2, 5)) {  // on the 1/4 grid: faces coincide with other grid boxes
    const double lo[3] = {0.25 * (d.below(7) - 4), 0.25 * (d.below(7) - 4),
                          0.25 * (d.below(7) - 4)};
    const double hi[3] = {lo[0] + 0.25 * (1 + d.below(6)), lo[1] + 0.25 * (1 + d.below(6)),
                          lo[2] + 0.25 * (1 + d.below(6))};
    return {"{\"box\": {\"min\": " + vec(lo[0], lo[1], lo[2]) +
                ", \"max\": " + vec(hi[0], hi[1], hi[2]) + "}}",
            "gridbox"};
  }
  const double h[3] = {d.real(0.2, 0.8), d.real(0.2, 0.8), d.real(0.2, 0.8)};
  const Vec3 a = axis(d);
  const double degrees = d.real(0, 360);
  const double t[3] = {d.real(-0.5, 0.5), d.real(-0.5, 0.5), d.real(-0.5, 0.5)};
  return {
      "{\"box\": {\"min\": " + vec(-h[0], -h[1], -h[2]) + ", \"max\": " + vec(h[0], h[1], h[2]) +
          "}, \"transform\": {\"rotate\": {\"axis\": " + vec(a.x, a.y, a.z) +
          ", \"degrees\": " + num(degrees) + "}, \"translate\": " + vec(t[0], t[1], t[2]) + "}}",
      "box"};
}

Leaf mesh_leaf(Draw& d, const MeshEntry& m) {
  const Vec3 c = 0.5 * (m.box.min + m.box.max);
  const Vec3 e = m.box.max - m.box.min;
  const double ext = std::max({e.x, e.y, e.z});
  const double size = d.real(0.4, 1.0);  // half the side of the cube it is scaled into
  Vec3 scale{2 * size / ext, 2 * size / ext, 2 * size / ext};
  if (d.chance(1, 3))  // a braced list is evaluated left to right: x, y, z draw in order
    scale = {scale.x * d.real(0.6, 1.4), scale.y * d.real(0.6, 1.4), scale.z * d.real(0.6, 1.4)};
  const double cz = d.real(-0.5, 0.5), cy = d.real(-0.5, 0.5), cx = d.real(-0.5, 0.5);
  const Vec3 centre{cx, cy, cz};          // drawn z, y, x (as above)
  const double degrees = d.real(0, 360);  // before the axis, as every recorded seed drew them
  const Transform matrix =
      Transform::trs(scale, axis(d), degrees, centre) * Transform::translation({-c.x, -c.y, -c.z});
  std::string json = "{\"mesh\": \"" + m.path.string() + "\", \"transform\": {\"matrix\": [";
  for (int i = 0; i < 16; ++i)
    json += (i ? ", " : "") + num(i < 12 ? matrix.rows[i / 4][i % 4] : (i == 15 ? 1.0 : 0.0));
  return {json + "]}}", m.path.stem().string()};
}

Leaf leaf(Draw& d, const std::vector<MeshEntry>& meshes, int& leaves) {
  ++leaves;
  if (d.chance(1, 3)) return box_leaf(d);
  return mesh_leaf(d, meshes[d.below(static_cast<int>(meshes.size()))]);
}

/// An operation node of `depth` levels (≥ 2): its operands are leaves, or (depth 3) operations.
Leaf operation(Draw& d, const std::vector<MeshEntry>& meshes, int depth, bool root, int& leaves) {
  static const char* const kOps[] = {"union", "intersection", "difference"};
  static const char* const kSymbols[] = {" ∪ ", " ∩ ", " − "};
  const int op = d.below(3);
  const int operands = d.chance(1, 4) ? 3 : 2;
  Leaf out{std::string("{\"") + kOps[op] + "\": [", "("};
  for (int k = 0; k < operands; ++k) {
    const bool nested = depth > 2 && ((root && k == 0) || d.chance(1, 2));
    const Leaf child =
        nested ? operation(d, meshes, depth - 1, false, leaves) : leaf(d, meshes, leaves);
    out.json += (k ? ",\n  " : "\n  ") + child.json;
    out.name += (k ? kSymbols[op] : "") + child.name;
  }
  out.json += "\n]}";
  out.name += ")";
  return out;
}

}  // namespace

RandomScene random_scene(uint64_t seed, const std::vector<MeshEntry>& meshes) {
  Draw d(seed);
  RandomScene s;
  s.depth = d.chance(1, 2) ? 3 : 2;
  const Leaf root = operation(d, meshes, s.depth, true, s.leaves);
  s.json = root.json + "\n";
  s.description = root.name;
  return s;
}

}  // namespace cover::stress
