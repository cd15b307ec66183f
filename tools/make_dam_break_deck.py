#!/usr/bin/env python3
"""Writes the dam-break deck of examples/dam_break (SI units: m, s, kg, N, Pa).

The water column of Koshizuka & Oka 1996 (L = 0.146 m wide, 2L high) at the end of a tank 4L
long, released at t = 0 under gravity. The water and the tank walls are *DEFINE_SPH_MESH_BOX
lattices of spacing L / N; the walls (3 layers, part 2) are held by *BOUNDARY_SPC_SET, the
water is part 1; both use *MAT_NULL with *EOS_MURNAGHAN (Tait water, c0 = 10 sqrt(2 g 2L)).

In 3D (default) the tank is --depth deep (default L) between side walls; with --dimension 2
the deck is plane strain in x-y (*CONTROL_SPH IDIM 2, gravity along -y).

Usage: make_dam_break_deck.py [--particles-across N] [--dimension 2|3] [--end-time T] > deck.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--particles-across", type=int, default=16, help="N: particles across the column")
p.add_argument("--dimension", type=int, choices=(2, 3), default=3)
p.add_argument("--column", type=float, default=0.146, help="L, the column width (m)")
p.add_argument("--depth", type=float, default=None, help="3D tank depth (m); default L")
p.add_argument("--end-time", type=float, default=0.5, help="s")
p.add_argument("--output-interval", type=float, default=0.01, help="s between field outputs")
args = p.parse_args()

g = 9.81
L = args.column
n = args.particles_across
dp = L / n
layers = 3  # wall layers: the kernel support is 2 h = 2.6 spacings (CSLH 1.3)
rho0 = 1000.0
c0 = 10 * math.sqrt(2 * g * 2 * L)  # 10 x the free-fall speed from the column top: Mach <= 0.1
gamma = 7.0
k0 = rho0 * c0 * c0 / gamma
tank_x, tank_h = 4 * n, 3 * n  # in spacings
plane = args.dimension == 2
depth_cells = 1 if plane else round((args.depth or L) / dp)

# Boxes as (part, lower corner, cell counts) in lattice cells; the walls come first so that
# their particles take node IDs 1 .. (number of wall particles), for the SPC set.
if plane:
    # x-y plane, y up; one layer in z centred on z = 0 (ZMIN -0.5, ZLEN 1: unit thickness)
    walls = [
        ((-layers, -layers), (tank_x + 2 * layers, layers)),  # floor
        ((-layers, 0), (layers, tank_h)),                     # back wall
        ((tank_x, 0), (layers, tank_h)),                      # front wall
    ]
    water = ((0, 0), (n, 2 * n))
else:
    y0, ny = -layers, depth_cells + 2 * layers
    walls = [
        ((-layers, y0, -layers), (tank_x + 2 * layers, ny, layers)),  # floor
        ((-layers, y0, 0), (layers, ny, tank_h)),                     # back wall
        ((tank_x, y0, 0), (layers, ny, tank_h)),                      # front wall
        ((0, -layers, 0), (tank_x, layers, tank_h)),                  # side wall y < 0
        ((0, depth_cells, 0), (tank_x, layers, tank_h)),              # side wall y > depth
    ]
    water = ((0, 0, 0), (n, depth_cells, 2 * n))


def count(box):
    c = 1
    for k in box[1]:
        c *= k
    return c


n_wall = sum(count(b) for b in walls)
n_water = count(water)

out = []
w = out.append


def card(*fields):
    w("".join(f"{f:>10}" for f in fields))


def length(x):
    """x in six significant digits, or as many as fit a 10-character field (a negative spacing
    of many particles across, -0.00625714, needs 11)."""
    for digits in range(6, 0, -1):
        text = f"{x:.{digits}g}"
        if len(text) <= 10:
            return text
    raise ValueError(f"{x} does not fit a 10-character field")


def box_cards(part, box):
    lower, cells = box
    if plane:
        card(length(lower[0] * dp), length(lower[1] * dp), "-0.5", length(cells[0] * dp), length(cells[1] * dp), "1.0")
        card(part, cells[0], cells[1], 1, "", 0, "0.0")
    else:
        card(*(length(v * dp) for v in lower), *(length(v * dp) for v in cells))
        card(part, *cells, "", 0, "0.0")


w("*KEYWORD")
w("*TITLE")
shape = "plane strain" if plane else f"3D, tank {depth_cells * dp:.4g} m deep"
w(f"Dam break (Koshizuka & Oka 1996): water column {L} m x {2 * L} m, tank {4 * L} m, {shape}")
w(f"$ Units: m, s, kg, N, Pa. Spacing L/{n} = {dp:.6g} m; {n_water} water and {n_wall} wall particles.")
w(f"$ T = t sqrt(2 g / L): t = {math.sqrt(L / (2 * g)):.6g} T s; the front reaches the far wall near T = 3.2.")
w("*CONTROL_TERMINATION")
w("$#  endtim")
card(f"{args.end_time:.4g}")
if plane:
    w("*CONTROL_SPH")
    w("$#    ncbs     boxid        dt      idim   nmneigh      form")
    card("", "", "", 2, "", 0)
w("*CONTROL_BULK_VISCOSITY")
w("$ Monaghan's artificial viscosity: beta = Q1 (LS-DYNA's default 1.5), alpha = Q2")
w("$#      q1        q2")
card("1.5", "0.1")
w("*DATABASE_BINARY_D3PLOT")
card(f"{args.output_interval:.4g}")
w("*DATABASE_GLSTAT")
card(f"{args.output_interval / 10:.4g}")
w("*PART")
w("water")
w("$#     pid     secid       mid     eosid")
card(1, 1, 1, 1)
w("*PART")
w("tank walls: fixed particles of the same liquid (dynamic boundary)")
card(2, 1, 1, 1)
w("*SECTION_SPH")
# h = CSLH x the spacing each part's boxes give; where their lengths, written in 10 characters,
# do not give the water and the walls one spacing to 1e-9 (many particles across), SPHINI sets h.
spacings = [float(length(v * dp)) / v for _, cells in walls + [water] for v in cells]
if max(spacings) - min(spacings) > 1e-10 * dp:
    w("$#   secid      cslh      hmin      hmax    sphini")
    card(1, "1.3", "1.0", "1.0", length(1.3 * dp))
else:
    w("$#   secid      cslh      hmin      hmax")
    card(1, "1.3", "1.0", "1.0")
w("*MAT_NULL")
w("$ PC 0: no tension (a free surface at zero pressure); MU: water")
w("$#     mid        ro        pc        mu")
card(1, f"{rho0:.1f}", "0.0", "1.0e-3")
w("*EOS_MURNAGHAN")
w(f"$ Tait water: K0 = rho0 c0^2 / gamma, c0 = {c0:.4f} m/s")
w("$#   eosid     gamma        k0")
card(1, f"{gamma:.1f}", f"{k0:.6g}")
w("*DEFINE_SPH_MESH_BOX")
w("$#    xmin      ymin      zmin      xlen      ylen      zlen")
w("$#    ipid        nx        ny        nz               idseg      sfsp")
for b in walls:
    box_cards(2, b)
w("*DEFINE_SPH_MESH_BOX")
box_cards(1, water)
w("*SET_NODE_LIST_GENERATE")
w("$ the wall particles: generated first, nodes 1 .. %d" % n_wall)
card(1)
card(1, n_wall)
w("*BOUNDARY_SPC_SET")
w("$#    nsid       cid      dofx      dofy      dofz")
card(1, 0, 1, 1, 1)
w("*DEFINE_CURVE")
card(1)
w(f"{0.0:20.4f}{g:20.4f}")
w(f"{1000.0:20.4f}{g:20.4f}")
w("*LOAD_BODY_Y" if plane else "*LOAD_BODY_Z")
w("$ gravity: a base acceleration of +g along the vertical pulls every particle down")
card(1)
w("*END")
print("\n".join(out))
