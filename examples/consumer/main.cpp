#include <cover/cover.h>

#include <iostream>
#include <mutex>
#include <vector>

#include "solid/types.h"  // the consumer's own header of that name (own/solid/types.h)

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
  // A mesh from the consumer's own std::vector arrays (the value types hold std::vector): a
  // tetrahedron of volume 1/6.
  cover::PolygonMesh tet;
  tet.vertices = std::vector<cover::Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tet.face_vertices = std::vector<uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  tet.face_start = std::vector<uint32_t>{0, 3, 6, 9, 12};
  std::cout << "tetrahedron " << cover::mesh(std::move(tet)).volume({.exact = true}).volume * 6
            << '\n';
  const consumer::Vec3 own{1, 2, 3};  // the consumer's own type of the same name
  std::cout << "own " << own.x + own.y + own.z << '\n';
  static std::once_flag once;  // the consumer's own std::call_once: the C library's pthread_once
  std::call_once(once, [] { std::cout << "call_once\n"; });
}
