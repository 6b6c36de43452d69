// OBJ reader (Wavefront, polygon geometry only). Line-based; '#' starts a comment:
//   v x y z [numbers]      vertex; trailing numbers (w, colour) are ignored
//   f r0 r1 r2 ...         face with >= 3 references; a reference is i, i/t, i//n or i/t/n where
//                          i is 1-based, or negative: relative to the last vertex defined so far
//   vt u [v [w]]           texture coordinate: read when the caller asks for texture coordinates
//                          (read_mesh_with_uvs: u and v per corner from the references' t;
//                          serial), else ignored like the statements below
//   vn vp g o s usemtl mtllib l p and the free-form curve/surface statements are ignored.
// Any other statement is an error (that is what binary garbage or a wrong format looks like).
// Positive indices may refer forward, so they are checked once the whole file is read; the
// message names the line where the largest index first appeared. A file of 1 MiB or more is
// read in parallel chunks of lines (read_obj_parallel), the same mesh as serially.

#include <algorithm>
#include <array>
#include <atomic>
#include <string>
#include <vector>

#include "cover/io/parse.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::detail {
namespace {

/// Files of at least this many bytes are read in parallel.
constexpr uint64_t kParallelBytes = uint64_t{1} << 20;

/// Statements that carry no polygon geometry.
constexpr std::array<std::string_view, 31> kIgnored = {
    "vt",   "vn",   "vp",     "g",        "o",        "s",      "usemtl", "mtllib",
    "l",    "p",    "cstype", "deg",      "bmat",     "step",   "curv",   "curv2",
    "surf", "parm", "trim",   "hole",     "scrv",     "sp",     "end",    "con",
    "mg",   "lod",  "bevel",  "c_interp", "d_interp", "usemap", "maplib"};

/// True for the tail of a reference after the vertex index: "", "/t", "//n", "/t/n".
bool is_reference_tail(std::string_view tail) {
  if (tail.empty()) return true;
  if (tail[0] != '/') return false;
  return std::all_of(tail.begin(), tail.end(),
                     [](char c) { return (c >= '0' && c <= '9') || c == '-' || c == '/'; });
}

/// What the statements of a run of lines add: vertices, faces, and the largest positive index.
struct ObjPart {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> face_vertices;
  std::vector<uint32_t> sizes;  ///< per face
  uint64_t max_index = 0;       ///< largest positive (1-based) index seen
  uint64_t max_index_line = 0;  ///< where it first appeared
  // Texture coordinates, when asked for:
  std::vector<double> vt;          ///< u, v per vt statement
  std::vector<int64_t> corner_vt;  ///< per corner: 0-based vt index, or -1 (none)
  uint64_t max_vt = 0, max_vt_line = 0;
  uint64_t corners_with_vt = 0, first_without_vt_line = 0, first_with_vt_line = 0;
};

/// The texture index of a reference's tail ("/t" or "/t/n"; 0-based, resolved against the `so_far`
/// vt statements for negative ones), or -1 when the tail names none ("", "//n").
int64_t texture_index(std::string_view tail, uint64_t so_far, const std::string& file, uint64_t n,
                      ObjPart& part) {
  if (tail.size() < 2 || tail[0] != '/' || tail[1] == '/') return -1;
  tail.remove_prefix(1);
  int64_t index = 0;
  const auto [ptr, ec] = std::from_chars(tail.data(), tail.data() + tail.size(), index);
  if (ec != std::errc() || (ptr != tail.data() + tail.size() && *ptr != '/'))
    fail_line(file, n, "expected a texture index, found " + quote(tail));
  if (index == 0) fail_line(file, n, "texture index 0 is invalid (OBJ indices start at 1)");
  if (index < 0) {
    const uint64_t back = 0 - static_cast<uint64_t>(index);
    if (back > so_far)
      fail_line(file, n,
                "relative texture index " + std::to_string(index) +
                    " reaches before the first vt (" + std::to_string(so_far) + " defined so far)");
    return static_cast<int64_t>(so_far - back);
  }
  if (static_cast<uint64_t>(index) > kMaxIndexCount)
    fail_line(file, n, "texture index " + std::to_string(index) + " exceeds 2^32-1");
  if (static_cast<uint64_t>(index) > part.max_vt) {
    part.max_vt = static_cast<uint64_t>(index);
    part.max_vt_line = n;
  }
  return index - 1;
}

/// Reads the lines of `data` (its first is line `first_line` of the file; 0: line numbers not
/// known) into `part`; `defined` counts the vertices of the file before `data`. \throws
/// InputError for any bad statement.
void read_obj_lines(const std::string& file, std::string_view data, uint64_t first_line,
                    uint64_t defined, ObjPart& part, bool texture = false) {
  LineReader lines(data);
  std::string_view line;
  while (lines.next(line)) {
    const uint64_t n = first_line == 0 ? 0 : first_line + lines.line_number() - 1;
    line = strip_comment(line);
    std::string_view keyword = next_token(line);
    if (keyword.empty()) continue;
    if (keyword == "v") {
      if (defined + part.vertices.size() >= kMaxIndexCount)
        fail_line(file, n, "more than 2^32-1 vertices");
      Vec3 p;
      p.x = parse_coordinate(next_token(line), file, n, 'x');
      p.y = parse_coordinate(next_token(line), file, n, 'y');
      p.z = parse_coordinate(next_token(line), file, n, 'z');
      check_numeric_tail(line, file, n);
      part.vertices.push_back(p);
    } else if (texture && keyword == "vt") {
      part.vt.push_back(parse_coordinate(next_token(line), file, n, 'u'));
      const std::string_view v = next_token(line);
      part.vt.push_back(v.empty() ? 0.0 : parse_coordinate(v, file, n, 'v'));
      check_numeric_tail(line, file, n);
    } else if (keyword == "f") {
      const size_t first = part.face_vertices.size();
      const uint64_t so_far = defined + part.vertices.size();
      for (std::string_view token = next_token(line); !token.empty(); token = next_token(line)) {
        int64_t index = 0;
        const char* end = token.data() + token.size();
        auto [ptr, ec] = std::from_chars(token.data(), end, index);
        if (ec != std::errc() || !is_reference_tail({ptr, static_cast<size_t>(end - ptr)}))
          fail_line(file, n, "expected a vertex reference, found " + quote(token));
        uint64_t resolved;
        if (index == 0) {
          fail_line(file, n, "vertex index 0 is invalid (OBJ indices start at 1)");
        } else if (index < 0) {
          const uint64_t back = 0 - static_cast<uint64_t>(index);
          if (back > so_far)
            fail_line(file, n,
                      "relative vertex index " + std::to_string(index) +
                          " reaches before the first vertex (" + std::to_string(so_far) +
                          " defined so far)");
          resolved = so_far - back;
        } else {
          const auto one_based = static_cast<uint64_t>(index);
          if (one_based > kMaxIndexCount)
            fail_line(file, n, "vertex index " + std::to_string(index) + " exceeds 2^32-1");
          if (one_based > part.max_index) {
            part.max_index = one_based;
            part.max_index_line = n;
          }
          resolved = one_based - 1;
        }
        part.face_vertices.push_back(static_cast<uint32_t>(resolved));
        if (texture) {
          const int64_t t = texture_index({ptr, static_cast<size_t>(end - ptr)}, part.vt.size() / 2,
                                          file, n, part);
          part.corner_vt.push_back(t);
          if (t >= 0) {
            if (part.corners_with_vt++ == 0) part.first_with_vt_line = n;
          } else if (part.first_without_vt_line == 0) {
            part.first_without_vt_line = n;
          }
        }
      }
      const size_t size = part.face_vertices.size() - first;
      if (size < 3)
        fail_line(file, n, "face with " + std::to_string(size) + " vertices (at least 3 needed)");
      if (part.face_vertices.size() > kMaxIndexCount)
        fail_line(file, n, "more than 2^32-1 face vertices in total");
      part.sizes.push_back(static_cast<uint32_t>(size));
    } else if (std::find(kIgnored.begin(), kIgnored.end(), keyword) == kIgnored.end()) {
      fail_line(file, n, "unknown OBJ statement " + quote(keyword));
    }
  }
}

/// How many vertex statements the lines of `data` hold (their keyword only).
uint64_t count_vertices(std::string_view data) {
  LineReader lines(data);
  std::string_view line;
  uint64_t count = 0;
  while (lines.next(line)) {
    line = strip_comment(line);
    count += next_token(line) == "v";
  }
  return count;
}

/// A file of kParallelBytes or more: chunks of whole lines, their vertex statements counted
/// first (a face's relative indices need the vertices before it), then each chunk read on its
/// own and the parts placed by prefix sums. Returns false on any error (the serial read then
/// reports it with its line number), so messages do not depend on this path.
bool read_obj_parallel(const std::string& file, std::string_view data, PolygonMesh& mesh) {
  const std::vector<std::string_view> pieces = line_chunks(data, size_t{1} << 18);
  const size_t chunks = pieces.size();
  std::vector<uint64_t> defined(chunks + 1, 0);
  parallel_for(chunks, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) defined[c + 1] = count_vertices(pieces[c]);
  });
  for (size_t c = 0; c < chunks; ++c) defined[c + 1] += defined[c];
  if (defined[chunks] >= kMaxIndexCount) return false;
  std::vector<ObjPart> parts(chunks);
  std::atomic<bool> failed{false};
  parallel_for(chunks, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end && !failed; ++c) {
      try {
        read_obj_lines(file, pieces[c], 0, defined[c], parts[c]);
      } catch (const InputError&) {
        failed = true;
      }
    }
  });
  if (failed) return false;
  uint64_t faces = 0, corners = 0, max_index = 0;
  for (const ObjPart& p : parts) {
    faces += p.sizes.size();
    corners += p.face_vertices.size();
    max_index = std::max(max_index, p.max_index);
  }
  if (faces == 0 || corners > kMaxIndexCount || max_index > defined[chunks]) return false;
  mesh.vertices.resize(defined[chunks]);
  mesh.face_vertices.resize(corners);
  mesh.face_start.resize(faces + 1);
  std::vector<uint64_t> face_at(chunks + 1, 0), corner_at(chunks + 1, 0);
  for (size_t c = 0; c < chunks; ++c) {
    face_at[c + 1] = face_at[c] + parts[c].sizes.size();
    corner_at[c + 1] = corner_at[c] + parts[c].face_vertices.size();
  }
  mesh.face_start[0] = 0;
  parallel_for(chunks, 1, [&](size_t begin, size_t end) {
    for (size_t c = begin; c < end; ++c) {
      const ObjPart& p = parts[c];
      std::copy(p.vertices.begin(), p.vertices.end(), mesh.vertices.begin() + defined[c]);
      std::copy(p.face_vertices.begin(), p.face_vertices.end(),
                mesh.face_vertices.begin() + corner_at[c]);
      uint64_t at = corner_at[c];
      for (size_t f = 0; f < p.sizes.size(); ++f) {
        at += p.sizes[f];
        mesh.face_start[face_at[c] + f + 1] = static_cast<uint32_t>(at);
      }
    }
  });
  return true;
}

}  // namespace

