#pragma once
// The half-edge view of one subdivision level, built from a PolygonMesh.
//   h          a corner of a face: face_start[f] + k, the half-edge from vertex fv[h] to the
//              next corner's vertex (fv = face_vertices); #H corners
//   next/prev  the following / preceding corner of the same face
//   opposite   the corner of the adjacent face running the other way, kNone on a border
//   edge       one per opposite pair or border corner, numbered by their smallest corner
//   ring       per vertex, its outgoing corners in rotation order h -> opposite(prev(h)); a
//              border vertex starts at its outgoing border corner

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::subdivision_detail {

inline constexpr uint32_t kNone = UINT32_MAX;

/// An allocator whose resize() leaves new elements uninitialized, so that the parallel loop
/// writing every slot is also the first to touch the memory.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  UninitializedAllocator(const UninitializedAllocator<U>&) {}
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) {
      ::new (static_cast<void*>(p)) U;
    } else {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  }
};
/// A vector of T whose resize() does not initialize (every slot is written before it is read).
template <class T>
using Buffer = std::vector<T, UninitializedAllocator<T>>;

struct Topology {
  const PolygonMesh* mesh = nullptr;
  Buffer<uint32_t> face_of;     ///< #H face of each corner
  Buffer<uint32_t> opposite;    ///< #H opposite corner or kNone
  Buffer<uint32_t> edge_of;     ///< #H edge of each corner
  Buffer<uint32_t> edge_half;   ///< #E the edge's smallest corner
  Buffer<uint32_t> ring_start;  ///< #V+1 offsets into ring
  Buffer<uint32_t> ring;        ///< outgoing corners of each vertex in rotation order
  std::vector<uint8_t> border;  ///< #V 1 for a border vertex

  uint32_t vertex(uint32_t h) const { return mesh->face_vertices[h]; }
  uint32_t next(uint32_t h) const {
    const uint32_t f = face_of[h];
    return h + 1 == mesh->face_start[f + 1] ? mesh->face_start[f] : h + 1;
  }
  uint32_t prev(uint32_t h) const {
    const uint32_t f = face_of[h];
    return h == mesh->face_start[f] ? mesh->face_start[f + 1] - 1 : h - 1;
  }
  uint32_t face_size(uint32_t f) const { return mesh->face_start[f + 1] - mesh->face_start[f]; }
  size_t edge_count() const { return edge_half.size(); }
};

/// The topology of `mesh`.
/// \throws InputError on a face with < 3 vertices or a repeated vertex, an index out of range, a
///   non-manifold or inconsistently oriented edge, or a non-manifold vertex (first in order).
Topology build_topology(const PolygonMesh& mesh);

/// Throws InputError naming the first face that is not a triangle (`scheme` names the scheme).
void require_triangles(const PolygonMesh& mesh, const char* scheme);

}  // namespace cover::subdivision_detail
