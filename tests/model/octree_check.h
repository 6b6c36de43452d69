#pragma once
// The octree's full / empty claims against classification (shared by the field and warp tests):
// every full (empty) leaf cell's (n + 1)³ lattice points over its closed box, corners included,
// must not classify outside (inside).
#include <vector>

#include "cover/model/model.h"

namespace cover::test {

/// The number of lattice points that contradict their cell's claim.
inline size_t certified_cells_wrong(const Model& m, const Octree& t, int n) {
  std::vector<Vec3> pts;
  std::vector<uint8_t> want;
  for (const Octree::Node& node : t.nodes) {
    if (node.first_child != 0 || node.state == CellState::kPartial) continue;
    const Bbox b = t.box(node);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        for (int k = 0; k <= n; ++k) {
          pts.push_back({b.min.x + (b.max.x - b.min.x) * i / n,
                         b.min.y + (b.max.y - b.min.y) * j / n,
                         b.min.z + (b.max.z - b.min.z) * k / n});
          want.push_back(node.state == CellState::kFull);
        }
  }
  const std::vector<PointClass> c = m.classify(pts);
  size_t wrong = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    wrong += want[i] ? c[i] == PointClass::kOutside : c[i] == PointClass::kInside;
  return wrong;
}

}  // namespace cover::test
