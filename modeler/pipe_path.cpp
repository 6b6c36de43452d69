// Curved pipes: the centre curve, the transported frames and the rings (detail/pipe_path.h).
// Hand-written: a cubic Hermite curve and a frame transported by minimal rotations are a few
// lines each; TopMod's handles (hermiteConnectFaces) use the same curve.

#include "cover/modeler/detail/pipe_path.h"

#include <cmath>
#include <string>

#include "cover/solid/errors.h"

namespace cover::modeler::detail {

namespace {

constexpr int kStepsPerRing = 64;

double length(const Vec3& v) { return std::sqrt(dot(v, v)); }

/// The rotation taking unit a to unit b about a × b (Rodrigues); about an axis across a when
/// they are opposite.
Frame minimal_rotation(const Vec3& a, const Vec3& b) {
  const double c = dot(a, b);
  Vec3 v = cross(a, b);
  if (1 + c < 1e-12) {  // opposite: a half turn about any axis across a
    Vec3 axis = cross(a, Vec3{1, 0, 0});
    if (dot(axis, axis) < 1e-6) axis = cross(a, Vec3{0, 1, 0});
    axis = (1 / length(axis)) * axis;
    Frame r;
    const double k[3] = {axis.x, axis.y, axis.z};
    for (int i = 0; i < 3; ++i) {
      double e[3];
      for (int j = 0; j < 3; ++j) e[j] = 2 * k[i] * k[j] - (i == j ? 1 : 0);
      r.row[i] = {e[0], e[1], e[2]};
    }
    return r;
  }
  const double s = 1 / (1 + c);
  // R = I + [v]× + [v]×² / (1 + c)
  return Frame{{{1 - s * (v.y * v.y + v.z * v.z), -v.z + s * v.x * v.y, v.y + s * v.x * v.z},
                {v.z + s * v.x * v.y, 1 - s * (v.x * v.x + v.z * v.z), -v.x + s * v.y * v.z},
                {-v.y + s * v.x * v.z, v.x + s * v.y * v.z, 1 - s * (v.x * v.x + v.y * v.y)}}};
}

Frame compose(const Frame& r, const Frame& f) {  // r · f
  Frame out;
  for (int i = 0; i < 3; ++i) {
    const Vec3 col[3] = {{f.row[0].x, f.row[1].x, f.row[2].x},
                         {f.row[0].y, f.row[1].y, f.row[2].y},
                         {f.row[0].z, f.row[1].z, f.row[2].z}};
    out.row[i] = {dot(r.row[i], col[0]), dot(r.row[i], col[1]), dot(r.row[i], col[2])};
  }
  return out;
}

Vec3 unit_tangent(const PipePath& path, double t) {
  Vec3 p, d;
  pipe_curve(path, t, p, d);
  const double l = length(d);
  if (!(l > 0))
    throw InputError("create_pipe: the curved path has a zero tangent at t = " + std::to_string(t) +
                     " (a cusp): change the weights or the path points");
  return (1 / l) * d;
}

}  // namespace

Vec3 Frame::apply_transposed(const Vec3& v) const {
  return v.x * row[0] + v.y * row[1] + v.z * row[2];
}

void pipe_curve(const PipePath& path, double t, Vec3& point, Vec3& tangent) {
  std::vector<Vec3> p{path.c1};
  p.insert(p.end(), path.points.begin(), path.points.end());
  p.push_back(path.c2);
  const int pieces = static_cast<int>(p.size()) - 1;
  const int k = std::min(pieces - 1, static_cast<int>(std::floor(t * pieces)));
  const double u = t * pieces - k;
  const auto tangent_at = [&](int i) -> Vec3 {
    if (i == 0) return (path.weight1 * length(p[1] - p[0])) * path.n1;
    if (i == pieces) return (-path.weight2 * length(p[i] - p[i - 1])) * path.n2;
    return 0.5 * (p[i + 1] - p[i - 1]);
  };
  const Vec3 m0 = tangent_at(k), m1 = tangent_at(k + 1);
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
               h11 = u3 - u2;
  point = h00 * p[k] + h10 * m0 + h01 * p[k + 1] + h11 * m1;
  // d/dt = pieces · d/du
  const double d00 = 6 * u2 - 6 * u, d10 = 3 * u2 - 4 * u + 1, d01 = -6 * u2 + 6 * u,
               d11 = 3 * u2 - 2 * u;
  tangent = static_cast<double>(pieces) * (d00 * p[k] + d10 * m0 + d01 * p[k + 1] + d11 * m1);
}

std::vector<Frame> pipe_frames(const PipePath& path, int segments) {
  std::vector<Frame> frames{Frame{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};
  Vec3 previous = unit_tangent(path, 0);
  Frame f = frames[0];
  for (int j = 1; j <= segments; ++j) {
    for (int s = 1; s <= kStepsPerRing; ++s) {
      const double t = (j - 1 + static_cast<double>(s) / kStepsPerRing) / segments;
      const Vec3 next = unit_tangent(path, t);
      f = compose(minimal_rotation(previous, next), f);
      previous = next;
    }
    frames.push_back(f);
  }
  return frames;
}

double pipe_correspondence_cost(const PipePath& path, const std::vector<Vec3>& p1,
                                const std::vector<Vec3>& p2_sigma, const Frame& end_frame) {
  double cost = 0;
  for (size_t i = 0; i < p1.size(); ++i) {
    const Vec3 d = (p1[i] - path.c1) - end_frame.apply_transposed(p2_sigma[i] - path.c2);
    cost += dot(d, d);
  }
  return cost;
}

std::vector<Vec3> pipe_rings(const PipePath& path, const std::vector<Vec3>& p1,
                             const std::vector<Vec3>& p2, int segments) {
  const std::vector<Frame> frames = pipe_frames(path, segments);
  const size_t n = p1.size();
  std::vector<Vec3> rings;
  rings.reserve(n * static_cast<size_t>(segments - 1));
  for (int j = 1; j < segments; ++j) {
    const double t = static_cast<double>(j) / segments;
    Vec3 c, d;
    pipe_curve(path, t, c, d);
    for (size_t i = 0; i < n; ++i) {
      const Vec3 a = p1[i] - path.c1;
      const Vec3 b = frames[segments].apply_transposed(p2[i] - path.c2);
      rings.push_back(c + frames[j].apply((1 - t) * a + t * b));
    }
  }
  return rings;
}

}  // namespace cover::modeler::detail
