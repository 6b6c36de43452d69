#pragma once
// A solid prepared for queries: the solid and the structures its queries share — the BVH of its
// covering triangles (bvh.h) and, when some leaf is open, the generalized-winding trees of the
// open leaves (gwn.h). Each is built on its first use, once (thread-safe: std::call_once), and
// then shared by every query. Every kernel over a solid takes a Prepared first: classify,
// leaf_windings, cast and volume (covering/), render (render/render.h), voxelize and
// voxelize_brick (voxel/voxelize.h), build_octree (octree/octree.h); each also has a one-shot
// form on a Solid that prepares it for the one call.
// Where a new kind of leaf plugs in: a leaf that is not a closed mesh is answered through its
// prepared structure here. Open meshes today: classify() and leaf_windings() take their
// membership from gwn(), cast() their spans (open_spans); voxelize, voxelize_brick and
// build_octree answer a solid with such leaves by classify() of their points (voxel centres,
// cells' sample points), and render() by the rays' spans. A field or point-set leaf adds its
// structure beside gwn() and its membership and spans in those two places; the grids and images
// follow. Field and warp leaves are answered through covering/detail/implicit.h (a warp leaf by
// its child's Prepared, warp_child()).

#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/gwn.h"
#include "cover/solid/solid.h"

namespace cover {

struct PrepareOptions {
  BvhOptions bvh;  ///< the BVH's build
  GwnOptions gwn;  ///< the open leaves' trees' build (leaf_size); queries pass their own
};

class Prepared {
 public:
  /// Refers to `solid`, which must outlive the Prepared and not change; builds nothing yet.
  explicit Prepared(const Solid& solid, const PrepareOptions& options = {});
  Prepared(Solid&&, const PrepareOptions& = {}) = delete;  // would refer to a temporary
  Prepared(const Prepared&) = delete;
  Prepared& operator=(const Prepared&) = delete;

  const Solid& solid() const { return *solid_; }
  /// The BVH over every covering triangle, built on first use.
  const Bvh& bvh() const;
  /// The open leaves' trees, built on first use; nullptr when every leaf is closed.
  const GwnForest* gwn() const;
  /// The prepared child of warp leaf `warp` (an index into Solid::warps), built on first use
  /// with this Prepared's options; its queries answer the warp leaf's (covering/detail/implicit.h).
  const Prepared& warp_child(size_t warp) const;

 private:
  const Solid* solid_;
  PrepareOptions options_;
  mutable std::once_flag bvh_once_, gwn_once_;
  mutable std::optional<Bvh> bvh_;
  mutable std::optional<GwnForest> gwn_;
  // Sized on first use (the solid may be built after this Prepared: model/model.cpp).
  mutable std::once_flag children_once_;
  mutable std::unique_ptr<std::once_flag[]> child_once_;
  mutable std::vector<std::unique_ptr<Prepared>> children_;
};

}  // namespace cover
