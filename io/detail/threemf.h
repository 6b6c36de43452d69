#pragma once
// 3MF serialization of a mesh (io/write_3mf.cpp states the conventions).

#include <string>

#include "cover/io/mesh_io.h"

namespace cover::detail {

/// The bytes of a .3mf package; `file` names the target in errors.
std::string threemf_bytes(const std::string& file, const PolygonMesh& mesh,
                          const FaceLabels* labels);

}  // namespace cover::detail
