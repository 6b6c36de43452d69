#include "arrays.h"

#include <algorithm>
#include <cmath>

#include "cover/mesh/triangulate.h"
#include "cover/solid/errors.h"

namespace cover::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// `obj` as a NumPy array (no copy for an array), or TypeError naming the argument.
py::array any_array(py::handle obj, const std::string& name) {
  py::array a = py::array::ensure(obj);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(name + ": expected an array-like of numbers");
  }
  return a;
}

void check_numeric(const py::array& a, const std::string& name, const char* kinds) {
  const char kind = a.dtype().kind();
  if (std::string(kinds).find(kind) == std::string::npos)
    throw py::type_error(name + ": expected " +
                         (std::string(kinds) == "iu" ? "integers" : "numbers") + ", got dtype " +
                         std::string(py::str(a.dtype())));
}

}  // namespace

Points points_arg(py::handle obj, const std::string& name) {
  py::array a = any_array(obj, name);
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(name + ": expected an array of shape (n, 3), got shape " + shape_text(a));
  check_numeric(a, name, "fiu");
  return Points{DoubleArray::ensure(a)};
}

std::vector<double> numbers_arg(py::handle obj, const std::string& name, size_t count) {
  py::array a = any_array(obj, name);
  if (a.ndim() != 1 || static_cast<size_t>(a.shape(0)) != count)
    throw py::value_error(name + ": expected " + std::to_string(count) + " numbers, got shape " +
                          shape_text(a));
  check_numeric(a, name, "fiu");
  const DoubleArray d = DoubleArray::ensure(a);
  return std::vector<double>(d.data(), d.data() + count);
}

Vec3 vec3_arg(py::handle obj, const std::string& name) {
  const std::vector<double> v = numbers_arg(obj, name, 3);
  return {v[0], v[1], v[2]};
}

std::vector<std::array<uint32_t, 3>> triangles_arg(py::handle obj, size_t vertices) {
  py::array a = any_array(obj, "F");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error("F: expected an array of shape (m, 3), got shape " + shape_text(a));
  if (a.size() > 0) check_numeric(a, "F", "iu");
  const auto f = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  const int64_t* idx = f.data();
  const size_t m = static_cast<size_t>(f.shape(0));
  std::vector<std::array<uint32_t, 3>> out(m);
  for (size_t t = 0; t < m; ++t)
    for (int c = 0; c < 3; ++c) {
      const int64_t v = idx[3 * t + c];
      if (v < 0 || static_cast<uint64_t>(v) >= vertices)
        throw InputError("mesh: triangle " + std::to_string(t) + ": vertex index " +
                         std::to_string(v) + " out of range (" + std::to_string(vertices) +
                         " vertices)");
      out[t][c] = static_cast<uint32_t>(v);
    }
  return out;
}

namespace {

/// Appends `m` faces of `k` vertices each, the integer array `a` in C order, to `mesh`.
void append_faces(const py::array& a, size_t m, size_t k, PolygonMesh& mesh) {
  if (a.size() > 0) check_numeric(a, "F", "iu");
  const auto f = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  const int64_t* idx = f.data();
  const size_t vertices = mesh.vertices.size();
  for (size_t i = 0; i < m * k; ++i)
    if (idx[i] < 0 || static_cast<uint64_t>(idx[i]) >= vertices)
      throw InputError("F: face " + std::to_string(mesh.face_count() + i / k) + ": vertex index " +
                       std::to_string(idx[i]) + " out of range (" + std::to_string(vertices) +
                       " vertices)");
  mesh.face_vertices.insert(mesh.face_vertices.end(), idx, idx + m * k);
  for (size_t i = 0; i < m; ++i)
    mesh.face_start.push_back(mesh.face_start.back() + static_cast<uint32_t>(k));
}

}  // namespace

