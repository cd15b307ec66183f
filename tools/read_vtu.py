#!/usr/bin/python3
"""Read a .vtu (or .pvtu) with VTK's own reader and summarise it, one fact per line:

    points N
    cells N
    FIELD components C type Float64|Int64|...
    FIELD component_names xx yy ...      (when the file names the components)
    FIELD min v1 [v2 ...]                (per component)
    FIELD max v1 [v2 ...]
    FIELD magnitude_min v / magnitude_max v   (fields of more than one component)
    FIELD value I v1 [v2 ...]            (with --values, every point)

Numbers print so that they read back to the same double (Python's repr) or integer, so a test can
compare them exactly. Exits 1 when the file cannot be read or a field is missing.
Run it with Debian's interpreter, which has python3-vtk9: /usr/bin/python3 tools/read_vtu.py ...
"""
import argparse
import sys

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def number(value):
    return str(int(value)) if numpy.issubdtype(type(value), numpy.integer) else repr(float(value))


def numbers(values):
    return " ".join(number(v) for v in values)


def xml_type(dtype):
    """The VTK XML name of a value type (Float64, Int64, UInt8, ...), as the file spells it."""
    kind = {"f": "Float", "i": "Int", "u": "UInt"}[dtype.kind]
    return f"{kind}{8 * dtype.itemsize}"


def read(path):
    reader = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    errors = []
    # VTK reports a bad file through its error event (its own message still goes to stderr) and
    # returns a grid anyway, empty or partial.
    reader.AddObserver("ErrorEvent", lambda caller, event: errors.append(event))
    reader.SetFileName(path)
    reader.Update()
    if errors or not reader.CanReadFile(path):
        sys.exit(f"read_vtu: {path}: VTK cannot read it as an unstructured grid")
    return reader.GetOutput()


def describe(grid, name, print_values):
    array = grid.GetPointData().GetArray(name)
    if array is None:
        present = [grid.GetPointData().GetArrayName(i) for i in range(grid.GetPointData().GetNumberOfArrays())]
        sys.exit(f"read_vtu: no point field '{name}' (present: {' '.join(present) or 'none'})")
    components = array.GetNumberOfComponents()
    values = vtk_to_numpy(array).reshape(-1, components)
    print(f"{name} components {components} type {xml_type(values.dtype)}")
    names = [array.GetComponentName(i) for i in range(components)]
    if all(names):
        print(f"{name} component_names {' '.join(names)}")
    if len(values) > 0:
        print(f"{name} min {numbers(values.min(axis=0))}")
        print(f"{name} max {numbers(values.max(axis=0))}")
        if components > 1:
            magnitude = numpy.linalg.norm(values.astype(float), axis=1)
            print(f"{name} magnitude_min {number(magnitude.min())}")
            print(f"{name} magnitude_max {number(magnitude.max())}")
    if print_values:
        for i, row in enumerate(values):
            print(f"{name} value {i} {numbers(row)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("file")
    parser.add_argument("--field", action="append", default=[], help="a point field to summarise (repeatable)")
    parser.add_argument("--values", action="store_true", help="also print every point's value of each field")
    args = parser.parse_args()

    grid = read(args.file)
    print(f"points {grid.GetNumberOfPoints()}")
    print(f"cells {grid.GetNumberOfCells()}")
    for name in args.field:
        describe(grid, name, args.values)


if __name__ == "__main__":
    main()
