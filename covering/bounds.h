#pragma once
// Boundedness and a box known to contain the result of a CSG expression, without evaluating
// it. A point far from every leaf is outside every leaf, so the result is bounded exactly when
// the expression is false with every leaf outside (a complement at the root is unbounded, a
// double complement is not). The box: leaf boxes; union → hull; intersection → overlap (empty
// when the operands' boxes are apart); difference → the first operand's box; a complemented
// operand of an intersection or difference leaves the others' box; nested complements are
// tracked (De Morgan), so every bounded expression gets a box.

#include <optional>
#include <string>

#include "cover/solid/solid.h"

namespace cover {

/// True when the result is a bounded set (exact: evaluates the tree with every leaf outside).
bool is_bounded(const Solid& solid);

/// A box containing the result; empty optional exactly when !is_bounded(solid).
std::optional<Bbox> result_bounds(const Solid& solid);

/// The one-line message of commands that need a bounded result, naming the input.
std::string unbounded_message(const std::string& input);

}  // namespace cover
