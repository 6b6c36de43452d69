"""Cover: CSG solids without boundary evaluation (simplicial coverings).

numpy in, numpy out. Build a Model with load(), box(), sphere(), cylinder() or mesh(), combine
Models with | (union), & (intersection), - (difference) and ~ (complement) or union_all() and
intersection_all(), move them with translate(), scale(), rotate(), mirror() and transform(),
and query it:
classify(), windings(), volume(), bounds(), voxelize(), cast(), first_hits(), render(),
evaluate(), clip(), info(). subdivide() refines a polygon mesh given as arrays; modify() applies
modeling operations (pipes, extrusions, ...) to one; write_mesh() writes one in any format the
CLI writes, write_png() an image. In a notebook a Model shows itself (a small render). See
docs/python.md.
"""

import os as _os
import tempfile as _tempfile

from ._cover import (
    CLASS_NAMES,
    Casts,
    Hits,
    InputError,
    Model,
    NotComputable,
    Octree,
    PreconditionError,
    __version__,
    box,
    cylinder,
    ffd,
    intersection_all,
    load,
    points,
    scene,
    sphere,
    HalfedgeMesh,
    modify,
    subdivide,
    union_all,
    view,
    Viewer,
    write_mesh,
    write_png,
    write_voxels,
)
from ._interop import mesh, to_vtk
from ._results import MeshResult, VolumeResult, VoxelLattice

__all__ = [
    "CLASS_NAMES",
    "Casts",
    "Hits",
    "InputError",
    "Model",
    "NotComputable",
    "PreconditionError",
    "__version__",
    "box",
    "cylinder",
    "ffd",
    "intersection_all",
    "load",
    "mesh",
    "points",
    "scene",
    "sphere",
    "HalfedgeMesh",
    "modify",
    "subdivide",
    "union_all",
    "view",
    "Viewer",
    "write_mesh",
    "write_png",
    "write_voxels",
    "Octree",
    "VolumeResult",
    "MeshResult",
    "VoxelLattice",
    "to_vtk",
]


def _repr_png_(self):
    """A 320x240 isometric render as PNG bytes (Jupyter's rich display); None for an empty or
    unbounded Model."""
    if self.empty or not self.bounded:
        return None
    handle, path = _tempfile.mkstemp(suffix=".png")
    _os.close(handle)
    try:
        write_png(path, self.render(320, 240))
        with open(path, "rb") as f:
            return f.read()
    finally:
        _os.remove(path)


Model._repr_png_ = _repr_png_


_evaluate = Model.evaluate


def _evaluate_result(self, *, leaf_ids=False, mesh_resolution=128, mesh_tolerance=0.0,
                     threads=None):
    return MeshResult(_evaluate(self, leaf_ids=leaf_ids, mesh_resolution=mesh_resolution,
                                mesh_tolerance=mesh_tolerance, threads=threads))


_evaluate_result.__name__ = "evaluate"
_evaluate_result.__doc__ = _evaluate.__doc__.replace("-> tuple", "-> cover.MeshResult", 1) + (
    "\n\nThe result is a cover.MeshResult: the tuple as before, with save(path).")
Model.evaluate = _evaluate_result
