// The mesh writers of io/mesh_io.h for Python (docs/python.md): every format the CLI writes, atomic
// as the CLI's, with per-face leaf labels where the format holds them; and the PNG writer of
// io/png.h for images (Model.render()).
#include "files.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <string>

#include "arrays.h"
#include "cover/io/mesh_io.h"
#include "cover/io/png.h"
#include "cover/render/render.h"
#include "cover/solid/errors.h"
#include "docstrings.h"

namespace py = pybind11;

namespace cover::python {

void bind_files(py::module_& m) {
  m.def(
      "write_mesh",
      [](const std::filesystem::path& path, py::handle v, py::handle f, py::handle leaf_ids,
         py::handle colours) {
        PolygonMesh mesh;
        const Points vertices = points_arg(v, "V");
        mesh.vertices.assign(vertices.span().begin(), vertices.span().end());
        faces_arg(f, mesh);
        if (leaf_ids.is_none()) {
          py::gil_scoped_release release;
          write_mesh(path, mesh);
          return;
        }
        const auto ids =
            py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(leaf_ids);
        if (!ids || ids.ndim() != 1 || static_cast<size_t>(ids.size()) != mesh.face_count())
          throw InputError("leaf_ids: expected one integer per face (" +
                           std::to_string(mesh.face_count()) + ")");
        FaceLabels labels;
        labels.ply_property = "leaf";
        int64_t largest = -1;
        for (py::ssize_t i = 0; i < ids.size(); ++i) {
          const int64_t id = ids.data()[i];
          if (id < 0 || id > 0x7FFFFFFF)
            throw InputError("leaf_ids: face " + std::to_string(i) + ": leaf " +
                             std::to_string(id) + " out of range");
          labels.labels.push_back(static_cast<uint32_t>(id));
          largest = std::max(largest, id);
        }
        // colours: (k, 3) uint8 per leaf id (Model.leaf_colours), else the render palette.
        std::vector<std::array<uint8_t, 3>> given;
        if (!colours.is_none()) {
          const auto c =
              py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(colours);
          if (!c || c.ndim() != 2 || c.shape(1) != 3)
            throw InputError("colours: expected a (leaves, 3) uint8 array, as Model.leaf_colours");
          for (py::ssize_t i = 0; i < c.shape(0); ++i)
            given.push_back({c.at(i, 0), c.at(i, 1), c.at(i, 2)});
        }
        for (int64_t l = 0; l <= largest; ++l) {
          labels.obj_groups.push_back("leaf_" + std::to_string(l));
          labels.colours.push_back(static_cast<size_t>(l) < given.size()
                                       ? given[l]
                                       : leaf_colour(static_cast<uint32_t>(l)));
        }
        py::gil_scoped_release release;
        write_mesh(path, mesh, labels);
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("leaf_ids") = py::none(), py::kw_only(),
      py::arg("colours") = py::none(), doc::kWriteMesh);
  m.def(
      "write_png",
      [](const std::filesystem::path& path, py::handle image) {
        const auto img =
            py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
        if (!img || img.ndim() != 3 || img.shape(2) != 3 || img.shape(0) < 1 || img.shape(1) < 1)
          throw InputError(
              "image: expected a uint8 array of shape (height, width, 3), as "
              "Model.render() returns");
        if (img.shape(0) > 65535 || img.shape(1) > 65535)
          throw InputError("image: at most 65535 pixels per side");
        check_png_path(path);
        const auto h = static_cast<int>(img.shape(0)), w = static_cast<int>(img.shape(1));
        const std::span<const uint8_t> rgb(img.data(), static_cast<size_t>(img.size()));
        py::gil_scoped_release release;
        write_png_rgb(path, w, h, rgb);
      },
      py::arg("path"), py::arg("image"), doc::kWritePng);
}

}  // namespace cover::python
