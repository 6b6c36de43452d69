#pragma once

#include <pybind11/pybind11.h>

#include "cover/model/model.h"

namespace cover::python {

/// cover.Octree, Model.octree and cover.write_voxels (python/grids.cpp).
void bind_grids(pybind11::module_& m, pybind11::class_<Model>& model);

}  // namespace cover::python
