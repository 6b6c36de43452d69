#pragma once
// cover.view and cover.Viewer (python/viewer.cpp): `cover view` from Python.

#include <pybind11/pybind11.h>

namespace cover::python {

/// Adds the viewer to the module.
void bind_viewer(pybind11::module_& m);

}  // namespace cover::python
