// Octrees and voxel files for Python (docs/python.md): Model.octree (the direct octree of
// octree/octree.h, as `cover octree`) returning cover.Octree, whose arrays view its nodes and
// whose save() writes .htg, .bt or .json as the CLI does; cover.write_voxels writes a bool grid
// with its bounds in the CLI's voxel formats (.binvox, .vti, .npy, .raw with its sidecar, .vdb),
// atomically.
#include "grids.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cctype>
#include <filesystem>
#include <optional>
#include <string>

#include "arrays.h"
#include "cover/io/octree_io.h"
#include "cover/io/vdb_io.h"
#include "cover/io/voxel_io.h"
#include "cover/octree/octree.h"
#include "cover/solid/errors.h"
#include "cover/voxel/voxelize.h"
#include "docstrings.h"

namespace py = pybind11;

namespace cover::python {
namespace {

using Threads = std::optional<int>;

template <class T, class F>
py::array_t<T> node_array(const Octree& tree, F&& field) {
  py::array_t<T> out(static_cast<py::ssize_t>(tree.nodes.size()));
  T* dst = out.mutable_data();
  for (size_t i = 0; i < tree.nodes.size(); ++i) dst[i] = field(tree.nodes[i]);
  return out;
}

}  // namespace

void bind_grids(py::module_& m, py::class_<Model>& model) {
  py::class_<Octree>(m, "Octree", doc::kOctree)
      .def_property_readonly("depth", [](const Octree& t) { return t.depth; })
      .def_property_readonly("bounds",
                             [](const Octree& t) {
                               return py::make_tuple(t.bounds.min.x, t.bounds.min.y, t.bounds.min.z,
                                                     t.bounds.size);
                             })
      .def_property_readonly("first_child",
                             [](const Octree& t) {
                               return node_array<uint32_t>(
                                   t, [](const Octree::Node& n) { return n.first_child; });
                             })
      .def_property_readonly("level",
                             [](const Octree& t) {
                               return node_array<uint8_t>(
                                   t, [](const Octree::Node& n) { return n.depth; });
                             })
      .def_property_readonly("state",
                             [](const Octree& t) {
                               return node_array<uint8_t>(t, [](const Octree::Node& n) {
                                 return static_cast<uint8_t>(n.state);
                               });
                             })
      .def_property_readonly("occupancy",
                             [](const Octree& t) {
                               return node_array<float>(
                                   t, [](const Octree::Node& n) { return n.occupancy; });
                             })
      .def_property_readonly("leaf_counts",
                             [](const Octree& t) {
                               const auto c = t.leaf_counts();
                               return py::dict(py::arg("empty") = c[0], py::arg("full") = c[1],
                                               py::arg("partial") = c[2]);
                             })
      .def("__len__", [](const Octree& t) { return t.nodes.size(); })
      .def(
          "save",
          [](const Octree& t, const std::filesystem::path& path, double threshold) {
            py::gil_scoped_release release;
            write_octree(path, t, threshold);
          },
          py::arg("path"), py::arg("threshold") = 0.5, doc::kOctreeSave);

  model.def(
      "octree",
      [](const Model& a, int depth, const py::object& bounds, int samples, int64_t max_memory,
         Threads threads) {
        if (depth < 0 || depth > 16)
          throw InputError("depth: expected a whole number from 0 to 16, got " +
                           std::to_string(depth));
        if (samples < 1 || samples > 32)
          throw InputError("samples: expected a whole number from 1 to 32, got " +
                           std::to_string(samples));
        if (max_memory < 1 || max_memory > (int64_t{1} << 40))
          throw InputError("max_memory: expected MiB from 1 to 2^40, got " +
                           std::to_string(max_memory));
        OctreeOptions o;
        o.depth = depth;
        o.samples = samples;
        o.max_bytes = static_cast<uint64_t>(max_memory) << 20;
        const std::optional<VoxelBounds> given = bounds_arg(bounds);
        KernelScope scope(threads);
        return scope.run([&] {
          Interrupt interrupt;
          o.progress = [&](double) { interrupt.poll(); };
          return a.octree(o, given);
        });
      },
      py::arg("depth") = 6, py::arg("bounds") = py::none(), py::kw_only(), py::arg("samples") = 4,
      py::arg("max_memory") = 4096, py::arg("threads") = py::none(), doc::kOctreeMethod);

  m.def(
      "write_voxels",
      [](const std::filesystem::path& path, py::handle grid, py::handle bounds) {
        const auto g =
            py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(grid);
        if (!g || g.ndim() != 3 || g.shape(0) != g.shape(1) || g.shape(1) != g.shape(2) ||
            g.shape(0) < 1 || g.shape(0) > kMaxVoxelDims)
          throw InputError(
              "grid: expected a cubic (N, N, N) array indexed [x, y, z], N from 1 "
              "to " +
              std::to_string(kMaxVoxelDims) + ", as Model.voxelize returns");
        const std::optional<VoxelBounds> b = bounds_arg(py::reinterpret_borrow<py::object>(bounds));
        if (!b)
          throw InputError("bounds: expected (xmin, ymin, zmin, size), as Model.voxel_bounds");
        const int n = static_cast<int>(g.shape(0));
        const VoxelLattice lattice = cubic_lattice(*b, n);
        VoxelGrid out = empty_voxel_grid(lattice, whole_box(lattice));
        const uint8_t* src = g.data();
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
              if (src[(static_cast<size_t>(i) * n + j) * n + k]) out.set(i, j, k);
        py::gil_scoped_release release;
        std::string ext = path.extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (ext == ".vdb")
          write_vdb(path, out);
        else
          write_voxels(path, out);
      },
      py::arg("path"), py::arg("grid"), py::arg("bounds"), doc::kWriteVoxels);
}

}  // namespace cover::python
