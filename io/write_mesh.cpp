// Mesh writers. The file is written through write_atomically (io/atomic_file.h: a temporary
// beside the target, renamed over it, or committed with the command's other outputs), so no
// reader ever sees a half-written mesh; on failure the temporary is removed.
//   .off  ASCII "OFF", V F 0, one vertex / face per line
//   .obj  ASCII v / f lines (1-based indices); with FaceLabels a "g NAME" line before each run of
//         faces with one label
//   .ply  binary_little_endian, double x y z, "list uchar int vertex_indices" (uint count when a
//         face has more than 255 vertices, uint items when there are more than 2^31-1 vertices);
//         with FaceLabels then "int NAME" per face
//   .stl  binary; polygons are fan-triangulated (v0, vi, vi+1) and coordinates rounded to float,
//         so an STL round trip is exact only for float-representable coordinates
//   .gltf, .glb  glTF 2.0 (io/write_gltf.cpp): float positions, fan-triangulated, a material per
//         face label
//   .3mf  3MF (io/write_3mf.cpp): one object, float positions, fan-triangulated, a base
//         material per face label
// Numbers are written with std::to_chars' shortest round-trip form, so .off/.obj/.ply round trips
// reproduce every double exactly. Vertex and face lines are formatted in parallel chunks and
// written in order (the same bytes as one by one): formatting, not the file system, took most of
// a write (a 30k-face OFF: 6 ms serial, cheese ∪ fandisk in bench/evaluate_vs_manifold).

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

#include "cover/io/atomic_file.h"
#include "cover/io/detail/gltf.h"
#include "cover/io/detail/threemf.h"
#include "cover/io/mesh_io.h"
#include "cover/io/parse.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

/// Appends a number's shortest round-trip text (doubles) or its decimal digits (integers).
void append_number(std::string& s, double value) {
  char digits[32];
  auto result = std::to_chars(digits, digits + sizeof digits, value);
  s.append(digits, static_cast<size_t>(result.ptr - digits));
}
void append_number(std::string& s, uint64_t value) {
  char digits[24];
  auto result = std::to_chars(digits, digits + sizeof digits, value);
  s.append(digits, static_cast<size_t>(result.ptr - digits));
}

/// Buffered writer to a FILE*; throws InputError naming the target on a failed write.
class Output {
 public:
  Output(std::FILE* stream, const std::string& file) : stream_(stream), file_(file) {}

  void text(std::string_view s) {
    buffer_.append(s);
    if (buffer_.size() >= kFlushBytes) flush();
  }
  void number(double value) { append_number(buffer_, value); }
  void number(uint64_t value) { append_number(buffer_, value); }
  /// format(i, s) appends the text of item i to s, for i in [0, n): chunks of items formatted in
  /// parallel, a block of chunks at a time (bounded memory), appended in item order.
  template <class Format>
  void items(size_t n, Format&& format) {
    constexpr size_t kGrain = 2048, kBlockChunks = 64;
    std::vector<std::string> chunk(kBlockChunks);
    for (size_t b0 = 0; b0 < n; b0 += kGrain * kBlockChunks) {
      const size_t m = std::min(n - b0, kGrain * kBlockChunks);
      parallel_for(m, kGrain, [&](size_t begin, size_t end) {
        std::string& s = chunk[begin / kGrain];
        s.clear();
        for (size_t i = b0 + begin; i < b0 + end; ++i) format(i, s);
      });
      for (size_t c = 0; c * kGrain < m; ++c) text(chunk[c]);
    }
  }
  /// Appends the little-endian bytes of an integer or floating-point value.
  template <typename T>
  void binary(T value) {
    using Bits = std::conditional_t<
        sizeof(T) == 1, uint8_t,
        std::conditional_t<sizeof(T) == 2, uint16_t,
                           std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
    auto bits = std::bit_cast<Bits>(value);
    char bytes[sizeof bits];
    for (size_t i = 0; i < sizeof bits; ++i) bytes[i] = static_cast<char>(bits >> (8 * i));
    text({bytes, sizeof bytes});
  }
  void flush() {
    if (!buffer_.empty() &&
        std::fwrite(buffer_.data(), 1, buffer_.size(), stream_) != buffer_.size())
      detail::fail_file(file_, std::string("cannot write: ") + std::strerror(errno));
    buffer_.clear();
  }

 private:
  static constexpr size_t kFlushBytes = size_t{1} << 20;
  std::FILE* stream_;
  const std::string& file_;
  std::string buffer_;
};

