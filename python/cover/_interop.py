"""Meshes from and to other Python libraries, by duck typing (none of them is a dependency):
trimesh, Open3D and meshio objects, and VTK's vtkPolyData (Debian python3-vtk9)."""

import warnings as _warnings

import numpy as _np

from . import _cover

__all__ = ["mesh", "to_vtk"]


def _arrays_of(obj):
    """(V float64 (n, 3), F int64 (m, 3)) of a mesh object, or TypeError naming what it lacks."""
    if hasattr(obj, "GetPolys") and hasattr(obj, "GetPoints"):  # vtkPolyData
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkFiltersCore import vtkTriangleFilter

        triangles = vtkTriangleFilter()
        triangles.SetInputData(obj)
        triangles.PassVertsOff()
        triangles.PassLinesOff()
        triangles.Update()
        poly = triangles.GetOutput()
        if poly.GetPoints() is None:
            raise _cover.InputError("V: the vtkPolyData has no points")
        V = vtk_to_numpy(poly.GetPoints().GetData()).astype(_np.float64)
        F = vtk_to_numpy(poly.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        return V, F.astype(_np.int64)
    if hasattr(obj, "vertices") and hasattr(obj, "faces"):  # trimesh.Trimesh
        return _np.asarray(obj.vertices, dtype=_np.float64), _np.asarray(obj.faces)
    if hasattr(obj, "vertices") and hasattr(obj, "triangles"):  # open3d TriangleMesh
        return _np.asarray(obj.vertices, dtype=_np.float64), _np.asarray(obj.triangles)
    if hasattr(obj, "points") and hasattr(obj, "cells_dict"):  # meshio.Mesh
        cells = obj.cells_dict
        if "triangle" not in cells:
            raise _cover.InputError("V: the meshio Mesh has no triangle cells (got "
                                    f"{', '.join(sorted(cells)) or 'none'})")
        return _np.asarray(obj.points, dtype=_np.float64)[:, :3], _np.asarray(cells["triangle"])
    raise TypeError("V: expected an (n, 3) array with F, or a mesh object (vertices and faces "
                    "or triangles, meshio points and cells, a vtkPolyData); got "
                    f"{type(obj).__name__}")


def mesh(V, F=None, *, closed_only=False):
    # The first line is the signature, as pybind11 writes it (python/tests/test_stubs.py).
    if F is None:
        V, F = _arrays_of(V)
    with _warnings.catch_warnings(record=True) as caught:
        _warnings.simplefilter("always")
        model = _cover.mesh(V, F, closed_only=closed_only)
    for w in caught:  # re-issued at the caller's line
        _warnings.warn(w.message, w.category, stacklevel=2)
    return model


mesh.__doc__ = (
    "mesh(V: object, F: object = None, *, closed_only: bool = False) -> cover.Model\n\n"
    + _cover.mesh.__doc__.split("\n", 1)[1].strip("\n") + "\n\n"
    "With F None, V may be a mesh object instead: anything with vertices and faces (trimesh), "
    "vertices and triangles (Open3D), points and cells_dict['triangle'] (meshio), or a VTK "
    "vtkPolyData (its polygons triangulated by vtkTriangleFilter).")


def to_vtk(V, F):
    # The first line is the signature, as pybind11 writes it (python/tests/test_stubs.py).
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    V = _np.ascontiguousarray(V, dtype=_np.float64)
    F = _np.ascontiguousarray(F, dtype=_np.int64)
    if V.ndim != 2 or V.shape[1] != 3:
        raise ValueError(f"V: expected an array of shape (n, 3), got shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"F: expected an array of shape (m, 3), got shape {F.shape}")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise _cover.InputError(f"F: vertex indices must be in [0, {len(V)})")
    points = vtkPoints()
    points.SetData(numpy_to_vtk(V, deep=True))
    cells = vtkCellArray()
    offsets = _np.arange(0, 3 * len(F) + 1, 3, dtype=_np.int64)
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(F.reshape(-1), deep=True))
    poly = vtkPolyData()
    poly.SetPoints(points)
    poly.SetPolys(cells)
    return poly


to_vtk.__doc__ = (
    "to_vtk(V: object, F: object) -> object\n\n"
    "A VTK vtkPolyData of the triangles F (int (m, 3)) over V (float (n, 3)), e.g. of "
    "Model.evaluate(): for PyVista (pyvista.wrap) or VTK's writers and filters. Needs VTK "
    "(Debian python3-vtk9).")
