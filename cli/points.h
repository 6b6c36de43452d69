#pragma once
// Reading query points for `cover classify` (CONTRACT.md): one point per line, "x y z" separated
// by spaces, tabs or commas; '#' starts a comment; blank lines are skipped; "-" is stdin.

#include <string>
#include <vector>

#include "solid/types.h"

namespace cover::cli {

/// Throws InputError "FILE:LINE: ..." on a malformed line or a non-finite coordinate.
std::vector<Vec3> read_points(const std::string& path);

/// Parses points from text already in memory; `name` is used in messages.
std::vector<Vec3> parse_points(const std::string& text, const std::string& name);

}  // namespace cover::cli
