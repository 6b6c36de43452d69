#pragma once
// Mesh file reading and writing. Format is chosen by the file extension (case-insensitive):
//   read:  .obj, .off, .stl (ASCII or binary, detected from content), .ply (ascii,
//          binary_little_endian, binary_big_endian)
//   write: .off, .obj, .stl (binary), .ply (binary_little_endian)
// Readers are hand-written (see mesh_io.cpp for why and the measurement).

#include <filesystem>
#include <string>
#include <vector>

#include "cover/solid/memory_limit.h"
#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Reads a polygon mesh. Faces keep their vertex order; polygons are not triangulated.
/// STL triangles are welded by exact coordinate equality.
/// Throws InputError "FILE:LINE: message" (binary formats: "FILE: byte N: ..." or
/// "FILE: triangle N (byte B): ..."; whole-file problems: "FILE: empty file", "FILE: no faces")
/// for any malformed input: empty, truncated, wrong counts, indices out of range, NaN/inf
/// coordinates, absurd sizes (counts that cannot fit the file are refused before allocating),
/// binary garbage, faces with fewer than 3 vertices, unsupported extension, unreadable file, and
/// (read_regular_file, solid/memory_limit.h) a FIFO / device / directory ("FILE: not a regular
/// file") or a file larger than `max_file_bytes` (refused before reading).
/// Numbers follow one rule in every text format (io/parse.h): a leading '+' is
/// allowed, overflow (1e400) is an error, underflow rounds to 0. Non-fatal problems (a binary
/// STL's trailing bytes) are appended to `*warnings` when given, one line each naming the file.
PolygonMesh read_mesh(const std::filesystem::path& path,
                      uint64_t max_file_bytes = kDefaultMaxMemoryBytes,
                      std::vector<std::string>* warnings = nullptr);

/// Writes a mesh atomically (io/atomic_file.h: a temporary beside the target, then rename;
/// inside an OutputBatch, renamed with the batch's other outputs).
/// Polygons are fan-triangulated for STL, glTF (.gltf, .glb) and 3MF (coordinates rounded to
/// float);
/// .off/.obj/.ply round trips are exact. Throws InputError on unsupported extension, I/O failure,
/// or a mesh that cannot be written (index out of range, face with fewer than 3 vertices,
/// non-finite vertex).
void write_mesh(const std::filesystem::path& path, const PolygonMesh& mesh);

/// Per-face labels (e.g. the source leaf of each face of an evaluated mesh) for the formats
/// that can hold them: .ply gets a face property `int <ply_property>` after vertex_indices;
/// .obj a line "g <obj_groups[label]>" before each run of faces with the same label (faces keep
/// their order, so indices match the unlabelled file); .gltf / .glb one primitive per label with
/// a material named obj_groups[label] in colours[label] (io/write_gltf.cpp); .3mf a base
/// material per label, the same name and colour, set on each triangle (io/write_3mf.cpp).
struct FaceLabels {
  std::string ply_property = "label";
  std::vector<uint32_t> labels;         ///< one per face
  std::vector<std::string> obj_groups;  ///< group name per label value (no whitespace)
  /// glTF: the material colour per label value (sRGB bytes); labels beyond it get grey.
  std::vector<std::array<uint8_t, 3>> colours;
};

/// write_mesh with face labels. Throws InputError as above, for .off / .stl ("cannot carry face
/// labels"), or when labels.labels does not have one label per face.
void write_mesh(const std::filesystem::path& path, const PolygonMesh& mesh,
                const FaceLabels& labels);

/// read_mesh() that also returns the texture coordinates of an OBJ file's corners in `uvs`: u, v
/// per corner in face_vertices order (a `vt` line's w is dropped; a missing v reads 0). `uvs` is
/// empty for other formats and for an OBJ whose faces name no texture coordinates.
/// \throws InputError as read_mesh, and "FILE:LINE: ..." for a texture index out of range or 0,
///   or an OBJ in which some corners name a texture coordinate and others do not.
PolygonMesh read_mesh_with_uvs(const std::filesystem::path& path, std::vector<double>& uvs,
                               uint64_t max_file_bytes = kDefaultMaxMemoryBytes,
                               std::vector<std::string>* warnings = nullptr);

/// write_mesh() of an OBJ with texture coordinates: one `vt u v` line per corner (2 values per
/// corner in `uvs`, face_vertices order) and faces `f v/t ...`. \throws InputError as write_mesh,
/// for another format than .obj, or when uvs does not hold 2 finite values per corner.
void write_mesh_with_uvs(const std::filesystem::path& path, const PolygonMesh& mesh,
                         const std::vector<double>& uvs);

/// True if the extension names a mesh format read_mesh understands.
bool is_mesh_extension(const std::filesystem::path& path);

/// True if the extension names a mesh format write_mesh writes: the read formats, glTF 2.0
/// (.gltf, .glb) and 3MF (.3mf).
bool is_mesh_output_extension(const std::filesystem::path& path);

/// The mesh output formats for messages.
inline constexpr const char* kMeshOutputFormats = ".off, .obj, .stl, .ply, .gltf, .glb or .3mf";

/// The extension of `path` with its dot, ASCII-lowercased (".OFF" → ".off"), or empty: how every
/// reader and writer picks a format.
std::string lower_extension(const std::filesystem::path& path);

}  // namespace cover
