#!/usr/bin/env python3
"""Writes the free-free elastic bar deck of examples/elastic_bar (SI units: m, s, kg, N, Pa).

A steel bar L x a x a on a cubic lattice of SPH particles, started in its first longitudinal
mode v_x(x) = V cos(pi x / L). Usage: make_bar_deck.py [--spacing DX] [--periods N] > bar.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__)
p.add_argument("--length", type=float, default=1.0)
p.add_argument("--width", type=float, default=0.1)
p.add_argument("--spacing", type=float, default=0.0125)
p.add_argument("--amplitude", type=float, default=1.0, help="V, m/s")
p.add_argument("--periods", type=float, default=2.0)
args = p.parse_args()

rho, E, nu = 7850.0, 200e9, 0.3
c = math.sqrt(E / rho)
period = 2 * args.length / c
nx = round(args.length / args.spacing)
ny = nz = round(args.width / args.spacing)
dx = args.spacing

out = []
w = out.append
w("*KEYWORD")
w("*TITLE")
w(f"Free-free steel bar {args.length} m x {args.width} m x {args.width} m, first longitudinal mode")
w("$ Units: m, s, kg, N, Pa. Bar speed c = sqrt(E/rho) = %.1f m/s; period 2L/c = %.6e s" % (c, period))
w("*CONTROL_TERMINATION")
w("$#  endtim    endcyc     dtmin    endeng    endmas")
w(f"{args.periods * period:10.4e}         0       0.0       0.0       0.0")
w("*CONTROL_TIMESTEP")
w("$#  dtinit    tssfac")
w("       0.0       0.9")
w("*DATABASE_BINARY_D3PLOT")
w("$#      dt")
w(f"{period / 20:10.4e}")
w("*DATABASE_GLSTAT")
w(f"{period / 200:10.4e}")
w("*PART")
w("steel bar")
w("$#     pid     secid       mid")
w("         1         1         1")
w("*SECTION_SPH")
w("$#   secid      cslh      hmin      hmax")
w("         1       1.2       1.0       1.0")
w("*MAT_ELASTIC")
w("$#     mid        ro         e        pr")
w(f"         1{rho:10.1f}{E:10.3e}{nu:10.2f}")
w("*NODE")
nid = 0
coords = []
for k in range(nz):
    for j in range(ny):
        for i in range(nx):
            nid += 1
            x, y, z = (i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx
            coords.append((nid, x))
            w(f"{nid:8d}{x:16.8e}{y:16.8e}{z:16.8e}")
w("*ELEMENT_SPH")
w("$ negative MASS = particle volume; mass = volume * RO")
for n, _ in coords:
    w(f"{n:8d}{1:8d}{-dx**3:16.8e}")
w("*INITIAL_VELOCITY_NODE")
w("$#     nid        vx        vy        vz")
for n, x in coords:
    w(f"{n:10d}{args.amplitude * math.cos(math.pi * x / args.length):10.6f}       0.0       0.0")
w("*END")
print("\n".join(out))
