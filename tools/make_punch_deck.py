#!/usr/bin/env python3
"""Writes the rotating-punch deck of examples/punch_rotation (SI units: m, s, kg, N, Pa).

A rigid flat-ended cylindrical punch (part 2, *MAT_RIGID steel, radius R, meshed as a square grid
mapped onto the disc) is pressed into an SPG block of 6061-T6 aluminium (part 1,
*SECTION_SOLID_SPG, *MAT_PLASTIC_KINEMATIC, its bottom held) while it turns at 3000 rpm, seed 001's
spindle speed: it plunges to DEPTH at SPEED, then holds its depth and keeps turning. The punch
touches the block through *CONTACT_AUTOMATIC_NODES_TO_SURFACE (the block's particles are the slave
nodes, the punch's faces the segments) with Coulomb friction MU and the soft-constraint penalty
(SOFT 1) that fem-contact.md recommends for a rigid tool on a soft workpiece. The torque on the
punch comes from friction alone; rcforc.csv has it (side 2, about the middle of the punch's face,
*DATABASE_RCFORC_MOMENT).
Usage: make_punch_deck.py [--spacing H] [--mu MU] [--end-time T] > punch.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__)
p.add_argument("--block", type=float, default=12e-3, help="the block's width and length")
p.add_argument("--height", type=float, default=4e-3, help="the block's height")
p.add_argument("--spacing", type=float, default=0.5e-3, help="the block's element size")
p.add_argument("--radius", type=float, default=2e-3, help="the punch's radius R")
p.add_argument("--mu", type=float, default=0.2, help="Coulomb coefficient")
p.add_argument("--depth", type=float, default=0.2e-3, help="how far the punch goes into the block")
p.add_argument("--speed", type=float, default=5.0, help="plunge speed, m/s")
p.add_argument("--rpm", type=float, default=3000.0)
p.add_argument("--end-time", type=float, default=2e-4)
p.add_argument("--outputs", type=int, default=20, help="field outputs over the run")
args = p.parse_args()

nx = round(args.block / args.spacing)
nz = round(args.height / args.spacing)
out = []
w = out.append


def card(*values, width=10):
    w("".join(f"{v:>{width}}" for v in values))


def node(nid, x, y, z):
    w(f"{nid:>8}{x:>16.8g}{y:>16.8g}{z:>16.8g}")


def lattice(part, first_node, first_element, cells, place):
    """A structured mesh of hexahedra of `part`: lattice point (i, j, k) at place(i, j, k); returns its node IDs."""
    cx, cy, cz = cells
    nid = lambda i, j, k: first_node + i + (cx + 1) * (j + (cy + 1) * k)
    w("*NODE")
    for k in range(cz + 1):
        for j in range(cy + 1):
            for i in range(cx + 1):
                node(nid(i, j, k), *place(i, j, k))
    w("*ELEMENT_SOLID")
    eid = first_element
    for k in range(cz):
        for j in range(cy):
            for i in range(cx):
                corners = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                           nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
                w(f"{eid:>8}{part:>8}" + "".join(f"{c:>8}" for c in corners))
                eid += 1
    return nid


omega = args.rpm * 2 * math.pi / 60
plunge_time = args.depth / args.speed
w("*KEYWORD")
w("*TITLE")
w(f"Rigid punch R = {args.radius*1e3:g} mm turning at {args.rpm:g} rpm pressed {args.depth*1e3:g} mm into an SPG "
  f"aluminium block, mu = {args.mu:g}")
w("$ Units: m, s, kg, N, Pa.")
w("*CONTROL_TERMINATION")
card(f"{args.end_time:.4e}")
w("*DATABASE_BINARY_D3PLOT")
card(f"{args.end_time / args.outputs:.4e}")
w("*DATABASE_GLSTAT")
card(f"{args.end_time / 200:.4e}")
w("*DATABASE_RCFORC")
card(f"{args.end_time / 200:.4e}")

w("$ The block: SPG particles on a hexahedral mesh, its bottom held.")
w("*PART")
w("block")
card(1, 1, 1)
w("*SECTION_SOLID_SPG")
w("$#   secid    elform       aet")
card(1, 47, 0)
w("$#      dx        dy        dz   ispline    kernel    lscale    smstep")
card("1.6", "1.6", "1.6", 0, 0, "", 15)
w("$#    idam        fs   stretch       itb")
w("$ no bond failure: the punch dents the block, it does not cut it")
card(1, "10.0", "1.0", 1)
w("*MAT_PLASTIC_KINEMATIC")
w("$#     mid        ro         e        pr      sigy      etan      beta")
w("$ 6061-T6 aluminium, bilinear isotropic hardening")
card(1, "2700.0", "6.9e10", "0.33", "2.76e8", "6.9e8", "1.0")
nid = lattice(1, 1, 1, (nx, nx, nz),
              lambda i, j, k: (args.block * (i / nx - 0.5), args.block * (j / nx - 0.5), args.height * (k / nz - 1)))
w("*SET_NODE_LIST")
card(1)
bottom = [nid(i, j, 0) for j in range(nx + 1) for i in range(nx + 1)]
for k in range(0, len(bottom), 8):
    card(*bottom[k:k + 8])
w("*BOUNDARY_SPC_SET")
w("$#    nsid       cid      dofx      dofy      dofz     dofrx     dofry     dofrz")
card(1, 0, 1, 1, 1, 1, 1, 1)

w("$ The punch: rigid, its face on the block's top at z = 0; x, y and the tilts held (CMO 1).")
w("*PART")
w("punch")
card(2, 2, 2)
w("*SECTION_SOLID")
card(2, 1)
w("*MAT_RIGID")
w("$#     mid        ro         e        pr         n    couple         m     alias")
card(2, "7850.0", "2.0e11", "0.3")
w("$#     cmo      con1      con2")
card("1.0", 4, 4)
n = 8
layers = 4
length = 3e-3


def disc(i, j, k):
    u, v = 2 * i / n - 1, 2 * j / n - 1
    return args.radius * u * math.sqrt(1 - v * v / 2), args.radius * v * math.sqrt(1 - u * u / 2), length * k / layers


punch = lattice(2, 100001, 100001, (n, n, layers), disc)
w("$ The plunge (z displacement) and the spindle speed (rad/s about z).")
w("*DEFINE_CURVE")
card(1)
for t, z in [(0.0, 0.0), (plunge_time, -args.depth), (1.0, -args.depth)]:
    card(f"{t:.6e}", f"{z:.6e}", width=20)
w("*DEFINE_CURVE")
card(2)
for t in (0.0, 1.0):
    card(f"{t:.6e}", f"{omega:.6e}", width=20)
w("*BOUNDARY_PRESCRIBED_MOTION_RIGID")
w("$#     pid       dof       vad      lcid        sf")
card(2, 3, 2, 1, "1.0")
w("*BOUNDARY_PRESCRIBED_MOTION_RIGID")
card(2, 7, 0, 2, "1.0")

w("*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID")
w("$#     cid                                                                 heading")
card(1, width=10)
w("$#   surfa     surfb  surfatyp  surfbtyp")
card(1, 2, 3, 3)
w("$#      fs        fd        dc        vc       vdc")
card(f"{args.mu:g}", f"{args.mu:g}", "0.0", "0.0", "20.0")
w("$#    sfsa      sfsb")
card("1.0", "1.0")
w("$#    soft    sofscl")
card(1, "0.1")
w("$ Moments of the punch's side about the node at the middle of its face, on its axis.")
w("*DATABASE_RCFORC_MOMENT")
w("$#     cid    nodesa    nodesb")
card(1, 0, punch(n // 2, n // 2, 0))
w("*END")
print("\n".join(out))
