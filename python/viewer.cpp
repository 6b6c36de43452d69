#include "viewer.h"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <memory>

#include "cover/view/viewer.h"

namespace py = pybind11;

namespace cover::python {

namespace {

constexpr const char* kView =
    R"(Serves the browser viewer of `cover view` for the mesh or scene at `path` (docs/viewer.md)
on a thread of its own and returns the running Viewer; open viewer.url in a browser.

host: the interface (default loopback only); port: 0 for any free port; poll: seconds between
checks of the input and the files it names (a change reloads them; the page keeps its view);
closed_only: refuse open meshes. Raises InputError for an input that does not load or a port
that cannot be bound. Use it as a context manager, or call stop().)";

constexpr const char* kViewer =
    R"(A running viewer (cover.view): url (with its access token), port, version (1, + 1 per
reload), error (the last failed reload's message, "" when none), stop().)";

}  // namespace

void bind_viewer(py::module_& m) {
  py::class_<Viewer>(m, "Viewer", kViewer)
      .def_property_readonly("url", &Viewer::url)
      .def_property_readonly("port", &Viewer::port)
      .def_property_readonly("version", [](const Viewer& v) { return v.state().version; })
      .def_property_readonly("error", [](const Viewer& v) { return v.state().error; })
      .def("check_files", &Viewer::check_files, py::call_guard<py::gil_scoped_release>(),
           "Checks the watched files now; True when it reloaded (or tried to).")
      .def("stop", &Viewer::stop, py::call_guard<py::gil_scoped_release>(),
           "Stops serving; idempotent.")
      .def(
          "__enter__", [](Viewer& v) -> Viewer& { return v; }, py::return_value_policy::reference)
      .def("__exit__",
           [](Viewer& v, const py::args&) {
             py::gil_scoped_release release;
             v.stop();
           })
      .def("__repr__", [](const Viewer& v) { return "<cover.Viewer " + v.url() + ">"; });
  m.def(
      "view",
      [](const std::filesystem::path& path, const std::string& host, int port, double poll,
         bool closed_only) {
        ViewerOptions o;
        o.host = host;
        o.port = port;
        o.poll_seconds = poll;
        o.load.require_closed = closed_only;
        std::unique_ptr<Viewer> v;
        {
          py::gil_scoped_release release;
          v = std::make_unique<Viewer>(path, o);
        }
        for (const std::string& w : v->warnings())
          if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
        return v;
      },
      py::arg("path"), py::kw_only(), py::arg("host") = "127.0.0.1", py::arg("port") = 0,
      py::arg("poll") = 0.5, py::arg("closed_only") = false, kView);
}

}  // namespace cover::python