/// Throws unless every face has >= 3 in-range indices and every vertex is finite.
void check_mesh(const std::string& file, const PolygonMesh& mesh) {
  if (mesh.face_start.empty() || mesh.face_start.front() != 0 ||
      mesh.face_start.back() != mesh.face_vertices.size())
    detail::fail_file(file, "cannot write: inconsistent face offsets");
  if (mesh.vertices.size() > detail::kMaxIndexCount)
    detail::fail_file(file, "cannot write: more than 2^32-1 vertices");
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Vec3& p = mesh.vertices[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      detail::fail_file(file, "cannot write: vertex " + std::to_string(v) + " is not finite");
  }
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (mesh.face_start[f + 1] < mesh.face_start[f] + 3)
      detail::fail_file(file,
                        "cannot write: face " + std::to_string(f) + " has fewer than 3 vertices");
    for (uint32_t v : mesh.face(f))
      if (v >= mesh.vertices.size())
        detail::fail_file(file, "cannot write: face " + std::to_string(f) + " references vertex " +
                                    std::to_string(v) + " of " +
                                    std::to_string(mesh.vertices.size()));
  }
}

void write_off(Output& out, const PolygonMesh& mesh) {
  out.text("OFF\n");
  out.number(uint64_t{mesh.vertices.size()});
  out.text(" ");
  out.number(uint64_t{mesh.face_count()});
  out.text(" 0\n");
  out.items(mesh.vertices.size(), [&](size_t v, std::string& s) {
    const Vec3& p = mesh.vertices[v];
    append_number(s, p.x), s += ' ', append_number(s, p.y), s += ' ', append_number(s, p.z);
    s += '\n';
  });
  out.items(mesh.face_count(), [&](size_t f, std::string& s) {
    append_number(s, uint64_t{mesh.face(f).size()});
    for (uint32_t v : mesh.face(f)) s += ' ', append_number(s, uint64_t{v});
    s += '\n';
  });
}

/// With `uvs` (2 per corner): a vt line per corner, in corner order, and `f v/t` references.
void write_obj(Output& out, const PolygonMesh& mesh, const FaceLabels* labels,
               const std::vector<double>* uvs = nullptr) {
  out.text("# written by Cover\n");
  out.items(mesh.vertices.size(), [&](size_t v, std::string& s) {
    const Vec3& p = mesh.vertices[v];
    s += "v ", append_number(s, p.x), s += ' ', append_number(s, p.y), s += ' ';
    append_number(s, p.z), s += '\n';
  });
  if (uvs)
    out.items(mesh.face_vertices.size(), [&](size_t c, std::string& s) {
      s += "vt ", append_number(s, (*uvs)[2 * c]), s += ' ', append_number(s, (*uvs)[2 * c + 1]);
      s += '\n';
    });
  out.items(mesh.face_count(), [&](size_t f, std::string& s) {
    if (labels && (f == 0 || labels->labels[f] != labels->labels[f - 1]))
      s += "g ", s += labels->obj_groups[labels->labels[f]], s += '\n';
    s += 'f';
    for (uint32_t c = mesh.face_start[f]; c < mesh.face_start[f + 1]; ++c) {
      s += ' ', append_number(s, uint64_t{mesh.face_vertices[c]} + 1);
      if (uvs) s += '/', append_number(s, uint64_t{c} + 1);
    }
    s += '\n';
  });
}

void write_ply(Output& out, const PolygonMesh& mesh, const FaceLabels* labels) {
  size_t largest = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) largest = std::max(largest, mesh.face(f).size());
  const bool wide_count = largest > 255;
  const bool wide_index = mesh.vertices.size() > 0x7FFFFFFFu;
  out.text("ply\nformat binary_little_endian 1.0\ncomment written by Cover\nelement vertex ");
  out.number(uint64_t{mesh.vertices.size()});
  out.text("\nproperty double x\nproperty double y\nproperty double z\nelement face ");
  out.number(uint64_t{mesh.face_count()});
  out.text(wide_count ? "\nproperty list uint " : "\nproperty list uchar ");
  out.text(wide_index ? "uint vertex_indices\n" : "int vertex_indices\n");
  if (labels) out.text("property int "), out.text(labels->ply_property), out.text("\n");
  out.text("end_header\n");
  for (const Vec3& p : mesh.vertices) out.binary(p.x), out.binary(p.y), out.binary(p.z);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    if (wide_count)
      out.binary(static_cast<uint32_t>(face.size()));
    else
      out.binary(static_cast<uint8_t>(face.size()));
    for (uint32_t v : face) out.binary(v);  // same bytes for int and uint (v < 2^31 for int)
    if (labels) out.binary(static_cast<int32_t>(labels->labels[f]));
  }
}

