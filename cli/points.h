#pragma once
// Reading query points for `cover classify` (CONTRACT.md): one point per line, "x y z" separated
// by spaces, tabs or commas; '#' starts a comment; blank lines are skipped; "-" is stdin. Numbers,
// the byte order mark and errors follow the mesh readers' rule (solid/detail/mesh_io_detail.h).

#include <string>
#include <string_view>
#include <vector>

#include "solid/types.h"

namespace cover::cli {

/// Throws InputError "FILE:LINE: ..." on a malformed line or a non-finite or out-of-range
/// coordinate, "FILE: cannot open: ..." / "FILE: cannot read: ..." (a folder) otherwise.
std::vector<Vec3> read_points(const std::string& path);

/// Parses points from text already in memory; `name` is used in messages.
std::vector<Vec3> parse_points(std::string_view text, const std::string& name);

}  // namespace cover::cli
