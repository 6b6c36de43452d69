// Octrees and voxel files for Python (docs/python.md): Model.octree (the direct octree of
// octree/octree.h, as `cover octree`) returning cover.Octree, whose arrays view its nodes and
// whose save() writes .htg, .bt or .json as the CLI does; cover.write_voxels writes a bool grid
// with its bounds or lattice in the CLI's voxel formats (.binvox, .vti, .npy, .raw with its
// sidecar, .zarr, .vdb), atomically.
#include "grids.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include "arrays.h"
#include "cover/io/octree_io.h"
#include "cover/io/vdb_io.h"
#include "cover/io/voxel_io.h"
#include "cover/io/zarr_io.h"
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
        std::optional<VoxelBounds> given;
        if (py::isinstance<py::str>(bounds)) {  // the cube `cover octree -o x.bt` picks
          if (bounds.cast<std::string>() != "octomap")
            throw InputError("bounds: expected (xmin, ymin, zmin, size), \"octomap\" or None");
          const std::optional<Bbox> box = a.bounds();
          if (!box)
            throw NotComputable("bounds: the result is unbounded (a complement at the root)");
          given = octomap_bounds(*box, std::max(depth, 1));
        } else {
          given = bounds_arg(bounds);
        }
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
      [](const std::filesystem::path& path, py::handle grid, const py::object& bounds,
         const py::object& lattice, int chunk) {
        const auto g =
            py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(grid);
        if (!g || g.ndim() != 3)
          throw InputError(
              "grid: expected a bool or 0/1 array of shape (NX, NY, NZ) indexed "
              "[x, y, z], as Model.voxelize returns");
        std::array<int, 3> dims{};
        for (int a = 0; a < 3; ++a) {
          if (g.shape(a) < 1 || g.shape(a) > kMaxVoxelDims)
            throw InputError("grid: expected 1 to " + std::to_string(kMaxVoxelDims) +
                             " voxels per axis");
          dims[a] = static_cast<int>(g.shape(a));
        }
        if (bounds.is_none() == lattice.is_none())
          throw InputError(
              "bounds, lattice: give exactly one (bounds = (xmin, ymin, zmin, size) of a cubic "
              "grid, as Model.voxel_bounds; lattice = Model.voxel_lattice(...) or (origin, "
              "spacing))");
        VoxelLattice l;
        if (!bounds.is_none()) {
          const std::optional<VoxelBounds> b = bounds_arg(bounds);
          if (!b)
            throw InputError("bounds: expected (xmin, ymin, zmin, size), as Model.voxel_bounds");
          if (dims[0] != dims[1] || dims[1] != dims[2])
            throw InputError(
                "grid: bounds describe a cubic (N, N, N) grid; give lattice= for "
                "a non-cubic one");
          l = cubic_lattice(*b, dims[0]);
        } else {
          const py::tuple t = py::tuple(lattice);  // VoxelLattice or (origin, spacing)
          if (t.size() < 2)
            throw InputError("lattice: expected (origin, spacing), as Model.voxel_lattice");
          l.origin = vec3_arg(t[0], "lattice origin");
          l.spacing = py::cast<double>(t[1]);
          if (!(l.spacing > 0) || !std::isfinite(l.spacing))
            throw InputError("lattice: expected a finite spacing > 0");
          if (t.size() > 2 && !t[2].is_none() &&
              numbers_arg(t[2], "lattice dims", 3) !=
                  std::vector<double>{double(dims[0]), double(dims[1]), double(dims[2])})
            throw InputError("lattice: its dims differ from the grid's shape");
          if (t.size() > 3 && !t[3].is_none()) l.cube_size = py::cast<double>(t[3]);
          l.dims = dims;
        }
        VoxelGrid out = empty_voxel_grid(l, whole_box(l));
        const uint8_t* src = g.data();
        for (int i = 0; i < dims[0]; ++i)
          for (int j = 0; j < dims[1]; ++j)
            for (int k = 0; k < dims[2]; ++k)
              if (src[(static_cast<size_t>(i) * dims[1] + j) * dims[2] + k]) out.set(i, j, k);
        py::gil_scoped_release release;
        if (is_zarr_extension(path)) {
          ZarrOptions o;
          o.chunk = chunk;
          write_zarr(path, out, o);
        } else if (is_vdb_extension(path)) {
          write_vdb(path, out);
        } else {
          write_voxels(path, out);
        }
      },
      py::arg("path"), py::arg("grid"), py::arg("bounds") = py::none(), py::kw_only(),
      py::arg("lattice") = py::none(), py::arg("chunk") = 128, doc::kWriteVoxels);
}

}  // namespace cover::python
