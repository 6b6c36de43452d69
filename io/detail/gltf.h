#pragma once
// glTF 2.0 serialization of a mesh (io/write_gltf.cpp states the conventions).

#include <string>

#include "cover/io/mesh_io.h"

namespace cover::detail {

/// The bytes of a .gltf (binary = false: JSON, the buffer a data URI) or .glb file; `file` names
/// the target in errors.
std::string gltf_bytes(const std::string& file, const PolygonMesh& mesh, const FaceLabels* labels,
                       bool binary);

}  // namespace cover::detail
