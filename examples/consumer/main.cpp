// Builds (box − sphere) ∪ a bar with cover::Model, then prints its exact evaluated volume, its
// ray-integrated volume with the proven bound, and the classes of a few points. `consumer` takes
// no arguments; it exits 1 if the ray volume's bound does not hold.
#include <cover/cover.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

int main() {
  const cover::Model part = (cover::box({0, 0, 0}, {2, 2, 2}) - cover::sphere({2, 2, 2}, 1)) |
                            cover::box({1.5, 0.5, 0.5}, {3.5, 1.0, 1.0});
  const cover::EvaluateResult brep = part.evaluate();  // one closed 2-manifold mesh, exact
  const cover::VolumeResult rays = part.volume();      // no evaluation: rays, proven bound
  std::printf("evaluated volume %.9f, %zu faces\n", brep.volume, brep.mesh.face_count());
  std::printf("ray volume %.9f (error bound %.3g, method %s)\n", rays.volume, rays.error_bound,
              rays.method.c_str());
  if (std::abs(rays.volume - brep.volume) > rays.error_bound + 1e-9 * brep.volume) return 1;

  const std::vector<cover::Vec3> points = {{0.5, 0.5, 0.5}, {1.9, 1.9, 1.9}, {3, 0.75, 0.75}, {2, 1, 1}};
  const std::vector<cover::PointClass> classes = part.classify(points);
  for (size_t i = 0; i < points.size(); ++i)
    std::printf("(%g, %g, %g) %s\n", points[i].x, points[i].y, points[i].z,
                std::string(cover::to_string(classes[i])).c_str());
  return 0;
}
