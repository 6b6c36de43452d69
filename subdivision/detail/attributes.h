#pragma once
// One level of corner attributes (subdivide.h, CornerAttributes): the values of the new mesh's
// corners from the old mesh's, interpolated within each old face.

#include "cover/subdivision/detail/evaluate.h"

namespace cover::subdivision_detail {

/// The attributes of `out`'s corners (out's faces already built by the level of `t`, `l`).
void refine_attributes(const Topology& t, const Layout& l, const PolygonMesh& out,
                       const CornerAttributes& in, CornerAttributes& result);

}  // namespace cover::subdivision_detail
