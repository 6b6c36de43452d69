#pragma once
// cover.write_mesh (python/files.cpp): the CLI's mesh writers from Python.

#include <pybind11/pybind11.h>

namespace cover::python {

/// Adds the file writers to the module.
void bind_files(pybind11::module_& m);

}  // namespace cover::python
