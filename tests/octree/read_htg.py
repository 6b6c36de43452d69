#!/usr/bin/env python3
"""Reads a .htg back through VTK's own reader (tests/octree/octree_test.cpp).

Usage: read_htg.py FILE

Loads FILE with vtkXMLHyperTreeGridReader (python3-vtk9), walks tree 0 depth first with a
vtkHyperTreeGridNonOrientedGeometryCursor (children in VTK's order: x fastest, then y, then z)
and prints one JSON object:
{"vertices": V, "levels": L, "trees": T,
 "leaves": [[level, xmin, xmax, ymin, ymax, zmin, zmax, state, occupancy], ...]}
with state and occupancy the cell arrays of the same names at each leaf. Exits with status 1 and
a message on stderr when VTK reports an error or the grid lacks a tree or an array.
"""

import json
import sys

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkHyperTreeGridNonOrientedGeometryCursor
from vtkmodules.vtkIOXML import vtkXMLHyperTreeGridReader


def fail(message):
    sys.stderr.write("read_htg: " + message + "\n")
    sys.exit(1)


def main():
    if len(sys.argv) != 2:
        fail("usage: read_htg.py FILE")
    errors = []
    reader = vtkXMLHyperTreeGridReader()
    reader.AddObserver(vtkCommand.ErrorEvent, lambda caller, event: errors.append(event))
    reader.SetFileName(sys.argv[1])
    reader.Update()
    if errors or reader.GetErrorCode() != 0:
        fail("VTK could not read %s" % sys.argv[1])
    grid = reader.GetOutput()
    if grid is None or grid.GetMaxNumberOfTrees() < 1 or grid.GetNumberOfVertices() < 1:
        fail("no tree")
    data = grid.GetCellData()
    state, occupancy = data.GetArray("state"), data.GetArray("occupancy")
    if state is None or occupancy is None:
        fail("missing cell array state or occupancy")
    leaves = []
    cursor = vtkHyperTreeGridNonOrientedGeometryCursor()
    grid.InitializeNonOrientedGeometryCursor(cursor, 0)

    def visit():
        if cursor.IsLeaf():
            bounds = [0.0] * 6
            cursor.GetBounds(bounds)
            i = cursor.GetGlobalNodeIndex()
            leaves.append([cursor.GetLevel()] + bounds + [state.GetValue(i), occupancy.GetValue(i)])
            return
        for child in range(cursor.GetNumberOfChildren()):
            cursor.ToChild(child)
            visit()
            cursor.ToParent()

    visit()
    json.dump({"vertices": grid.GetNumberOfVertices(), "levels": grid.GetNumberOfLevels(),
               "trees": grid.GetMaxNumberOfTrees(), "leaves": leaves}, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
