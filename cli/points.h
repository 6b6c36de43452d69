#pragma once
// Query points and classes of `cover classify` (docs/cli.md,
// `cover classify`).
// Points, text: one point per line, "x y z" separated by spaces, tabs or commas; '#' starts a
// comment; blank lines are skipped; "-" is stdin. Numbers, the byte order mark and errors follow
// the mesh readers' rule (io/parse.h). The text is parsed in parallel, in
// chunks of whole lines; the points and the error (the first bad line in file order) do not
// depend on the thread count.
// Points, NumPy (io/npy.h): a file named *.npy (any case), or any input whose bytes start with
// the .npy magic (stdin included); dtype float64 or float32 ('<f8', '<f4', '>f8', '>f4'), shape
// (N, 3), C or Fortran order; the data exactly fills the rest of the file.
// Every coordinate must be finite and within ±kMaxCoordinate (solid/types.h).
// Classes: a NumPy uint8 array of shape (N,), codes = PointClass order (outside 0, inside 1,
// face 2, edge 3, vertex 4; covering/classify.h).

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cover/covering/classify.h"
#include "cover/solid/types.h"

namespace cover::cli {

/// Reads the points of `path` within `max_bytes`, for a caller that needs `bytes_per_point` per
/// point besides the input (the points themselves included). The input must fit first: a regular
/// file larger than `max_bytes` is refused before reading, stdin as soon as it exceeds it
/// (solid/memory_limit.h); then every point (for text: every line, as each may hold a point)
/// must fit, before any is converted.
/// \throws InputError naming FILE ("<stdin>" for "-"): "FILE:LINE: ..." for a malformed text
/// line, "FILE: point I (counting from 0): ..." for a bad .npy value, "FILE: ..." for a malformed
/// .npy file, "FILE: not a regular file", and the memory messages.
std::vector<Vec3> read_points(const std::string& path, uint64_t max_bytes, size_t bytes_per_point);

/// Parses text points already in memory; `name` is used in messages (as read_points).
std::vector<Vec3> parse_points(std::string_view text, const std::string& name);

/// Parses the bytes of an .npy file of points; `name` is used in messages (as read_points).
std::vector<Vec3> parse_npy_points(std::string_view data, const std::string& name);

/// Throws InputError "PATH: unsupported classes format 'EXT' (expected .npy)" unless `path` ends
/// in .npy (any case); called before any work so that a typo costs nothing.
void check_classes_path(const std::string& path);

/// Writes `classes` to `path` as an .npy uint8 array of shape (N,) through write_atomically
/// (joining the caller's OutputBatch, if one is open). \throws InputError as check_classes_path,
/// "PATH: cannot write: reason", and write_atomically's "PATH: cannot write the classes (reason)".
void write_classes(const std::string& path, std::span<const PointClass> classes);
/// Writes `count` items of `item_bytes` each as a 1-d .npy array of dtype `descr` ("|u1", "<f8"),
/// as write_classes does (`what` names the content in write errors: "the distances").
void write_npy_vector(const std::string& path, std::string_view descr, const void* data,
                      size_t count, size_t item_bytes, const std::string& what);

}  // namespace cover::cli
