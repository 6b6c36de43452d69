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

}  // namespace cover
