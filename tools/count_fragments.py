#!/usr/bin/python3
"""Fragments of a Spall SPH run: the connected pieces of one .vtu, and their crack faces.

    /usr/bin/python3 tools/count_fragments.py RUN/d3plot_NNNNN.vtu [--link 1.5] [--part PID]

Two particles belong to one fragment when a chain of particles joins them in which each link is
shorter than --link times the initial spacing (the median nearest-neighbour distance of the
initial positions, x - displacement). 1.5 spacings joins a lattice's face and edge diagonals
(1 and 1.41 spacings) and separates pieces as soon as a gap of half a spacing has opened.

A *crack-face particle* is one whose initial neighbours (within the link distance of its
initial position) now lie partly in another fragment: the particles along the faces a fracture
created. With the point field `category` (*SPALL_SPH_COLOUR_FIELD) the tool counts how many of
them the colour field flags as surface (2), inner layer (1) or interior (0).

Prints, one fact per line:
    fragments N                      (pieces of at least --min-size particles; smaller: debris)
    debris N                         (particles in pieces below --min-size)
    fragment K particles N mass M x0_min X x0_max X x_min X x_max X velocity VX VY VZ
                                     (x0: initial positions, x: now; velocity: mass-weighted mean)
    crack_face_particles N surface N2 inner_layer N1 interior N0
Numbers in the run's units. Reads with VTK (python3-vtk9); run it with /usr/bin/python3.
"""
import argparse
import sys

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from particle_files import median_spacing, point_locator, read_particles


def field(grid, path, name, required=True):
    array = grid.GetPointData().GetArray(name)
    if array is None:
        if required:
            sys.exit(f"count_fragments: {path}: no point field '{name}'")
        return None
    return vtk_to_numpy(array).reshape(grid.GetNumberOfPoints(), -1)


def neighbours(x, radius):
    """For each point, the indices of the other points closer than radius."""
    locator = point_locator(x)
    ids = vtk.vtkIdList()
    result = []
    for i, p in enumerate(x):
        locator.FindPointsWithinRadius(radius, p, ids)
        result.append([ids.GetId(k) for k in range(ids.GetNumberOfIds()) if ids.GetId(k) != i])
    return result


def components(links):
    """Connected components of the graph given as adjacency lists: a label per point."""
    label = numpy.full(len(links), -1)
    count = 0
    for start in range(len(links)):
        if label[start] >= 0:
            continue
        label[start] = count
        stack = [start]
        while stack:
            i = stack.pop()
            for j in links[i]:
                if label[j] < 0:
                    label[j] = count
                    stack.append(j)
        count += 1
    return label


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("vtu")
    parser.add_argument("--link", type=float, default=1.5, help="link distance in initial spacings")
    parser.add_argument("--min-size", type=int, default=2, help="smaller pieces count as debris")
    parser.add_argument("--part", type=int, help="only this part's particles (needs part_id)")
    args = parser.parse_args()

    grid = read_particles(args.vtu, "count_fragments")
    x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    x0 = x - field(grid, args.vtu, "displacement")
    v = field(grid, args.vtu, "velocity")
    mass = field(grid, args.vtu, "mass")[:, 0]
    category = field(grid, args.vtu, "category", required=False)
    keep = mass > 0  # SPH particles (other nodes have no SPH mass field)
    if args.part is not None:
        keep &= field(grid, args.vtu, "part_id")[:, 0] == args.part
    if not keep.any():
        sys.exit("count_fragments: no SPH particle selected")
    x, x0, v, mass = x[keep], x0[keep], v[keep], mass[keep]
    category = category[keep, 0] if category is not None else None

    radius = args.link * median_spacing(x0)
    label = components(neighbours(x, radius))
    sizes = numpy.bincount(label)
    order = [k for k in numpy.argsort(-sizes, kind="stable") if sizes[k] >= args.min_size]
    print(f"fragments {len(order)}")
    print(f"debris {int(sizes[sizes < args.min_size].sum())}")
    for rank, k in enumerate(order, start=1):
        members = label == k
        m = mass[members]
        velocity = (m[:, None] * v[members]).sum(axis=0) / m.sum()
        print(f"fragment {rank} particles {int(sizes[k])} mass {m.sum():.6g} "
              f"x0_min {x0[members, 0].min():.6g} x0_max {x0[members, 0].max():.6g} "
              f"x_min {x[members, 0].min():.6g} x_max {x[members, 0].max():.6g} "
              f"velocity {velocity[0]:.6g} {velocity[1]:.6g} {velocity[2]:.6g}")
    initial = neighbours(x0, radius)
    face = numpy.array([any(label[j] != label[i] for j in initial[i]) for i in range(len(x))], bool)
    line = f"crack_face_particles {int(face.sum())}"
    if category is not None:
        line += (f" surface {int((category[face] == 2).sum())} inner_layer {int((category[face] == 1).sum())}"
                 f" interior {int((category[face] == 0).sum())}")
    print(line)


if __name__ == "__main__":
    main()
