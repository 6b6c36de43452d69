#pragma once
// Reading query points for `cover classify` (CONTRACT.md): one point per line, "x y z" separated
// by spaces, tabs or commas; '#' starts a comment; blank lines are skipped; "-" is stdin. Numbers,
// the byte order mark and errors follow the mesh readers' rule (solid/detail/mesh_io_detail.h).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "solid/types.h"

namespace cover::cli {

/// Reads the points of `path` within `max_bytes`, for a caller that needs `bytes_per_point` per
/// point besides the text (the points themselves included). The text must fit first: a regular
/// file larger than `max_bytes` is refused before reading, stdin as soon as it exceeds it
/// (solid/memory_limit.h); then every line counting as a point must fit, before any is parsed.
/// Throws InputError "FILE:LINE: ..." on a malformed line or a non-finite or out-of-range
/// coordinate, "FILE: not a regular file", and the memory messages naming FILE ("<stdin>" for
/// "-").
std::vector<Vec3> read_points(const std::string& path, uint64_t max_bytes, size_t bytes_per_point);

/// Parses points from text already in memory; `name` is used in messages.
std::vector<Vec3> parse_points(std::string_view text, const std::string& name);

}  // namespace cover::cli
