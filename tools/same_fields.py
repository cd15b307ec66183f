#!/usr/bin/python3
"""Whether two runs wrote the same fields, bit for bit: every dataset of FIRST/d3plot.pvd and of
SECOND/d3plot.pvd, in turn, read with VTK's own readers (a .vtu, or the pieces an MPI run's .pvtu
joins), must have the same output times, the same points and the same point fields with the same
bits, node by node (matched by node_id, so that the order of the pieces does not count, and a node
that two pieces share written alike by both), and the same cell fields element by element.

For the MPI tests: a run on several ranks writes .pvtu files whose pieces are the ranks' nodes, and
must hold exactly what the single process's .vtu files hold. Exits 1 naming the first difference.
Run it with Debian's interpreter, which has python3-vtk9: /usr/bin/python3 tools/same_fields.py A B
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree

import numpy
from read_vtu import read
from vtk.util.numpy_support import vtk_to_numpy


def series(folder):
    """The (time, path) of every dataset of FOLDER/d3plot.pvd, the time as the file writes it."""
    root = ElementTree.parse(os.path.join(folder, "d3plot.pvd")).getroot()
    return [(d.get("timestep"), os.path.join(folder, d.get("file"))) for d in root.iter("DataSet")]


def by_key(arrays, key, where):
    """The arrays' rows in the order of the key array; a row that repeats (a node on a boundary of
    pieces, written by each piece with a cell on it) must repeat exactly and is kept once."""
    _, first = numpy.unique(arrays[key], return_index=True)
    for name, values in arrays.items():
        kept = values[first][numpy.searchsorted(arrays[key][first], arrays[key])]
        if kept.tobytes() != values.tobytes():
            sys.exit(f"same_fields: {where}: a {key} written twice with two values of '{name}'")
    return {name: numpy.ascontiguousarray(values[first]) for name, values in arrays.items()}


def fields(path):
    """The points and every point field of a dataset as bytes-comparable arrays, in node_id order,
    and the cell fields of its elements (cells with an element_id), in element_id order."""
    grid = read(path)
    data = grid.GetPointData()
    arrays = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)) for i in range(data.GetNumberOfArrays())}
    arrays["points"] = vtk_to_numpy(grid.GetPoints().GetData()) if grid.GetNumberOfPoints() else numpy.zeros((0, 3))
    found = by_key(arrays, "node_id", path)
    cells = grid.GetCellData()
    if cells.GetArray("element_id") is not None:
        arrays = {cells.GetArrayName(i): vtk_to_numpy(cells.GetArray(i)) for i in range(cells.GetNumberOfArrays())}
        elements = arrays["element_id"] >= 0  # the vertex cells have the fill value
        arrays = by_key({name: values[elements] for name, values in arrays.items()}, "element_id", path)
        found.update({f"cell {name}": values for name, values in arrays.items()})
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("first")
    parser.add_argument("second")
    args = parser.parse_args()
    a, b = series(args.first), series(args.second)
    if [t for t, _ in a] != [t for t, _ in b]:
        sys.exit(f"same_fields: the output times differ: {[t for t, _ in a]} and {[t for t, _ in b]}")
    for (time, first), (_, second) in zip(a, b):
        x, y = fields(first), fields(second)
        if sorted(x) != sorted(y):
            sys.exit(f"same_fields: {first} and {second} have different fields: {sorted(x)} and {sorted(y)}")
        for name in sorted(x):
            if x[name].shape != y[name].shape or x[name].tobytes() != y[name].tobytes():
                sys.exit(f"same_fields: '{name}' at t = {time} differs between {first} and {second}")
    print(f"same_fields: {len(a)} datasets alike")


if __name__ == "__main__":
    main()