void faces_arg(py::handle obj, PolygonMesh& mesh) {
  if (!py::isinstance<py::array>(obj)) {
    // A list of equal-length index lists reads as one array; a ragged one face by face.
    py::array a = py::array::ensure(obj);
    if (!a) PyErr_Clear();
    if (!a || a.ndim() != 2 || std::string("iu").find(a.dtype().kind()) == std::string::npos) {
      if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj))
        throw py::type_error("F: expected an (m, k) integer array or a list of index lists");
      const py::sequence faces = py::reinterpret_borrow<py::sequence>(obj);
      for (size_t i = 0; i < faces.size(); ++i) {
        const std::string name = "F[" + std::to_string(i) + "]";
        py::array face = any_array(faces[i], name);
        if (face.ndim() != 1)
          throw py::value_error(name + ": expected a list of vertex indices, got shape " +
                                shape_text(face));
        append_faces(face, 1, static_cast<size_t>(face.shape(0)), mesh);
      }
      return;
    }
    obj = a;
  }
  py::array a = any_array(obj, "F");
  if (a.ndim() != 2)
    throw py::value_error("F: expected an array of shape (m, k), got shape " + shape_text(a));
  append_faces(a, static_cast<size_t>(a.shape(0)), static_cast<size_t>(a.shape(1)), mesh);
}

py::object faces_object(const PolygonMesh& mesh) {
  const size_t m = mesh.face_count();
  const size_t k = m == 0 ? 3 : mesh.face(0).size();
  bool uniform = true;
  for (size_t f = 0; f < m && uniform; ++f) uniform = mesh.face(f).size() == k;
  if (uniform) {
    py::array_t<int64_t> out({static_cast<py::ssize_t>(m), static_cast<py::ssize_t>(k)});
    std::copy(mesh.face_vertices.begin(), mesh.face_vertices.end(), out.mutable_data());
    return out;
  }
  py::list out(m);
  for (size_t f = 0; f < m; ++f) {
    const auto face = mesh.face(f);
    py::list l(face.size());
    for (size_t c = 0; c < face.size(); ++c) l[c] = py::int_(face[c]);
    out[f] = std::move(l);
  }
  return out;
}

int thread_count(const std::optional<int>& threads) {
  if (!threads) return 0;
  if (*threads < 0)
    throw py::value_error("threads: expected None, 0 (all cores) or a positive count, got " +
                          std::to_string(*threads));
  return *threads;
}

void Interrupt::poll(bool force) {
  if (std::this_thread::get_id() != caller_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_ < std::chrono::milliseconds(50)) return;
  last_ = now;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

py::array_t<double> vertices_array(const std::vector<Vec3>& vertices) {
  py::array_t<double> out({static_cast<py::ssize_t>(vertices.size()), py::ssize_t{3}});
  std::copy(vertices.begin(), vertices.end(), reinterpret_cast<Vec3*>(out.mutable_data()));
  return out;
}

py::array_t<int64_t> triangles_array(const PolygonMesh& mesh) {
  // The project's one face triangulation (mesh/triangulate.h: exact, fans for convex faces).
  std::vector<std::array<uint32_t, 3>> tris;
  tris.reserve(mesh.face_count());
  const std::span<const Vec3> points(mesh.vertices.data(), mesh.vertices.size());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    if (face.size() == 3) {
      tris.push_back({face[0], face[1], face[2]});
    } else if (face.size() > 3 && triangulate_face(points, face, tris) == FaceTiling::kCrossing) {
      throw InternalError("triangles_array: face " + std::to_string(f) + " crosses itself");
    }
  }
  py::array_t<int64_t> out({static_cast<py::ssize_t>(tris.size()), py::ssize_t{3}});
  int64_t* o = out.mutable_data();
  for (size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) o[3 * t + k] = tris[t][k];
  return out;
}

std::optional<VoxelBounds> bounds_arg(const py::object& bounds) {
  if (bounds.is_none()) return std::nullopt;
  const std::vector<double> b = numbers_arg(bounds, "bounds", 4);
  if (!std::isfinite(b[0]) || !std::isfinite(b[1]) || !std::isfinite(b[2]) ||
      !std::isfinite(b[3]) || !(b[3] > 0))
    throw InputError("bounds: expected finite xmin,ymin,zmin and a size > 0");
  return VoxelBounds{{b[0], b[1], b[2]}, b[3]};
}

}  // namespace cover::python