PolygonMesh read_obj(const std::string& file, std::string_view data, std::vector<double>* uvs) {
  data = without_bom(data);
  // A large file is read in parallel (read_obj_parallel); any error there: read serially below.
  if (uvs == nullptr && data.size() >= kParallelBytes) {
    PolygonMesh mesh;
    if (read_obj_parallel(file, data, mesh)) return mesh;
  }
  ObjPart part;
  read_obj_lines(file, data, 1, 0, part, uvs != nullptr);
  if (part.sizes.empty()) fail_file(file, "no faces");
  if (part.max_index > part.vertices.size())
    fail_line(file, part.max_index_line,
              "vertex index " + std::to_string(part.max_index) + " out of range (the file has " +
                  std::to_string(part.vertices.size()) + " vertices)");
  if (uvs) {
    uvs->clear();
    if (part.max_vt > part.vt.size() / 2)
      fail_line(file, part.max_vt_line,
                "texture index " + std::to_string(part.max_vt) + " out of range (the file has " +
                    std::to_string(part.vt.size() / 2) + " vt lines)");
    if (part.corners_with_vt > 0 && part.corners_with_vt < part.corner_vt.size())
      fail_line(file, part.first_without_vt_line,
                "a face corner without a texture index, although the face on line " +
                    std::to_string(part.first_with_vt_line) + " has them");
    if (part.corners_with_vt > 0) {
      uvs->resize(2 * part.corner_vt.size());
      for (size_t c = 0; c < part.corner_vt.size(); ++c) {
        (*uvs)[2 * c] = part.vt[2 * static_cast<size_t>(part.corner_vt[c])];
        (*uvs)[2 * c + 1] = part.vt[2 * static_cast<size_t>(part.corner_vt[c]) + 1];
      }
    }
  }
  PolygonMesh mesh;
  mesh.vertices.assign(part.vertices.begin(), part.vertices.end());
  mesh.face_vertices.assign(part.face_vertices.begin(), part.face_vertices.end());
  mesh.face_start.resize(part.sizes.size() + 1);
  mesh.face_start[0] = 0;
  for (size_t f = 0; f < part.sizes.size(); ++f)
    mesh.face_start[f + 1] = mesh.face_start[f] + part.sizes[f];
  return mesh;
}

}  // namespace cover::detail
