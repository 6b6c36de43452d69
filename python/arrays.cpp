#include "python/arrays.h"

#include <algorithm>
#include <cmath>

#include "solid/errors.h"

namespace cover::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d)
    s += (d ? ", " : "") + std::to_string(a.shape(d));
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

py::array_t<double> vertices_array(const LargeVector<Vec3>& vertices) {
  py::array_t<double> out({static_cast<py::ssize_t>(vertices.size()), py::ssize_t{3}});
  std::copy(vertices.begin(), vertices.end(), reinterpret_cast<Vec3*>(out.mutable_data()));
  return out;
}

namespace {

using Tri = std::array<int64_t, 3>;

/// 2D cross product of (b − a) and (c − a).
double cross2(const std::array<double, 2>& a, const std::array<double, 2>& b,
              const std::array<double, 2>& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/// Appends the triangles of one polygon face (see triangles_array()).
void triangulate(std::span<const uint32_t> loop, const LargeVector<Vec3>& v, std::vector<Tri>& out) {
  const size_t n = loop.size();
  if (n < 3) return;
  if (n == 3) {
    out.push_back({loop[0], loop[1], loop[2]});
    return;
  }
  // Newell normal; project onto the plane of its two smaller components, counter-clockwise.
  Vec3 normal;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = v[loop[i]], b = v[loop[(i + 1) % n]];
    normal = normal + Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                           (a.x - b.x) * (a.y + b.y)};
  }
  const double ax = std::abs(normal.x), ay = std::abs(normal.y), az = std::abs(normal.z);
  const int k = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  const int u = (k + 1) % 3, w = (k + 2) % 3;
  const bool flip = normal[k] < 0;
  std::vector<std::array<double, 2>> p(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 q = v[loop[i]];
    p[i] = {q[u], flip ? -q[w] : q[w]};
  }
  bool convex = true;
  for (size_t i = 0; i < n && convex; ++i)
    convex = cross2(p[i], p[(i + 1) % n], p[(i + 2) % n]) >= 0;
  if (convex) {
    for (size_t i = 1; i + 1 < n; ++i) out.push_back({loop[0], loop[i], loop[i + 1]});
    return;
  }
  // Ear clipping: an ear is a convex corner whose triangle holds no other remaining corner.
  std::vector<size_t> rest(n);
  for (size_t i = 0; i < n; ++i) rest[i] = i;
  while (rest.size() > 3) {
    const size_t m = rest.size();
    size_t ear = m;
    for (size_t i = 0; i < m && ear == m; ++i) {
      const size_t a = rest[(i + m - 1) % m], b = rest[i], c = rest[(i + 1) % m];
      if (cross2(p[a], p[b], p[c]) <= 0) continue;
      bool empty = true;
      for (size_t j = 0; j < m && empty; ++j) {
        const size_t q = rest[j];
        if (q == a || q == b || q == c || loop[q] == loop[a] || loop[q] == loop[b] ||
            loop[q] == loop[c])
          continue;
        empty = !(cross2(p[a], p[b], p[q]) >= 0 && cross2(p[b], p[c], p[q]) >= 0 &&
                  cross2(p[c], p[a], p[q]) >= 0);
      }
      if (empty) ear = i;
    }
    if (ear == m) ear = 0;  // degenerate rings (collinear runs): cut any corner
    out.push_back({loop[rest[(ear + m - 1) % m]], loop[rest[ear]], loop[rest[(ear + 1) % m]]});
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  out.push_back({loop[rest[0]], loop[rest[1]], loop[rest[2]]});
}

}  // namespace

py::array_t<int64_t> triangles_array(const PolygonMesh& mesh) {
  std::vector<Tri> tris;
  tris.reserve(mesh.face_count());
  for (size_t f = 0; f < mesh.face_count(); ++f) triangulate(mesh.face(f), mesh.vertices, tris);
  py::array_t<int64_t> out({static_cast<py::ssize_t>(tris.size()), py::ssize_t{3}});
  std::copy(tris.begin(), tris.end(), reinterpret_cast<Tri*>(out.mutable_data()));
  return out;
}

}  // namespace cover::python
