#pragma once
// Point-cloud files of point-set leaves (docs/cli.md "Point sets"):
//   .xyz, .txt, .pts, .csv  text, one point per line: "x y z" or "x y z nx ny nz" (spaces, tabs or
//                           commas; '#' starts a comment; blank lines skipped; every line the same
//                           count), numbers by the mesh readers' rule (io/parse.h)
//   .npy                    float64 or float32 (little or big endian), shape (N, 3) or (N, 6)
//                           (normals in the last three columns), C order
//   .ply .off .obj .stl     the vertices of a mesh file (positions only; faces are ignored)

#include <filesystem>
#include <vector>

#include "cover/solid/memory_limit.h"
#include "cover/solid/types.h"

namespace cover {

struct PointCloud {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;  ///< empty when the file has none
};

/// \throws InputError naming the file and the line (text) or the point (.npy): a malformed
/// line, a mixed column count, a bad .npy header or dtype, a file over `max_file_bytes`.
PointCloud read_point_cloud(const std::filesystem::path& path,
                            uint64_t max_file_bytes = kDefaultMaxMemoryBytes);

}  // namespace cover
