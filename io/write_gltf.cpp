// glTF 2.0 mesh output (.gltf: JSON with the buffer embedded as a data URI; .glb: the binary
// container), through tinygltf (Debian libtinygltf-dev; header-only, compiled here once).
// Conventions:
//   - one buffer: positions (float32 VEC3; glTF has no double positions, so coordinates round to
//     float as for STL), then the triangle indices (uint32) of each primitive in turn;
//   - polygons are fan-triangulated (v0, vi, vi+1), as the STL writer does;
//   - without FaceLabels one primitive with a neutral grey material; with labels one primitive
//     per label value present (in increasing order), each with its own material named
//     obj_groups[label] (or "label_N") whose baseColorFactor is FaceLabels::colours[label]
//     (sRGB bytes, converted to glTF's linear factors: c = ((s/255 + 0.055)/1.055)^2.4, or
//     s/255/12.92 below 0.04045), metallic 0, roughness 1;
//   - the y axis is up in glTF; Cover writes its coordinates unchanged (z up) and adds the node
//     rotation that shows z up: -90° about x, so viewers stand the model upright.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_USE_CPP14
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

#include "cover/io/detail/gltf.h"
#include "cover/io/parse.h"

namespace cover::detail {

namespace {

double linear(uint8_t s) {
  const double c = s / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

template <class T>
void append_bytes(std::vector<unsigned char>& data, const T* values, size_t count) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(values);
  data.insert(data.end(), bytes, bytes + count * sizeof(T));
}

}  // namespace

std::string gltf_bytes(const std::string& file, const PolygonMesh& mesh, const FaceLabels* labels,
                       bool binary) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Cover";
  tinygltf::Buffer buffer;
  // Positions and their bounds (accessor min/max are required for POSITION).
  std::vector<float> positions;
  positions.reserve(3 * mesh.vertices.size());
  std::vector<double> lo(3, HUGE_VAL), hi(3, -HUGE_VAL);
  for (const Vec3& p : mesh.vertices)
    for (int k = 0; k < 3; ++k) {
      const auto f = static_cast<float>(p[k]);
      positions.push_back(f);
      lo[k] = std::min(lo[k], double(f));
      hi[k] = std::max(hi[k], double(f));
    }
  append_bytes(buffer.data, positions.data(), positions.size());
  tinygltf::BufferView position_view;
  position_view.buffer = 0;
  position_view.byteLength = buffer.data.size();
  position_view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  model.bufferViews.push_back(position_view);
  tinygltf::Accessor position_accessor;
  position_accessor.bufferView = 0;
  position_accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  position_accessor.count = mesh.vertices.size();
  position_accessor.type = TINYGLTF_TYPE_VEC3;
  if (!mesh.vertices.empty()) position_accessor.minValues = lo, position_accessor.maxValues = hi;
  model.accessors.push_back(position_accessor);

  // Faces per primitive: by label, or all in one.
  std::map<uint32_t, std::vector<uint32_t>> triangles;  // label -> indices
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    std::vector<uint32_t>& out = triangles[labels ? labels->labels[f] : 0];
    for (size_t i = 1; i + 1 < loop.size(); ++i)
      out.insert(out.end(), {loop[0], loop[i], loop[i + 1]});
  }
  tinygltf::Mesh gltf_mesh;
  for (const auto& [label, indices] : triangles) {
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.data.size();
    append_bytes(buffer.data, indices.data(), indices.size());
    view.byteLength = indices.size() * sizeof(uint32_t);
    view.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
    model.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model.bufferViews.size() - 1);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = indices.size();
    accessor.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(accessor);
    tinygltf::Material material;
    std::array<uint8_t, 3> colour{200, 200, 200};
    if (labels) {
      material.name = label < labels->obj_groups.size() ? labels->obj_groups[label]
                                                        : "label_" + std::to_string(label);
      if (label < labels->colours.size()) colour = labels->colours[label];
    } else {
      material.name = "surface";
    }
    material.pbrMetallicRoughness.baseColorFactor = {linear(colour[0]), linear(colour[1]),
                                                     linear(colour[2]), 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    material.doubleSided = false;
    model.materials.push_back(material);
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = 0;
    primitive.indices = static_cast<int>(model.accessors.size() - 1);
    primitive.material = static_cast<int>(model.materials.size() - 1);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    gltf_mesh.primitives.push_back(primitive);
  }
  // 4-byte alignment of the index views after float positions holds (both are 4-byte types).
  model.buffers.push_back(std::move(buffer));
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "cover";
  node.rotation = {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)};  // z up shown as glTF's y up
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, !binary, binary))
    fail_file(file, "cannot write: the glTF serializer failed");
  return stream.str();
}

}  // namespace cover::detail
