"""What the particle tools share: reading one Spall .vtu (or .pvtu) with VTK, and a point locator.

Imported by render_particles.py and count_fragments.py (run them with /usr/bin/python3, which has
python3-vtk9).
"""
import sys

import numpy
import vtk
from vtk.util.numpy_support import numpy_to_vtk


def read_particles(path, tool):
    """The unstructured grid of a .vtu (or of an MPI run's .pvtu, its pieces joined); exits naming
    `tool` when VTK finds no particles in it."""
    reader = vtk.vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtk.vtkXMLUnstructuredGridReader()
    errors = []
    reader.AddObserver("ErrorEvent", lambda caller, event: errors.append(event))
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    if errors or grid.GetNumberOfPoints() == 0:
        sys.exit(f"{tool}: {path}: VTK cannot read particles from it")
    return grid


def point_locator(x):
    """A VTK static point locator over the positions x (n, 3)."""
    points = vtk.vtkPoints()
    points.SetData(numpy_to_vtk(numpy.ascontiguousarray(x)))
    cloud = vtk.vtkPolyData()
    cloud.SetPoints(points)
    locator = vtk.vtkStaticPointLocator()
    locator.SetDataSet(cloud)
    locator.BuildLocator()
    return locator


def median_spacing(x):
    """The median distance from a particle to its nearest neighbour (of up to 2000 samples)."""
    locator = point_locator(x)
    ids = vtk.vtkIdList()
    step = max(1, len(x) // 2000)
    distances = []
    for i in range(0, len(x), step):
        locator.FindClosestNPoints(2, x[i], ids)
        j = ids.GetId(1) if ids.GetId(0) == i else ids.GetId(0)
        distances.append(numpy.linalg.norm(x[j] - x[i]))
    return float(numpy.median(distances))
