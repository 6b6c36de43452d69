#include "cover/covering/prepared.h"

namespace cover {

Prepared::Prepared(const Solid& solid, const PrepareOptions& options)
    : solid_(&solid), options_(options) {}

const Bvh& Prepared::bvh() const {
  std::call_once(bvh_once_, [this] { bvh_.emplace(*solid_, options_.bvh); });
  return *bvh_;
}

const GwnForest* Prepared::gwn() const {
  if (!solid_->has_open_leaf()) return nullptr;
  std::call_once(gwn_once_, [this] { gwn_.emplace(build_gwn(*solid_, options_.gwn)); });
  return &*gwn_;
}

const Prepared& Prepared::warp_child(size_t warp) const {
  std::call_once(children_once_, [this] {
    child_once_ = std::make_unique<std::once_flag[]>(solid_->warps.size());
    children_.resize(solid_->warps.size());
  });
  std::call_once(child_once_[warp], [this, warp] {
    children_[warp] = std::make_unique<Prepared>(*solid_->warps[warp].child, options_);
  });
  return *children_[warp];
}

}  // namespace cover
