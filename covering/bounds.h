#pragma once
// A box known to contain the result of a CSG expression, without evaluating it: leaf boxes;
// union → their hull; intersection → their overlap (empty when the operands' boxes are apart);
// difference → the first operand's box; complement → unbounded.

#include <optional>

#include "solid/solid.h"

namespace cover {

/// Empty optional when the result is unbounded (a complement at the root, or below a union).
std::optional<Bbox> result_bounds(const Solid& solid);

}  // namespace cover
