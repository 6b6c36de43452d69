#pragma once
// NumPy ⇄ C++ conversions and the call discipline of the Python bindings (module.cpp).
//
// Inputs: a float64, C-contiguous (n, 3) array is viewed in place as std::span<const Vec3> (Vec3
// is three doubles, 24 bytes); any other array-like (lists, float32, Fortran order, strided
// views) is converted once by NumPy. A wrong shape raises ValueError naming the argument and
// the shape it got. Outputs are NumPy arrays allocated with the GIL held and filled without it.
//
// Kernels run in a KernelScope: the GIL is released, the worker threads are limited to the
// caller's `threads` for that call alone (a TBB task arena; None or 0: all cores), and
// Interrupt::poll() re-acquires the GIL at most every 50 ms to run Python's signal handlers, so
// Ctrl-C raises KeyboardInterrupt between batches (py::error_already_set thrown through the
// kernel).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cover/solid/parallel.h"
#include "cover/solid/polygon_mesh.h"
#include "cover/solid/types.h"
#include "cover/solid/voxel_bounds.h"

namespace cover::python {

namespace py = pybind11;

static_assert(sizeof(Vec3) == 3 * sizeof(double) && alignof(Vec3) == alignof(double),
              "Vec3 must be three packed doubles to view (n, 3) float64 arrays in place");

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// An (n, 3) float64 C-contiguous array (the caller's own when it already is one) and its view.
struct Points {
  DoubleArray array;
  std::span<const Vec3> span() const {
    return {reinterpret_cast<const Vec3*>(array.data()), static_cast<size_t>(array.shape(0))};
  }
};

/// `obj` as (n, 3) float64 points. \throws ValueError "NAME: expected an array of shape (n, 3),
/// got shape (...)", TypeError for a non-numeric dtype.
Points points_arg(py::handle obj, const std::string& name);

/// Exactly `count` finite-or-not doubles from a sequence or array (a point, a plane, bounds).
/// \throws ValueError "NAME: expected K numbers, got shape (...)".
std::vector<double> numbers_arg(py::handle obj, const std::string& name, size_t count);
Vec3 vec3_arg(py::handle obj, const std::string& name);

/// (m, 3) integer triangles as uint32 vertex indices, each checked against `vertices`.
/// \throws ValueError for a wrong shape, TypeError for a non-integer dtype, cover::InputError for
/// an index outside [0, vertices) (as cover::mesh words it).
std::vector<std::array<uint32_t, 3>> triangles_arg(py::handle obj, size_t vertices);

/// Polygon faces into `mesh` (its face lists; `mesh.vertices` already set): an (m, k) integer
/// array, every face of k vertices, or a sequence of integer sequences, faces of mixed degrees.
/// \throws ValueError for a wrong shape, TypeError for non-integers, cover::InputError for an
/// index outside [0, vertices) ("F: face 3: vertex index 9 out of range (8 vertices)").
void faces_arg(py::handle obj, PolygonMesh& mesh);

/// The faces of `mesh` as int64 (m, k) when every face has k vertices (an empty mesh: (0, 3)),
/// else a list of lists of int, one per face.
py::object faces_object(const PolygonMesh& mesh);

/// The worker-thread count of a `threads=` argument (None or 0: all cores). \throws ValueError
/// for a negative count.
int thread_count(const std::optional<int>& threads);

/// Releases the GIL for its lifetime; run() applies the call's thread limit.
class KernelScope {
 public:
  explicit KernelScope(const std::optional<int>& threads)
      : count_(thread_count(threads)), release_() {}

  /// Runs `f` (the kernel) with this call's thread limit: in a task arena of that many threads
  /// (at most the machine's cores), so the limit binds this call only and calls from other
  /// Python threads with their own limits run at the same time; 0: the default arena, all cores.
  /// The calling thread joins the arena and runs `f` itself (Interrupt's caller check).
  template <class F>
  auto run(F&& f) {
    if (count_ <= 0) return f();
    tbb::task_arena arena(std::min(count_, tbb::info::default_concurrency()));
    return arena.execute(std::forward<F>(f));
  }

 private:
  int count_;
  py::gil_scoped_release release_;
};

/// Runs Python's signal handlers (with the GIL) at most every 50 ms; a handler that raises
/// (SIGINT: KeyboardInterrupt) becomes py::error_already_set, thrown to stop the kernel.
/// Call only on the thread that released the GIL.
class Interrupt {
 public:
  void poll(bool force = false);

 private:
  std::thread::id caller_ = std::this_thread::get_id();
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/// A `bounds=` argument: None, or (xmin, ymin, zmin, size) finite with size > 0 (InputError).
std::optional<VoxelBounds> bounds_arg(const py::object& bounds);

/// Vertices as float64 (n, 3).
py::array_t<double> vertices_array(const std::vector<Vec3>& vertices);

/// Faces as int64 (m, 3) triangles: a triangle as it is, any other face by triangulate_face
/// (mesh/triangulate.h: exact; a convex face as a fan from its first vertex; orientation kept,
/// so outward triangles stay outward).
py::array_t<int64_t> triangles_array(const PolygonMesh& mesh);

/// A copy of `values` as a NumPy array of the given shape.
template <class T>
py::array_t<T> copy_array(std::span<const T> values, std::vector<py::ssize_t> shape) {
  py::array_t<T> out(shape);
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

}  // namespace cover::python