void write_stl(Output& out, const PolygonMesh& mesh, const std::string& file) {
  uint64_t triangles = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) triangles += mesh.face(f).size() - 2;
  if (triangles > 0xFFFFFFFFull)
    detail::fail_file(file, "cannot write: more than 2^32-1 STL triangles");
  std::string header = "binary STL written by Cover";
  header.resize(80, ' ');
  out.text(header);
  out.binary(static_cast<uint32_t>(triangles));
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    const Vec3 a = mesh.vertices[face[0]];
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3 b = mesh.vertices[face[i]], c = mesh.vertices[face[i + 1]];
      Vec3 normal = cross(b - a, c - a);
      const double length = std::sqrt(dot(normal, normal));
      normal = length > 0 ? (1 / length) * normal : Vec3{};
      for (const Vec3& p : {normal, a, b, c})
        out.binary(static_cast<float>(p.x)), out.binary(static_cast<float>(p.y)),
            out.binary(static_cast<float>(p.z));
      out.binary(uint16_t{0});
    }
  }
}

}  // namespace

static void write_mesh_labelled(const std::filesystem::path& path, const PolygonMesh& mesh,
                                const FaceLabels* labels, const std::vector<double>* uvs);

void write_mesh(const std::filesystem::path& path, const PolygonMesh& mesh) {
  write_mesh_labelled(path, mesh, nullptr, nullptr);
}

void write_mesh(const std::filesystem::path& path, const PolygonMesh& mesh,
                const FaceLabels& labels) {
  write_mesh_labelled(path, mesh, &labels, nullptr);
}

void write_mesh_with_uvs(const std::filesystem::path& path, const PolygonMesh& mesh,
                         const std::vector<double>& uvs) {
  write_mesh_labelled(path, mesh, nullptr, &uvs);
}

static void write_mesh_labelled(const std::filesystem::path& path, const PolygonMesh& mesh,
                                const FaceLabels* labels, const std::vector<double>* uvs) {
  const std::string file = path.string();
  const std::string ext = lower_extension(path);
  if (!is_mesh_output_extension(path))
    detail::fail_file(file, "unsupported mesh format '" + path.extension().string() +
                                "' (expected " + kMeshOutputFormats + ")");
  check_mesh(file, mesh);
  if (uvs) {
    if (ext != ".obj") detail::fail_file(file, "cannot carry texture coordinates (use .obj)");
    if (uvs->size() != 2 * mesh.face_vertices.size())
      detail::fail_file(file, "cannot write: " + std::to_string(uvs->size()) +
                                  " texture values for " +
                                  std::to_string(mesh.face_vertices.size()) + " corners");
    for (double u : *uvs)
      if (!std::isfinite(u)) detail::fail_file(file, "cannot write: a texture value is not finite");
  }
  if (labels) {
    if (ext != ".ply" && ext != ".obj" && ext != ".gltf" && ext != ".glb" && ext != ".3mf")
      detail::fail_file(file, "cannot carry face labels (use .ply, .obj, .gltf, .glb or .3mf)");
    if (labels->labels.size() != mesh.face_count())
      detail::fail_file(file, "cannot write: " + std::to_string(labels->labels.size()) +
                                  " face labels for " + std::to_string(mesh.face_count()) +
                                  " faces");
    for (uint32_t l : labels->labels)
      if (l > 0x7FFFFFFFu || (ext == ".obj" && l >= labels->obj_groups.size()))
        detail::fail_file(file, "cannot write: face label " + std::to_string(l) + " out of range");
  }
  // glTF and 3MF are serialized by their libraries first (errors before any file exists), then
  // written through the same Output as the other formats.
  const bool packaged = ext == ".gltf" || ext == ".glb" || ext == ".3mf";
  const std::string bytes = !packaged       ? std::string()
                            : ext == ".3mf" ? detail::threemf_bytes(file, mesh, labels)
                                            : detail::gltf_bytes(file, mesh, labels, ext == ".glb");
  write_atomically(
      path,
      [&](const std::filesystem::path& temporary) {
        std::FILE* stream = std::fopen(temporary.c_str(), "wb");
        if (stream == nullptr)
          detail::fail_file(file, std::string("cannot write: ") + std::strerror(errno));
        try {
          Output out(stream, file);
          if (packaged)
            out.text(bytes);
          else if (ext == ".off")
            write_off(out, mesh);
          else if (ext == ".obj")
            write_obj(out, mesh, labels, uvs);
          else if (ext == ".ply")
            write_ply(out, mesh, labels);
          else
            write_stl(out, mesh, file);
          out.flush();
        } catch (...) {
          std::fclose(stream);
          throw;
        }
        if (std::fclose(stream) != 0)
          detail::fail_file(file, std::string("cannot write: ") + std::strerror(errno));
        return true;
      },
      "the mesh");
}

}  // namespace cover
