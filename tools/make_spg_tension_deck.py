#!/usr/bin/env python3
"""Writes the SPG tensile-bar deck of examples/spg_tension (SI units: m, s, kg, N, Pa).

A 4340 steel bar L x W x W (default 10 x 2 x 2 mm) meshed with hexahedra and run as SPG particles
(*SECTION_SOLID_SPG: DX 1.6, updated-Lagrangian kernel, bond failure at FS 0.6 with STRETCH 1.2),
Johnson-Cook plasticity (Johnson & Cook 1985 constants for 4340 steel), both end faces pulled
apart at V each. The section narrows by 3 % towards the middle (a cosine taper) so that the neck
forms there. With --fem-ends F, the elements within F L of either end are hexahedral finite
elements instead (part 2, *SECTION_SOLID ELFORM 2, the same material), sharing their interface
nodes with the SPG middle: seed 001's FEM region around an SPG core (examples/fem_spg_bar).
Usage: make_spg_tension_deck.py [--elements N] [--speed V] [--end-time T] [--fem-ends F] > bar.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__)
p.add_argument("--length", type=float, default=10e-3)
p.add_argument("--width", type=float, default=2e-3)
p.add_argument("--elements", type=int, default=30, help="elements along the bar; W/L of that across")
p.add_argument("--speed", type=float, default=10.0, help="V, m/s at each end")
p.add_argument("--end-time", type=float, default=1.6e-4)
p.add_argument("--taper", type=float, default=0.03)
p.add_argument("--fem-ends", type=float, default=0.0, help="fraction of the length at each end as finite elements")
args = p.parse_args()

L, W = args.length, args.width
nx = args.elements
ny = nz = max(2, round(nx * W / L))

out = []
w = out.append
w("*KEYWORD")
w("*TITLE")
kind = "FEM ends on an SPG" if args.fem_ends > 0 else "SPG"
w(f"{kind} tensile bar, 4340 steel (Johnson-Cook), {L*1e3:g} x {W*1e3:g} x {W*1e3:g} mm, ends pulled at {args.speed:g} m/s")
w("$ Units: m, s, kg, N, Pa.")
w("*CONTROL_TERMINATION")
w("$#  endtim")
w(f"{args.end_time:10.4e}")
w("*CONTROL_TIMESTEP")
w("$#  dtinit    tssfac")
w("       0.0       0.9")
w("*DATABASE_BINARY_D3PLOT")
w(f"{args.end_time / 40:10.4e}")
w("*DATABASE_GLSTAT")
w(f"{args.end_time / 400:10.4e}")
w("*PART")
w("tensile bar")
w("$#     pid     secid       mid")
w("         1         1         1")
if args.fem_ends > 0:
    w("*PART")
    w("finite-element ends")
    w("$#     pid     secid       mid")
    w("         2         2         1")
    w("*SECTION_SOLID")
    w("$#   secid    elform")
    w("         2         2")
w("*SECTION_SOLID_SPG")
w("$#   secid    elform       aet")
w("         1        47         0")
w("$#      dx        dy        dz   ispline    kernel    unused    smstep       msc")
w("       1.6       1.6       1.6         0         0       0.0        15       0.0")
w("$#    idam        fs   stretch       itb     msfac       isc     boxid     pdamp")
w("         1       0.6       1.2         1")
w("*MAT_JOHNSON_COOK")
w("$#     mid        ro         g         e        pr")
w("         1    7830.0   7.70e10   2.00e11      0.29")
w("$#       a         b         n         c         m        tm        tr      epso")
w("   7.92e08   5.10e08      0.26     0.014      1.03    1793.0     293.0       1.0")
w("$#      cp        pc     spall        it        d1        d2        d3        d4")
w("     477.0    -1.e20       2.0       0.0       0.0       0.0       0.0       0.0")
w("$#      d5")
w("       0.0")
w("*NODE")


def node_id(i, j, k):
    return 1 + i + (nx + 1) * (j + (ny + 1) * k)


for k in range(nz + 1):
    for j in range(ny + 1):
        for i in range(nx + 1):
            x = L * i / nx
            s = 1 - args.taper * 0.5 * (1 + math.cos(2 * math.pi * (x / L - 0.5)))
            y = W / 2 + (W * j / ny - W / 2) * s
            z = W / 2 + (W * k / nz - W / 2) * s
            w(f"{node_id(i, j, k):8d}{x:16.8e}{y:16.8e}{z:16.8e}")
w("*ELEMENT_SOLID")
eid = 0
for k in range(nz):
    for j in range(ny):
        for i in range(nx):
            eid += 1
            n = [node_id(i, j, k), node_id(i + 1, j, k), node_id(i + 1, j + 1, k), node_id(i, j + 1, k),
                 node_id(i, j, k + 1), node_id(i + 1, j, k + 1), node_id(i + 1, j + 1, k + 1), node_id(i, j + 1, k + 1)]
            centre = L * (i + 0.5) / nx
            pid = 2 if min(centre, L - centre) < args.fem_ends * L else 1
            w(f"{eid:8d}{pid:8d}" + "".join(f"{m:8d}" for m in n))
for sid, i in ((1, 0), (2, nx)):
    w("*SET_NODE_LIST")
    w(f"{sid:10d}")
    ids = [node_id(i, j, k) for k in range(nz + 1) for j in range(ny + 1)]
    for a in range(0, len(ids), 8):
        w("".join(f"{m:10d}" for m in ids[a:a + 8]))
w("*DEFINE_CURVE")
w("$#    lcid")
w("         1")
w("$ velocity ramped up over 10 us, then held")
w(f"{0.0:20.6e}{0.0:20.6e}")
w(f"{1e-5:20.6e}{1.0:20.6e}")
w(f"{1.0:20.6e}{1.0:20.6e}")
for sid, sign in ((1, -1), (2, 1)):
    w("*BOUNDARY_PRESCRIBED_MOTION_SET")
    w("$#    nsid       dof       vad      lcid        sf")
    w(f"{sid:10d}         1         0         1{sign * args.speed:10.3f}")
w("*END")
print("\n".join(out))
