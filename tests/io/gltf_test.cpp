// glTF 2.0 output (io/write_gltf.cpp) read back by a parser written here from the specification
// (the GLB container: a 12-byte header, a JSON chunk, a BIN chunk; accessors into buffer views),
// independent of tinygltf: the same vertices (as float), the same triangles per label, one
// material per label in its colour (sRGB bytes → linear factors), .gltf and .glb alike.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "helpers.h"

namespace cover {
namespace {

using nlohmann::json;

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The JSON and the binary buffer of a .glb or a .gltf (base64 data URI).
struct Gltf {
  json doc;
  std::string bin;
};

std::string base64_decode(const std::string& text) {
  std::string out;
  int value = 0, bits = -8;
  for (char c : text) {
    int d = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
                                   : -1;
    if (d < 0) break;
    value = (value << 6) + d;
    bits += 6;
    if (bits >= 0) {
      out.push_back(static_cast<char>((value >> bits) & 0xFF));
      bits -= 8;
    }
  }
  return out;
}

Gltf parse(const std::filesystem::path& p) {
  const std::string bytes = read_file(p);
  Gltf g;
  if (p.extension() == ".glb") {
    uint32_t header[3], chunk[2];
    std::memcpy(header, bytes.data(), 12);
    EXPECT_EQ(header[0], 0x46546C67u);  // "glTF"
    EXPECT_EQ(header[1], 2u);
    EXPECT_EQ(header[2], bytes.size());
    std::memcpy(chunk, bytes.data() + 12, 8);
    EXPECT_EQ(chunk[1], 0x4E4F534Au);  // "JSON"
    g.doc = json::parse(bytes.substr(20, chunk[0]));
    const size_t at = 20 + chunk[0];
    uint32_t bin[2];
    std::memcpy(bin, bytes.data() + at, 8);
    EXPECT_EQ(bin[1], 0x004E4942u);  // "BIN\0"
    g.bin = bytes.substr(at + 8, bin[0]);
  } else {
    g.doc = json::parse(bytes);
    const std::string uri = g.doc["buffers"][0]["uri"];
    const std::string prefix = "data:application/octet-stream;base64,";
    EXPECT_EQ(uri.rfind(prefix, 0), 0u);
    g.bin = base64_decode(uri.substr(prefix.size()));
  }
  return g;
}

template <class T>
std::vector<T> accessor(const Gltf& g, int index) {
  const json& a = g.doc["accessors"][index];
  const json& view = g.doc["bufferViews"][a["bufferView"].get<int>()];
  const size_t count = a["count"].get<size_t>() * (a["type"] == "VEC3" ? 3 : 1);
  std::vector<T> out(count);
  std::memcpy(out.data(), g.bin.data() + view.value("byteOffset", 0), count * sizeof(T));
  return out;
}

double linear(uint8_t s) {
  const double c = s / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(Gltf, LabelledMeshReadsBackWithItsVerticesTrianglesAndColours) {
  // A unit cube of quads (fan-triangulated on writing), faces labelled 0, 1 or 2.
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 0.1}};
  for (std::vector<uint32_t> f : std::vector<std::vector<uint32_t>>{
           {0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}})
    m.add_face(f);
  FaceLabels labels;
  labels.labels = {2, 0, 0, 1, 2, 2};
  labels.obj_groups = {"leaf_0", "leaf_1", "leaf_2"};
  labels.colours = {{255, 0, 0}, {10, 128, 200}, {0, 0, 0}};
  const auto dir = test::temp_dir("gltf");
  for (const char* name : {"m.glb", "m.gltf"}) {
    SCOPED_TRACE(name);
    write_mesh(dir / name, m, labels);
    const Gltf g = parse(dir / name);
    EXPECT_EQ(g.doc["asset"]["version"], "2.0");
    const json& primitives = g.doc["meshes"][0]["primitives"];
    ASSERT_EQ(primitives.size(), 3u);
    const std::vector<float> p = accessor<float>(g, primitives[0]["attributes"]["POSITION"]);
    ASSERT_EQ(p.size(), 24u);
    for (size_t v = 0; v < 8; ++v)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(p[3 * v + k], static_cast<float>(m.vertices[v][k]));
    for (uint32_t label = 0; label < 3; ++label) {
      const json& prim = primitives[label];
      std::vector<uint32_t> expected;
      for (size_t f = 0; f < m.face_count(); ++f) {
        if (labels.labels[f] != label) continue;
        const auto loop = m.face(f);
        for (size_t i = 1; i + 1 < loop.size(); ++i)
          expected.insert(expected.end(), {loop[0], loop[i], loop[i + 1]});
      }
      EXPECT_EQ(accessor<uint32_t>(g, prim["indices"]), expected) << label;
      const json& material = g.doc["materials"][prim["material"].get<int>()];
      EXPECT_EQ(material["name"], labels.obj_groups[label]);
      const json& factor = material["pbrMetallicRoughness"]["baseColorFactor"];
      for (int k = 0; k < 3; ++k)
        EXPECT_DOUBLE_EQ(factor[k].get<double>(), linear(labels.colours[label][k]));
    }
  }
  // Unlabelled: one primitive; labels out of range and a bad extension are InputErrors.
  write_mesh(dir / "plain.glb", m);
  EXPECT_EQ(parse(dir / "plain.glb").doc["meshes"][0]["primitives"].size(), 1u);
  EXPECT_THROW(write_mesh(dir / "m.gltf2", m), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover
