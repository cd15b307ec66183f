#!/usr/bin/env python3
"""Writes the Taylor bar deck of examples/taylor_bar (SI units: m, s, kg, N, Pa, K).

Wilkins & Guinan 1973 (J. Appl. Phys. 44:1200), test 1: an OFHC copper rod, L0 = 23.47 mm,
D0 = 7.62 mm, hits a rigid frictionless wall at 210 m/s; Johnson & Cook's 1983 constants for
OFHC copper (shared/reference/validation.md §1(b)). The same scene as tests/support/taylor_bar.hpp:
a square lattice of spacing D0/N cut to the rod's circle, round(L0/dx) layers spread evenly over
L0, equal masses adding up to the rod's mass, the wall at z = 0 with the rod above it.

Usage: make_taylor_bar_deck.py [--across N] [--end-time T] > taylor_bar.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--across", type=int, default=10, help="particles across the diameter (spacing D0/N)")
p.add_argument("--end-time", type=float, default=80e-6, help="s; the rod is at rest by about 70 us")
p.add_argument("--outputs", type=int, default=16, help="field outputs (VTU files) over the run")
args = p.parse_args()

length, diameter, speed = 23.47e-3, 7.62e-3, 210.0
# OFHC copper, Johnson & Cook 1983.
rho, E, nu = 8960.0, 124e9, 0.34
G = E / (2 * (1 + nu))
A, B, n, C, m = 90e6, 292e6, 0.31, 0.025, 1.09
Tm, Tr, epso, cp = 1356.0, 298.0, 1.0, 383.0
pc = -1.0e9  # tension cut at 1 GPa (about copper's spall strength); not reached in this test

dx = diameter / args.across
radius = diameter / 2
layers = round(length / dx)
positions = []
for k in range(layers):
    for j in range(args.across):
        for i in range(args.across):
            x, y = (i + 0.5) * dx - radius, (j + 0.5) * dx - radius
            if x * x + y * y < radius * radius:
                positions.append((x, y, (k + 0.5) * length / layers))
mass = rho * math.pi * radius**2 * length / len(positions)

out = []
w = out.append
w("*KEYWORD")
w("*TITLE")
w(f"Taylor bar, Wilkins & Guinan 1973 test 1: OFHC copper, 210 m/s, D0/{args.across}, {len(positions)} particles")
w("$ Units: m, s, kg, N, Pa, K (SI). L0 23.47 mm, D0 7.62 mm; measured L/L0 0.630, R/R0 2.204.")
w("*CONTROL_TERMINATION")
w("$#  endtim    endcyc     dtmin    endeng    endmas")
w(f"{args.end_time:10.4e}         0       0.0       0.0       0.0")
w("*CONTROL_TIMESTEP")
w("$#  dtinit    tssfac")
w("       0.0       0.9")
w("*DATABASE_BINARY_D3PLOT")
w("$#      dt")
w(f"{args.end_time / args.outputs:10.4e}")
w("*DATABASE_GLSTAT")
w(f"{args.end_time / 400:10.4e}")
w("*DATABASE_RWFORC")
w(f"{args.end_time / 400:10.4e}")
w("*PART")
w("copper rod")
w("$#     pid     secid       mid")
w("         1         1         1")
w("*SECTION_SPH")
w("$#   secid      cslh      hmin      hmax")
w("         1       1.2       0.2       2.0")
w("*MAT_JOHNSON_COOK")
w("$#     mid        ro         g         e        pr")
w(f"         1{rho:10.1f}{G:10.4e}{E:10.3e}{nu:10.2f}")
w("$#       a         b         n         c         m        tm        tr      epso")
w(f"{A:10.3e}{B:10.3e}{n:10.2f}{C:10.3f}{m:10.2f}{Tm:10.1f}{Tr:10.1f}{epso:10.1f}")
w("$#      cp        pc     spall")
w(f"{cp:10.1f}{pc:10.2e}         1")
w("*NODE")
for nid, (x, y, z) in enumerate(positions, start=1):
    w(f"{nid:8d}{x:16.8e}{y:16.8e}{z:16.8e}")
w("*ELEMENT_SPH")
w("$#   nid     pid            mass")
for nid in range(1, len(positions) + 1):
    w(f"{nid:8d}{1:8d}{mass:16.8e}")
w("*INITIAL_VELOCITY")
w("$#    nsid    nsidex     boxid")
w("         0         0         0")
w("$#      vx        vy        vz")
w(f"       0.0       0.0{-speed:10.1f}")
w("*RIGIDWALL_PLANAR")
w("$ the plane z = 0, normal +z towards the rod, frictionless; every node is tracked")
w("$#    nsid    nsidex     boxid    offset     birth     death     rwksf")
w("         0         0         0       0.0       0.0       0.0       1.0")
w("$#      xt        yt        zt        xh        yh        zh      fric")
w("       0.0       0.0       0.0       0.0       0.0       1.0       0.0")
w("*END")
print("\n".join(out))
