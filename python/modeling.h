#pragma once
// cover.subdivide, cover.modify and cover.HalfedgeMesh (python/modeling.cpp).

#include <pybind11/pybind11.h>

namespace cover::python {

/// Adds the modeling functions and the HalfedgeMesh class to the module.
void bind_modeling(pybind11::module_& m);

}  // namespace cover::python
