#include <cover/cover.h>

#include <iostream>
#include <mutex>
#include <vector>

int main(int argc, char** argv) {  // argv[1]: a scene (default: Cover's models/default.json)
  const cover::Model part = cover::box({0, 0, 0}, {2, 2, 2}) - cover::sphere({2, 2, 2}, 1.2);
  std::cout << "volume " << part.volume({.exact = true}).volume << '\n';  // exact B-rep volume
  const std::vector<cover::Vec3> points = {{1, 1, 1}, {2, 2, 2}, {0, 1, 1}, {2, 0, 0}};
  for (cover::PointClass c : part.classify(points)) std::cout << cover::to_string(c) << '\n';
  const cover::Model scene = cover::load(argc > 1 ? argv[1] : "models/default.json");
  const cover::Model half = scene & cover::box({-9, -9, -9}, {9, 9, 0});  // its lower half
  const cover::EvaluateResult brep = half.evaluate();  // one closed, outward 2-manifold
  cover::write_mesh("half.off", brep.mesh);
  std::cout << brep.mesh.face_count() << " faces, volume " << brep.volume << '\n';
  static std::once_flag once;  // the consumer's own std::call_once: the C library's pthread_once
  std::call_once(once, [] {});
}
