// Point-cloud files (point_set_io.h).

#include "cover/io/point_set_io.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "cover/io/mesh_io.h"
#include "cover/io/npy.h"
#include "cover/io/parse.h"
#include "cover/solid/errors.h"

namespace cover {
namespace {

using detail::fail_file;
using detail::fail_line;
using detail::parse_coordinate;

std::string lower_ext(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

PointCloud parse_text(std::string_view data, const std::string& file) {
  PointCloud out;
  if (data.starts_with("\xEF\xBB\xBF")) data.remove_prefix(3);
  uint64_t line_no = 0;
  size_t columns = 0;
  double v[6];
  while (!data.empty()) {
    ++line_no;
    const size_t eol = data.find('\n');
    std::string_view line = data.substr(0, eol);
    data.remove_prefix(eol == std::string_view::npos ? data.size() : eol + 1);
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    size_t count = 0;
    size_t at = 0;
    while (at < line.size()) {
      while (at < line.size() &&
             (line[at] == ' ' || line[at] == '\t' || line[at] == ',' || line[at] == '\r'))
        ++at;
      if (at >= line.size()) break;
      size_t end = at;
      while (end < line.size() && line[end] != ' ' && line[end] != '\t' && line[end] != ',' &&
             line[end] != '\r')
        ++end;
      if (count == 6) fail_line(file, line_no, "expected 3 or 6 numbers (x y z [nx ny nz])");
      v[count] = parse_coordinate(line.substr(at, end - at), file, line_no, "xyzxyz"[count]);
      ++count;
      at = end;
    }
    if (count == 0) continue;
    if (count != 3 && count != 6)
      fail_line(file, line_no,
                "expected 3 or 6 numbers (x y z [nx ny nz]), got " + std::to_string(count));
    if (columns == 0) columns = count;
    if (count != columns)
      fail_line(file, line_no,
                "expected " + std::to_string(columns) +
                    " numbers as on the first point's line, got " + std::to_string(count));
    out.points.push_back({v[0], v[1], v[2]});
    if (count == 6) out.normals.push_back({v[3], v[4], v[5]});
  }
  return out;
}

PointCloud parse_npy(std::string_view data, const std::string& file) {
  const NpyHeader h = parse_npy_header(data, file);
  const bool f8 = h.descr == "<f8" || h.descr == ">f8", f4 = h.descr == "<f4" || h.descr == ">f4";
  if (!f8 && !f4) fail_file(file, "expected dtype float64 or float32, got '" + h.descr + "'");
  if (h.shape.size() != 2 || (h.shape[1] != 3 && h.shape[1] != 6))
    fail_file(file, "expected shape (N, 3) or (N, 6)");
  if (h.fortran_order) fail_file(file, "expected C order (fortran_order False)");
  const size_t n = h.shape[0], cols = h.shape[1], size = f8 ? 8 : 4;
  if (data.size() - h.data_offset != n * cols * size)
    fail_file(file, "the data does not fill the declared shape");
  const bool swap = h.descr[0] == '>';
  auto value = [&](size_t i) {
    unsigned char b[8];
    std::memcpy(b, data.data() + h.data_offset + i * size, size);
    if (swap) std::reverse(b, b + size);
    if (f8) {
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
    float f;
    std::memcpy(&f, b, 4);
    return static_cast<double>(f);
  };
  PointCloud out;
  out.points.resize(n);
  if (cols == 6) out.normals.resize(n);
  for (size_t i = 0; i < n; ++i) {
    double v[6];
    for (size_t c = 0; c < cols; ++c) {
      v[c] = value(i * cols + c);
      if (!std::isfinite(v[c]))
        fail_file(file, "point " + std::to_string(i) + " (counting from 0): not finite");
    }
    out.points[i] = {v[0], v[1], v[2]};
    if (cols == 6) out.normals[i] = {v[3], v[4], v[5]};
  }
  return out;
}

}  // namespace

PointCloud read_point_cloud(const std::filesystem::path& path, uint64_t max_file_bytes) {
  const std::string ext = lower_ext(path), file = path.string();
  if (ext == ".ply" || ext == ".off" || ext == ".obj" || ext == ".stl") {
    PointCloud out;
    out.points = read_mesh(path, max_file_bytes).vertices;
    return out;
  }
  if (ext != ".xyz" && ext != ".txt" && ext != ".pts" && ext != ".csv" && ext != ".npy")
    throw InputError(file + ": unsupported point-cloud format '" + ext +
                     "' (expected .xyz, .txt, .pts, .csv, .npy, or a mesh's vertices: .ply, "
                     ".off, .obj, .stl)");
  const FileBytes bytes = read_regular_file(path, max_file_bytes);
  return ext == ".npy" ? parse_npy(bytes.view(), file) : parse_text(bytes.view(), file);
}

}  // namespace cover
