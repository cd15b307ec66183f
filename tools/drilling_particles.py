#!/usr/bin/python3
"""The workpiece's particles in a friction-drilling run's field output (examples/friction_drilling).

For each d3plot_*.vtu given: the workpiece's nodes (parts 1 and 2), how many are lost (a position or
velocity that is not finite, or a node thrown out of the region the process can reach: beyond the
disk's radius, or more than LIMIT from the sheet's faces), the fastest one, the broken bonds of the
SPG particles (each bond counts at both its ends, so halved) and the largest effective plastic
strain. Exits 1 when a node is lost.
Run it with Debian's interpreter, which has python3-vtk9: /usr/bin/python3 tools/drilling_particles.py RUN/d3plot_*.vtu
"""
import argparse
import sys

import numpy
from particle_files import read_particles
from vtk.util.numpy_support import vtk_to_numpy

p = argparse.ArgumentParser(description=__doc__)
p.add_argument("files", nargs="+")
p.add_argument("--radius", type=float, default=9e-3, help="the disk's radius (m)")
p.add_argument("--thickness", type=float, default=1.5e-3, help="the sheet's thickness (m), its top at z = 0")
p.add_argument("--limit", type=float, default=5e-3, help="how far from the sheet's faces a node may go (m)")
args = p.parse_args()

lost_any = False
for path in args.files:
    grid = read_particles(path, "drilling_particles")
    data = grid.GetPointData()
    x = vtk_to_numpy(grid.GetPoints().GetData())
    v = vtk_to_numpy(data.GetArray("velocity"))
    part = vtk_to_numpy(data.GetArray("part_id"))
    work = (part == 1) | (part == 2)
    x, v = x[work], v[work]
    finite = numpy.isfinite(x).all(axis=1) & numpy.isfinite(v).all(axis=1)
    r = numpy.hypot(x[:, 0], x[:, 1])
    inside = (r <= args.radius * 1.001) & (x[:, 2] <= args.limit) & (x[:, 2] >= -args.thickness - args.limit)
    lost = int((~(finite & inside)).sum())
    lost_any |= lost > 0
    speed = numpy.linalg.norm(numpy.where(finite[:, None], v, 0), axis=1)
    spg = part[work] == 1
    broken = data.GetArray("broken_bonds")
    bonds = int(vtk_to_numpy(broken)[work][spg].sum()) // 2 if broken else 0
    strain = data.GetArray("effective_plastic_strain")
    eps = float(numpy.nanmax(vtk_to_numpy(strain)[work])) if strain else float("nan")
    print(f"{path}: workpiece nodes {int(work.sum())}, lost {lost}, fastest {speed.max():.4g} m/s, "
          f"broken bonds {bonds}, largest effective plastic strain {eps:.4g}")
sys.exit(1 if lost_any else 0)
