#pragma once
// PolygonMesh: the plain indexed polygon soup every reader produces and every writer takes.
//   vertices      #V points
//   face_start    #F+1 offsets into face_vertices (face_start[0] == 0, non-decreasing)
//   face_vertices concatenated vertex indices; face f is face_vertices[face_start[f] ..
//   face_start[f+1])
// A face is a closed polygon, counter-clockwise seen from outside. A face may hold several loops
// joined by false edges (an index pair that appears once in each direction inside the face,
// [Segura2004 §3 Fig. 1]); such faces are kept as one index list.

#include <cstdint>
#include <span>
#include <vector>

#include "cover/solid/types.h"

namespace cover {

struct PolygonMesh {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> face_start{0};
  std::vector<uint32_t> face_vertices;

  size_t face_count() const { return face_start.size() - 1; }
  std::span<const uint32_t> face(size_t f) const {
    return {face_vertices.data() + face_start[f], face_start[f + 1] - face_start[f]};
  }
  /// Appends one face (indices are not checked here).
  void add_face(std::span<const uint32_t> loop) {
    face_vertices.insert(face_vertices.end(), loop.begin(), loop.end());
    face_start.push_back(static_cast<uint32_t>(face_vertices.size()));
  }
  void add_face(std::initializer_list<uint32_t> loop) {
    add_face(std::span<const uint32_t>(loop.begin(), loop.size()));
  }
};

/// Bounding box of the vertices that faces reference (unreferenced vertices are ignored).
Bbox face_bbox(const PolygonMesh& mesh);

}  // namespace cover
