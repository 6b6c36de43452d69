// 3MF mesh output (the 3D Manufacturing Format) through lib3mf 1.8 (Debian lib3mf-dev), its C
// interface. Conventions:
//   - one mesh object holding the whole mesh (a printable solid stays one closed object), one
//     build item; float positions (3MF's), fan-triangulated faces; the model unit is 3MF's
//     default, the millimetre;
//   - with FaceLabels: one base-material group with a material per label value, named
//     obj_groups[label] (or "label_N") and coloured colours[label] (grey without one), and each
//     triangle's property set to its face's label (3MF's per-triangle base materials, which
//     slicers show as colours).
#include <NMR_DLLInterfaces.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cover/io/detail/threemf.h"
#include "cover/io/parse.h"

namespace cover::detail {

namespace {

using namespace NMR;

/// Releases a lib3mf handle at the end of its scope.
struct Handle {
  PLib3MFBase* p = nullptr;
  ~Handle() {
    if (p) lib3mf_release(p);
  }
};

void check(LIB3MFRESULT r, const std::string& file, const char* step) {
  if (r != LIB3MF_OK) fail_file(file, std::string("cannot write: lib3mf failed to ") + step);
}

/// A UUID (version 4 layout) from 64-bit FNV-1a hashes of the geometry and `salt`, so the same
/// mesh gives the same package bytes (lib3mf would otherwise draw random UUIDs).
std::string content_uuid(const std::vector<MODELMESHVERTEX>& v,
                         const std::vector<MODELMESHTRIANGLE>& t, uint64_t salt) {
  const auto fnv = [](const void* data, size_t n, uint64_t h) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
  };
  uint64_t a = fnv(v.data(), v.size() * sizeof(v[0]), 0xcbf29ce484222325ull ^ salt);
  uint64_t b = fnv(t.data(), t.size() * sizeof(t[0]), a ^ 0x9e3779b97f4a7c15ull);
  a = (a & ~0xF000ull) | 0x4000ull;                         // version 4
  b = (b & 0x3FFFFFFFFFFFFFFFull) | 0x8000000000000000ull;  // variant 10
  char text[37];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xFFFF), static_cast<unsigned>(a & 0xFFFF),
                static_cast<unsigned>(b >> 48),
                static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

}  // namespace

std::string threemf_bytes(const std::string& file, const PolygonMesh& mesh,
                          const FaceLabels* labels) {
  Handle model, object, writer, builditem, materials, properties, defaults;
  check(lib3mf_createmodel(&model.p), file, "create a model");
  check(lib3mf_model_addmeshobject(model.p, &object.p), file, "add the mesh object");
  check(lib3mf_object_setnameutf8(object.p, "cover"), file, "name the object");
  std::vector<MODELMESHVERTEX> vertices(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int k = 0; k < 3; ++k)
      vertices[v].m_fPosition[k] = static_cast<float>(mesh.vertices[v][k]);
  std::vector<MODELMESHTRIANGLE> triangles;
  std::vector<uint32_t> triangle_label;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      triangles.push_back({{loop[0], loop[i], loop[i + 1]}});
      if (labels) triangle_label.push_back(labels->labels[f]);
    }
  }
  if (vertices.size() > 0xFFFFFFFFu || triangles.size() > 0xFFFFFFFFu)
    fail_file(file, "cannot write: more than 2^32-1 3MF vertices or triangles");
  check(
      lib3mf_meshobject_setgeometry(object.p, vertices.data(), static_cast<DWORD>(vertices.size()),
                                    triangles.data(), static_cast<DWORD>(triangles.size())),
      file, "set the geometry");
  if (labels && !triangles.empty()) {
    check(lib3mf_model_addbasematerialgroup(model.p, &materials.p), file, "add materials");
    DWORD group = 0;
    check(lib3mf_resource_getresourceid(materials.p, &group), file, "read the material group id");
    uint32_t largest = 0;
    for (uint32_t l : triangle_label) largest = std::max(largest, l);
    std::vector<DWORD> index(largest + 1, 0);
    for (uint32_t l = 0; l <= largest; ++l) {
      const std::string name =
          l < labels->obj_groups.size() ? labels->obj_groups[l] : "label_" + std::to_string(l);
      const std::array<uint8_t, 3> c =
          l < labels->colours.size() ? labels->colours[l] : std::array<uint8_t, 3>{200, 200, 200};
      check(lib3mf_basematerial_addmaterialutf8(materials.p, name.c_str(), c[0], c[1], c[2],
                                                &index[l]),
            file, "add a material");
      // Opaque: lib3mf 1.8's addmaterial writes alpha 0 (#RRGGBB00, transparent).
      check(lib3mf_basematerial_setdisplaycolorrgba(materials.p, index[l], c[0], c[1], c[2], 255),
            file, "colour a material");
    }
    check(lib3mf_meshobject_createpropertyhandler(object.p, &properties.p), file,
          "create the property handler");
    std::vector<ModelResourceID> groups(triangles.size(), group);
    std::vector<DWORD> material(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) material[t] = index[triangle_label[t]];
    check(lib3mf_propertyhandler_setbasematerialarray(properties.p, groups.data(), material.data()),
          file, "set the triangles' materials");
    // 3MF requires an object-level default property beside triangle properties: the first
    // triangle's material.
    check(lib3mf_object_createdefaultpropertyhandler(object.p, &defaults.p), file,
          "create the default property handler");
    check(lib3mf_defaultpropertyhandler_setbasematerial(defaults.p, group, material[0]), file,
          "set the default material");
  }
  check(lib3mf_model_addbuilditem(model.p, object.p, nullptr, &builditem.p), file,
        "add the build item");
  check(lib3mf_object_setuuidutf8(object.p, content_uuid(vertices, triangles, 1).c_str()), file,
        "set the object's UUID");
  check(lib3mf_builditem_setuuidutf8(builditem.p, content_uuid(vertices, triangles, 2).c_str()),
        file, "set the build item's UUID");
  check(lib3mf_model_setbuilduuidutf8(model.p, content_uuid(vertices, triangles, 3).c_str()), file,
        "set the build's UUID");
  check(lib3mf_model_querywriter(model.p, "3mf", &writer.p), file, "create the writer");
  ULONG64 size = 0;
  if (lib3mf_writer_getstreamsize(writer.p, &size) != LIB3MF_OK) {
    DWORD code = 0;
    LPCSTR message = nullptr;
    lib3mf_getlasterror(writer.p, &code, &message);
    fail_file(file, std::string("cannot write: lib3mf: ") + (message ? message : "error") + " (" +
                        std::to_string(code) + ")");
  }
  std::string bytes(size, '\0');
  check(lib3mf_writer_writetobuffer(writer.p, reinterpret_cast<BYTE*>(bytes.data()), size), file,
        "write the package");
  return bytes;
}

}  // namespace cover::detail
