#include "cover/solid/polygon_mesh.h"

namespace cover {

Bbox face_bbox(const PolygonMesh& mesh) {
  Bbox box;
  for (uint32_t v : mesh.face_vertices) box.add(mesh.vertices[v]);
  return box;
}

}  // namespace cover
