// The modeling part of the module `cover._cover` (docs/python.md): cover.subdivide (subdivision/),
// cover.modify and cover.HalfedgeMesh (the DLFL modeler, modeler/script.h).
#include "modeling.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "cover/modeler/dlfl.h"
#include "cover/modeler/ffd.h"
#include "cover/modeler/script.h"
#include "cover/solid/errors.h"
#include "cover/subdivision/subdivide.h"
#include "docstrings.h"

namespace cover::python {
namespace {

namespace py = pybind11;

/// cover.HalfedgeMesh: the DLFL modeler's mesh (modeler/dlfl.h) with its operators; each
/// operator runs as a one-step script (modeler/script.h), so ids and points name elements as in
/// `cover modify`.
void bind_halfedge_mesh(py::module_& m) {
  using modeler::DlflMesh;
  const auto run = [](DlflMesh& mesh, const nlohmann::json& op) {
    py::gil_scoped_release release;
    modeler::apply_script(mesh, nlohmann::json::array({op}).dump(), "HalfedgeMesh");
  };
  const auto target = [](py::handle h) -> nlohmann::json {
    if (py::isinstance<py::int_>(h)) return h.cast<int64_t>();
    const std::vector<double> p = h.cast<std::vector<double>>();
    return nlohmann::json(p);
  };
  const auto corner = [target](py::handle h) -> nlohmann::json {
    if (py::isinstance<py::int_>(h)) return {{"vertex", h.cast<int64_t>()}};
    const py::tuple t = h.cast<py::tuple>();
    if (t.size() != 2)
      throw InputError("corner: expected (face, vertex) or a point-sphere's vertex");
    return {{"face", target(t[0])}, {"vertex", target(t[1])}};
  };
  py::class_<DlflMesh>(m, "HalfedgeMesh", doc::kHalfedgeMesh)
      .def(py::init([](py::handle v, py::handle f) {
             PolygonMesh in;
             const Points vertices = points_arg(v, "V");
             in.vertices.assign(vertices.span().begin(), vertices.span().end());
             faces_arg(f, in);
             return modeler::from_polygon_mesh(in);
           }),
           py::arg("V"), py::arg("F"))
      .def_property_readonly("vertex_count", &DlflMesh::vertex_count)
      .def_property_readonly("edge_count", &DlflMesh::edge_count)
      .def_property_readonly("face_count", &DlflMesh::face_count)
      .def_property_readonly("genus",
                             [](const DlflMesh& mesh) {
                               int g = 0;
                               for (const auto& c : modeler::components(mesh)) g += c.genus;
                               return g;
                             })
      .def_property_readonly("components",
                             [](const DlflMesh& mesh) { return modeler::components(mesh).size(); })
      .def("arrays",
           [](const DlflMesh& mesh) {
             const PolygonMesh out = modeler::to_polygon_mesh(mesh);
             return py::make_tuple(vertices_array(out.vertices), faces_object(out));
           })
      .def("check", [](const DlflMesh& mesh) { modeler::check_valid(mesh); })
      .def(
          "create_vertex",
          [](DlflMesh& mesh, const std::array<double, 3>& p) {
            return mesh.create_vertex({p[0], p[1], p[2]});
          },
          py::arg("point"))
      .def(
          "delete_vertex",
          [run, target](DlflMesh& mesh, py::handle v) {
            run(mesh, {{"delete_vertex", {{"vertex", target(v)}}}});
          },
          py::arg("vertex"))
      .def(
          "insert_edge",
          [run, corner](DlflMesh& mesh, py::handle c1, py::handle c2) {
            run(mesh, {{"insert_edge", {{"corners", {corner(c1), corner(c2)}}}}});
          },
          py::arg("c1"), py::arg("c2"))
      .def(
          "delete_edge",
          [run, target](DlflMesh& mesh, py::handle e) {
            run(mesh, {{"delete_edge", {{"edge", target(e)}}}});
          },
          py::arg("edge"))
      .def(
          "remove_edge",
          [run, target](DlflMesh& mesh, py::handle e) {
            run(mesh, {{"remove_edge", {{"edge", target(e)}}}});
          },
          py::arg("edge"))
      .def(
          "subdivide_edge",
          [run, target](DlflMesh& mesh, py::handle e, int points) {
            run(mesh, {{"subdivide_edge", {{"edge", target(e)}, {"points", points}}}});
          },
          py::arg("edge"), py::arg("points") = 1)
      .def(
          "pipe",
          [run, target](DlflMesh& mesh, py::handle f1, py::handle f2, int segments, double twist,
                        bool curved, std::array<double, 2> weights,
                        std::optional<std::vector<std::array<double, 3>>> path) {
            nlohmann::json pipe = {{"faces", {target(f1), target(f2)}},
                                   {"segments", segments},
                                   {"twist", twist},
                                   {"curved", curved},
                                   {"weights", weights}};
            if (path) pipe["path"] = *path;
            run(mesh, {{"pipe", pipe}});
          },
          py::arg("f1"), py::arg("f2"), py::arg("segments") = 1, py::arg("twist") = 0.0,
          py::arg("curved") = false, py::arg("weights") = std::array<double, 2>{1.0, 1.0},
          py::arg("path") = py::none())
      .def(
          "extrude",
          [run, target](DlflMesh& mesh, py::handle f, double distance, const std::string& kind) {
            run(mesh, {{"extrude", {{"face", target(f)}, {"distance", distance}, {"kind", kind}}}});
          },
          py::arg("face"), py::arg("distance"), py::arg("kind") = "straight")
      .def(
          "truncate",
          [run, target](DlflMesh& mesh, py::handle v, double fraction) {
            run(mesh, {{"truncate", {{"vertex", target(v)}, {"fraction", fraction}}}});
          },
          py::arg("vertex"), py::arg("fraction") = 0.25)
      .def(
          "apply",
          [](DlflMesh& mesh, py::handle operations) {
            const std::string script =
                py::isinstance<py::str>(operations)
                    ? operations.cast<std::string>()
                    : py::module_::import("json").attr("dumps")(operations).cast<std::string>();
            py::gil_scoped_release release;
            modeler::apply_script(mesh, script, "operations");
          },
          py::arg("operations"));
}

}  // namespace

void bind_modeling(py::module_& m) {
  const auto threads = py::arg("threads") = py::none();
  m.def(
      "subdivide",
      [](py::handle v, py::handle f, const std::string& scheme, int levels, bool exact_rounding,
         py::handle uv, const std::optional<int>& threads) -> py::tuple {
        PolygonMesh in;
        const Points vertices = points_arg(v, "V");
        in.vertices.assign(vertices.span().begin(), vertices.span().end());
        faces_arg(f, in);
        const std::optional<Scheme> s = scheme_from_string(scheme);
        if (!s)
          throw InputError(
              "scheme: expected 'catmull-clark', 'doo-sabin', 'loop' or 'sqrt3', got '" + scheme +
              "'");
        const SubdivideOptions options{
            .scheme = *s, .levels = levels, .exact_rounding = exact_rounding};
        if (uv.is_none()) {
          PolygonMesh out;
          {
            KernelScope scope(threads);
            scope.run([&] { out = subdivide(in, options); });
          }
          return py::make_tuple(vertices_array(out.vertices), faces_object(out));
        }
        // Corner attributes: (corners, k), or (faces, n, k) for faces of one size n.
        const DoubleArray a = DoubleArray::ensure(uv);
        if (!a || (a.ndim() != 2 && a.ndim() != 3))
          throw InputError("uv: expected a float array (corners, k) or (faces, n, k)");
        const auto corners = static_cast<py::ssize_t>(in.face_vertices.size());
        const py::ssize_t k = a.shape(a.ndim() - 1);
        if (k < 1 || a.size() != corners * k)
          throw InputError("uv: expected " + std::to_string(corners) +
                           " values per column (one per corner of F, in face order), got " +
                           std::to_string(a.size() / std::max<py::ssize_t>(k, 1)));
        CornerAttributes attributes{static_cast<int>(k),
                                    std::vector<double>(a.data(), a.data() + a.size())};
        PolygonMesh out;
        {
          KernelScope scope(threads);
          scope.run([&] { out = subdivide(in, options, attributes); });
        }
        py::array_t<double> values({static_cast<py::ssize_t>(out.face_vertices.size()), k});
        std::copy(attributes.values.begin(), attributes.values.end(), values.mutable_data());
        return py::make_tuple(vertices_array(out.vertices), faces_object(out), values);
      },
      py::arg("V"), py::arg("F"), py::arg("scheme") = "catmull-clark", py::arg("levels") = 1,
      py::arg("exact_rounding") = false, py::kw_only(), py::arg("uv") = py::none(), threads,
      doc::kSubdivide);
  m.def(
      "ffd",
      [](py::handle v, py::handle f, py::handle lattice_min, py::handle lattice_max,
         py::handle points, py::handle degree, double tolerance) -> py::tuple {
        PolygonMesh in;
        const Points vertices = points_arg(v, "V");
        in.vertices.assign(vertices.span().begin(), vertices.span().end());
        faces_arg(f, in);
        FfdLattice lattice;
        lattice.min = vec3_arg(lattice_min, "lattice_min");
        lattice.max = vec3_arg(lattice_max, "lattice_max");
        const std::vector<double> d = numbers_arg(degree, "degree", 3);
        for (int a = 0; a < 3; ++a) {
          if (d[a] != std::floor(d[a]) || d[a] < 1 || d[a] > 16)
            throw InputError("degree: expected 3 integers from 1 to 16");
          lattice.degree[a] = static_cast<int>(d[a]);
        }
        const Points control = points_arg(points, "points");
        lattice.points.assign(control.span().begin(), control.span().end());
        if (!(tolerance >= 0) || !std::isfinite(tolerance))
          throw InputError("tolerance: expected a finite number >= 0");
        const FfdResult r = ffd(in, lattice, {.tolerance = tolerance});
        py::dict report;
        report["levels"] = r.levels;
        report["chord_bound"] = r.chord_bound;
        return py::make_tuple(vertices_array(r.mesh.vertices), faces_object(r.mesh), report);
      },
      py::arg("V"), py::arg("F"), py::arg("lattice_min"), py::arg("lattice_max"), py::arg("points"),
      py::kw_only(), py::arg("degree") = std::vector<int>{1, 1, 1}, py::arg("tolerance") = 0.0,
      doc::kFfd);
  m.def(
      "modify",
      [](py::handle v, py::handle f, py::handle operations) {
        PolygonMesh in;
        const Points vertices = points_arg(v, "V");
        in.vertices.assign(vertices.span().begin(), vertices.span().end());
        faces_arg(f, in);
        const std::string script =
            py::isinstance<py::str>(operations)
                ? operations.cast<std::string>()
                : py::module_::import("json").attr("dumps")(operations).cast<std::string>();
        PolygonMesh out;
        {
          py::gil_scoped_release release;
          modeler::DlflMesh mesh = modeler::from_polygon_mesh(in);
          modeler::apply_script(mesh, script, "operations");
          out = modeler::to_polygon_mesh(mesh);
        }
        return py::make_tuple(vertices_array(out.vertices), faces_object(out));
      },
      py::arg("V"), py::arg("F"), py::arg("operations"), doc::kModify);
  bind_halfedge_mesh(m);
}

}  // namespace cover::python
