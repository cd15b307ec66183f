#!/usr/bin/python3
"""Final shape of a Taylor bar run: L/L0 and R/R0 from the run's first and last field output.

    /usr/bin/python3 tools/taylor_bar_shape.py RESULTS_FOLDER   (reads RESULTS_FOLDER/d3plot.pvd)

The rod stands on the wall z = 0 along +z, its axis at x = y = 0 (tools/make_taylor_bar_deck.py).
Measured as tests/support/taylor_bar.hpp does for the verification test: the length is the
highest particle centre plus half a spacing, the foot radius the largest distance of a particle
centre from the axis plus half a spacing (each particle stands for a cell of one spacing; the
mushroom is widest at its foot). Both ratios divide by the same measure of the rod before impact, so that the lattice's
own overshoot of the circle cancels. The spacing is the lattice's: the smallest gap between
distinct x coordinates at t = 0. Prints the time of each file and the two ratios against
Wilkins & Guinan 1973 test 1 (L/L0 0.630, R/R0 2.204). Needs Debian's python3-vtk9 and numpy.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy

MEASURED_LENGTH_RATIO, MEASURED_RADIUS_RATIO = 0.630, 2.204  # Wilkins & Guinan 1973, test 1


def series(folder):
    """(time, path) of every file in folder/d3plot.pvd, in time order."""
    pvd = os.path.join(folder, "d3plot.pvd")
    if not os.path.exists(pvd):
        sys.exit(f"taylor_bar_shape: {pvd} does not exist (run spall first)")
    entries = [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
               for d in ET.parse(pvd).getroot().iter("DataSet")]
    if len(entries) < 2:
        sys.exit(f"taylor_bar_shape: {pvd} lists {len(entries)} file(s); need the first and a later one")
    return sorted(entries)


def points(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfPoints() == 0:
        sys.exit(f"taylor_bar_shape: {path}: no particles")
    return vtk_to_numpy(grid.GetPoints().GetData())


def lattice_spacing(x):
    coords = numpy.unique(numpy.round(x[:, 0], 12))
    return float(numpy.diff(coords).min())


def shape(x, dx):
    length = x[:, 2].max() + dx / 2
    radius = numpy.hypot(x[:, 0], x[:, 1]).max() + dx / 2
    return length, radius


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    args = parser.parse_args()
    files = series(args.folder)
    (t0, first), (t1, last) = files[0], files[-1]
    x0 = points(first)
    dx = lattice_spacing(x0)
    length0, radius0 = shape(x0, dx)
    length1, radius1 = shape(points(last), dx)
    lr, rr = length1 / length0, radius1 / radius0
    print(f"particles {len(x0)}  spacing {dx:.6g}")
    print(f"t {t0:.6g}: length {length0:.6g}  foot radius {radius0:.6g}  ({os.path.basename(first)})")
    print(f"t {t1:.6g}: length {length1:.6g}  foot radius {radius1:.6g}  ({os.path.basename(last)})")
    print(f"L/L0 {lr:.4f}  (Wilkins & Guinan 0.630: {100 * (lr / MEASURED_LENGTH_RATIO - 1):+.1f} %)")
    print(f"R/R0 {rr:.4f}  (Wilkins & Guinan 2.204: {100 * (rr / MEASURED_RADIUS_RATIO - 1):+.1f} %)")


if __name__ == "__main__":
    main()
