#!/usr/bin/python3
"""Wall force and shape of a compression run (tools/make_compression_deck.py) against plasticity.

    /usr/bin/python3 tools/compression_force.py RESULTS --flow A B N [--shape block|cylinder]
                                               [--sticking] [--cslh 1.2]

RESULTS is the run's output folder (rwforc.csv, d3plot.pvd). The flow stress is
sigma_y(eps) = A + B eps^N in the deck's stress unit (B = 0: perfectly plastic). The walls stand
at the bottom and top particle layers, so the wall gap G is the height of the particle centres;
G0 at t = 0 and the wall speed come from the first and last field outputs. The specimen's volume
V0 = sum_b m_b / rho_b = sum_b (h_b / CSLH)^3 (h = CSLH (m / rho)^(1/3), docs/THEORY.md).

For each tenth of the run, averaged over its rwforc.csv rows (the kinematic wall's force is that
of one step, so it is noisy), the table gives the force on each wall and the homogeneous upsetting
force sigma_y(ln(G0/G)) V0/G: exact for frictionless walls (uniform strain eps = ln(G0/G), area
V0/G by constant volume). With --sticking (walls without sliding, cylinder) it also gives the
slab-method force for sticking friction (shear k = sigma_y/sqrt(3) on the faces): the mean face
pressure is sigma_y (1 + 2R/(3 sqrt(3) G)) (e.g. Dieter, Mechanical Metallurgy, ch. 19), an
estimate that is known to run high for D/G below about 2. The final shape: the largest lateral
distance of particle centres from the axis at the walls and at mid-height, over the initial one,
against the homogeneous sqrt(G0/G).
"""
import argparse
import csv
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def series(folder):
    pvd = os.path.join(folder, "d3plot.pvd")
    if not os.path.exists(pvd):
        sys.exit(f"compression_force: {pvd} does not exist (run spall first)")
    entries = sorted((float(d.get("timestep")), os.path.join(folder, d.get("file")))
                     for d in ET.parse(pvd).getroot().iter("DataSet"))
    if len(entries) < 2:
        sys.exit(f"compression_force: {pvd} lists fewer than two files")
    return entries


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    x = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    h = vtk_to_numpy(grid.GetPointData().GetArray("smoothing_length")).astype(float)
    return x, h


def wall_rows(folder):
    path = os.path.join(folder, "rwforc.csv")
    with open(path) as f:
        rows = list(csv.reader(f))[1:]
    walls = {}
    for r in rows:
        walls.setdefault(int(r[1]), []).append((float(r[0]), float(r[2])))
    if len(walls) != 2:
        sys.exit(f"compression_force: {path} has {len(walls)} walls; expected the fixed and the moving one")
    return walls


def lateral_extent(x, shape, axis, band):
    """Largest lateral distance from the axis of particles with z in band."""
    z = x[:, 2]
    sel = (z >= band[0]) & (z <= band[1])
    d = x[sel, :2] - axis
    return float((numpy.hypot(d[:, 0], d[:, 1]) if shape == "cylinder" else numpy.abs(d).max(axis=1)).max())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--flow", type=float, nargs=3, metavar=("A", "B", "N"), required=True)
    parser.add_argument("--shape", choices=["block", "cylinder"], default="block")
    parser.add_argument("--sticking", action="store_true", help="also the slab-method force (cylinder)")
    parser.add_argument("--cslh", type=float, default=1.2)
    args = parser.parse_args()
    if args.sticking and args.shape != "cylinder":
        sys.exit("compression_force: the slab estimate is written for a cylinder")
    A, B, N = args.flow

    def flow_stress(eps):
        return A + B * eps**N

    files = series(args.folder)
    (t0, first), (t1, last) = files[0], files[-1]
    x0, h0 = read(first)
    x1, _ = read(last)
    g0 = x0[:, 2].max() - x0[:, 2].min()
    g1 = x1[:, 2].max() - x1[:, 2].min()
    speed = (g0 - g1) / (t1 - t0)
    volume = float(((h0 / args.cslh) ** 3).sum())
    walls = wall_rows(args.folder)
    moving = max(walls)
    print(f"G0 {g0:.6g}  wall speed {speed:.6g}  volume {volume:.6g}  (deck units)")
    head = "   t        G/G0   eps    F fixed    F moving   sy*V0/G    F/(sy*V0/G)"
    print(head + ("   slab      F/slab" if args.sticking else ""))
    rows = {w: sorted(r) for w, r in walls.items()}
    count = min(len(r) for r in rows.values())
    for k in range(10):
        lo, hi = k * count // 10, (k + 1) * count // 10
        t = numpy.mean([r[0] for r in rows[moving][lo:hi]])
        force = {w: numpy.mean([r[1] for r in rows[w][lo:hi]]) for w in rows}
        gap = g0 - speed * t
        eps = math.log(g0 / gap)
        homogeneous = flow_stress(eps) * volume / gap
        line = (f"{t:10.4g} {gap / g0:6.3f} {eps:6.3f} {force[min(rows)]:10.4g} {force[moving]:10.4g} "
                f"{homogeneous:10.4g} {force[moving] / homogeneous:8.3f}")
        if args.sticking:
            radius = math.sqrt(volume / (math.pi * gap))
            slab = homogeneous * (1 + 2 * radius / (3 * math.sqrt(3) * gap))
            line += f"   {slab:8.4g} {force[moving] / slab:8.3f}"
        print(line)

    # Shape: the axis through the centroid; the layers at the walls and the middle band.
    axis0, axis1 = x0[:, :2].mean(axis=0), x1[:, :2].mean(axis=0)
    layer = g1 / 20
    z_lo, z_hi = x1[:, 2].min(), x1[:, 2].max()
    initial = lateral_extent(x0, args.shape, axis0, (-numpy.inf, numpy.inf))
    bottom = lateral_extent(x1, args.shape, axis1, (z_lo, z_lo + layer))
    top = lateral_extent(x1, args.shape, axis1, (z_hi - layer, z_hi))
    middle = lateral_extent(x1, args.shape, axis1, (0.5 * (z_lo + z_hi) - layer, 0.5 * (z_lo + z_hi) + layer))
    name = "radius" if args.shape == "cylinder" else "half-width"
    print(f"t {t1:.4g}: G/G0 {g1 / g0:.3f}; largest {name} of particle centres over the initial one: "
          f"at the fixed wall {bottom / initial:.3f}, mid-height {middle / initial:.3f}, "
          f"at the moving wall {top / initial:.3f}; homogeneous sqrt(G0/G) {math.sqrt(g0 / g1):.3f}")


if __name__ == "__main__":
    main()
