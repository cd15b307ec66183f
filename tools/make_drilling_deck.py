#!/usr/bin/env python3
"""Writes the friction-drilling deck of examples/friction_drilling (seed 001 §3; SI units: m, s, kg, N, Pa).

The workpiece is an AISI 304 disk, 18 mm across and 1.5 mm thick, its top face at z = 0: the central
6.4 x 6.4 mm square is SPG (part 1, *SECTION_SOLID_SPG), the rest hexahedral finite elements (part 2,
ELFORM 2) on a ring mesh that shares the square's boundary nodes; the rim is held. Both take
*MAT_JOHNSON_COOK with *EOS_LINEAR_POLYNOMIAL. The tool (part 3) is a rigid friction drill meshed
with tetrahedra, turning about z and plunging along -z through the disk; the workpiece's nodes are
the slave nodes of *CONTACT_AUTOMATIC_NODES_TO_SURFACE against its faces, with Coulomb friction.

Time scaling: the plunge speed is TIME_SCALE times the test's 100 mm/min, and the tool turns so that
its surface moves SPIN_RATIO times faster than it plunges (the test's 3000 rpm is 510 times; with
SPIN_RATIO 0 the spindle speed is sped up by TIME_SCALE too, keeping the feed per revolution: the
README says why that is out of reach). *CONTROL_TIMESTEP DT2MS adds mass where the step is below
|DT2MS|. The run covers the plunge from the tool's tip GAP above the sheet until the start of its
cylindrical part is 0.5 mm below the bottom face.

A structured mesher of its own (no gmsh): the disk is a square lattice with a ring of hexahedra
mapped from the square to the circle, the tool a solid of revolution built from prisms (rings of
triangles stacked along the axis), each cut into three tetrahedra by the lowest-node-ID rule of
Dompierre et al. (1999), which makes neighbouring prisms cut their shared faces alike.

Usage: make_drilling_deck.py [--spacing H] [--mu MU] [--material m1|m2] [...] > drilling.k
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--spacing", type=float, default=0.2e-3, help="SPG nodal spacing in the plane (m)")
p.add_argument("--layers", type=int, default=8, help="element layers through the thickness")
p.add_argument("--ring-layers", type=int, default=6, help="FEM element rings from the square to the rim")
p.add_argument("--material", choices=["m1", "m2"], default="m2",
               help="seed 001's m2: E 193 GPa, yield 205 MPa (efunda); m1: E 207.8 GPa, yield 280 MPa")
p.add_argument("--mu", type=float, default=0.2, help="Coulomb coefficient (FS = FD)")
p.add_argument("--fail-strain", type=float, default=0.4, help="bond failure at this effective plastic strain (FS)")
p.add_argument("--smstep", type=int, default=5,
               help="steps between Eulerian kernel updates (seed 001 Fig. 2's card: 5; its §3 text: 15)")
p.add_argument("--support", type=float, default=1.6, help="normalized support DX = DY = DZ")
p.add_argument("--time-scale", type=float, default=2000.0, help="speed-up of the plunge over the test's")
p.add_argument("--spin-ratio", type=float, default=20.0,
               help="the tool's surface speed over its plunge speed (0: the test's, 510, at every time scale)")
p.add_argument("--dt2ms", type=float, default=-1.0e-7, help="*CONTROL_TIMESTEP DT2MS (0: no mass scaling)")
p.add_argument("--fem-only", action="store_true",
               help="the whole disk in FEM (ELFORM 2) with element erosion at EROSION_STRAIN (seed 001 Fig. 4b)")
p.add_argument("--erosion-strain", type=float, default=0.4, help="*MAT_ADD_EROSION EFFEPS of --fem-only")
p.add_argument("--segments", type=int, default=48, help="tool facets around its axis")
p.add_argument("--outputs", type=int, default=40, help="field outputs over the run")
p.add_argument("--histories", type=int, default=500, help="rcforc/rbdout/spcforc/glstat rows over the run")
args = p.parse_args()

# The test (Krasauskas et al. 2014, as seed 001 §3.1 quotes it): 3000 rpm, 100 mm/min.
RPM, FEED = 3000.0, 100e-3 / 60
DISK_RADIUS, THICKNESS, SQUARE = 9e-3, 1.5e-3, 6.4e-3
GAP = 0.1e-3
# The tool: a friction drill for an M6 form-tapped hole (README: profile and every dimension).
TIP_RADIUS, CENTRE_RADIUS, TOOL_RADIUS = 0.2e-3, 0.6e-3, 2.7e-3
CENTRE_HALF_ANGLE, CONE_HALF_ANGLE = math.radians(45.0), math.radians(18.0)
CYLINDER_LENGTH = 3.0e-3
z_centre = (CENTRE_RADIUS - TIP_RADIUS) / math.tan(CENTRE_HALF_ANGLE)
z_cone = z_centre + (TOOL_RADIUS - CENTRE_RADIUS) / math.tan(CONE_HALF_ANGLE)
z_top = z_cone + CYLINDER_LENGTH
# Travel: from GAP above the sheet until the cylinder's start is 0.5 mm below its bottom face.
TRAVEL = GAP + z_cone + THICKNESS + 0.5e-3

MATERIALS = {"m1": (207.8e9, 280e6), "m2": (193e9, 205e6)}
young, yield_stress = MATERIALS[args.material]
poisson, density = 0.29, 7900.0
shear = young / (2 * (1 + poisson))
bulk = young / (3 * (1 - 2 * poisson))

feed = FEED * args.time_scale
omega = args.spin_ratio * feed / TOOL_RADIUS if args.spin_ratio > 0 else RPM * 2 * math.pi / 60 * args.time_scale
end_time = TRAVEL / feed

out = []
w = out.append


def card(*values, width=10):
    w("".join(f"{v:>{width}}" for v in values))


def real(x):
    """x in a 10-character field."""
    return f"{x:.4e}" if x >= 0 else f"{x:.3e}"


def node(nid, x, y, z):
    w(f"{nid:>8}{x:>16.9g}{y:>16.9g}{z:>16.9g}")


def solid(eid, pid, nodes):
    w(f"{eid:>8}{pid:>8}" + "".join(f"{n:>8}" for n in nodes))


def id_list(ids):
    for k in range(0, len(ids), 8):
        card(*ids[k:k + 8])


# ---- the workpiece -------------------------------------------------------------------------------------
# An odd count of particle spacings across the square, so that no column of particles stands on the
# drill's axis: one under the tip's flat was carried ahead of it, or squeezed until it inverted.
n = 2 * round((SQUARE / args.spacing - 1) / 2) + 1
layers = args.layers
half = SQUARE / 2
z_of = lambda k: -THICKNESS + THICKNESS * k / layers
square_id = lambda i, j, k: 1 + i + (n + 1) * (j + (n + 1) * k)
positions = {}
for k in range(layers + 1):
    for j in range(n + 1):
        for i in range(n + 1):
            positions[square_id(i, j, k)] = (-half + SQUARE * i / n, -half + SQUARE * j / n, z_of(k))

# The square's boundary, counter-clockwise from (-half, -half): 4n lattice points.
boundary = [(i, 0) for i in range(n)] + [(n, j) for j in range(n)] + \
           [(n - i, n) for i in range(n)] + [(0, n - j) for j in range(n)]
around = len(boundary)
rings = args.ring_layers
ring_base = 100001


def ring_id(m, r, k):
    """Node m along the boundary, r rings out (r = 0: the square's own node), layer k."""
    m %= around
    if r == 0:
        return square_id(boundary[m][0], boundary[m][1], k)
    return ring_base + m + around * ((r - 1) + rings * k)


for k in range(layers + 1):
    for m, (i, j) in enumerate(boundary):
        x, y, _ = positions[square_id(i, j, k)]
        reach = math.hypot(x, y)
        for r in range(1, rings + 1):
            s = r / rings
            positions[ring_id(m, r, k)] = ((1 - s) * x + s * DISK_RADIUS * x / reach,
                                           (1 - s) * y + s * DISK_RADIUS * y / reach, z_of(k))


def volume_sign(corners):
    """Sign of the triple product of the hexahedron's edges at its first node (right-handed: positive)."""
    a, b, d, e = (positions[corners[q]] for q in (0, 1, 3, 4))
    u = [b[c] - a[c] for c in range(3)]
    v = [d[c] - a[c] for c in range(3)]
    t = [e[c] - a[c] for c in range(3)]
    return (u[1] * v[2] - u[2] * v[1]) * t[0] + (u[2] * v[0] - u[0] * v[2]) * t[1] + (u[0] * v[1] - u[1] * v[0]) * t[2]


def oriented(bottom, top):
    corners = bottom + top
    return corners if volume_sign(corners) > 0 else bottom[::-1] + top[::-1]


square_elements, ring_elements = [], []
for k in range(layers):
    for j in range(n):
        for i in range(n):
            square_elements.append(oriented([square_id(i, j, k), square_id(i + 1, j, k), square_id(i + 1, j + 1, k),
                                             square_id(i, j + 1, k)],
                                            [square_id(i, j, k + 1), square_id(i + 1, j, k + 1),
                                             square_id(i + 1, j + 1, k + 1), square_id(i, j + 1, k + 1)]))
    for m in range(around):
        for r in range(rings):
            q = lambda kk: [ring_id(m, r, kk), ring_id(m + 1, r, kk), ring_id(m + 1, r + 1, kk), ring_id(m, r + 1, kk)]
            ring_elements.append(oriented(q(k), q(k + 1)))
rim = [ring_id(m, rings, k) for k in range(layers + 1) for m in range(around)]

# ---- the tool --------------------------------------------------------------------------------------------
def tool_radius(h):
    """The tool's radius at height h above its tip."""
    if h <= z_centre:
        return TIP_RADIUS + h * math.tan(CENTRE_HALF_ANGLE)
    if h <= z_cone:
        return CENTRE_RADIUS + (h - z_centre) * math.tan(CONE_HALF_ANGLE)
    return TOOL_RADIUS


# Levels along the axis about 0.25 mm apart on the cone, through the profile's corners; the centre point is
# one level (a contact segment's thickness is its element's volume over its area: thin tetrahedra at the
# tip would let the particles there through, fem-contact.md §2.7).
levels = [0.0]
for start, stop, step in ((0.0, z_centre, z_centre), (z_centre, z_cone, 0.25e-3), (z_cone, z_top, 0.5e-3)):
    count = max(1, round((stop - start) / step))
    levels += [start + (stop - start) * q / count for q in range(1, count + 1)]
segments = args.segments
tool_rings = 1  # every tetrahedron reaches the axis: thick behind each face
tool_base = 200001
tip_height = GAP  # the tip starts GAP above the sheet


def tool_id(level, ring, a):
    """Axis node (ring 0) or node a of ring `ring` at `level`."""
    per_level = 1 + tool_rings * segments
    return tool_base + level * per_level + (0 if ring == 0 else 1 + (ring - 1) * segments + a % segments)


for level, h in enumerate(levels):
    positions[tool_id(level, 0, 0)] = (0.0, 0.0, tip_height + h)
    for ring in range(1, tool_rings + 1):
        radius = tool_radius(h) * ring / tool_rings
        for a in range(segments):
            phi = 2 * math.pi * a / segments
            positions[tool_id(level, ring, a)] = (radius * math.cos(phi), radius * math.sin(phi), tip_height + h)

triangles = []  # of the cross-section, as (ring, a) pairs
for a in range(segments):
    triangles.append(((0, 0), (1, a), (1, a + 1)))
    for ring in range(1, tool_rings):
        triangles.append(((ring, a), (ring + 1, a), (ring + 1, a + 1)))
        triangles.append(((ring, a), (ring + 1, a + 1), (ring, a + 1)))


def tet_volume(t):
    a, b, c, d = (positions[x] for x in t)
    u = [b[q] - a[q] for q in range(3)]
    v = [c[q] - a[q] for q in range(3)]
    s = [d[q] - a[q] for q in range(3)]
    return ((u[1] * v[2] - u[2] * v[1]) * s[0] + (u[2] * v[0] - u[0] * v[2]) * s[1] +
            (u[0] * v[1] - u[1] * v[0]) * s[2]) / 6


def prism_tets(v):
    """Three tetrahedra of the prism v[0:3] (bottom), v[3:6] (top, v[3] over v[0]), cut by the lowest-ID rule."""
    perms = []
    for k in range(3):
        bottom = [k, (k + 1) % 3, (k + 2) % 3]
        top = [3 + x for x in bottom]
        perms += [bottom + top, top + bottom]
    V = [v[q] for q in min(perms, key=lambda perm: v[perm[0]])]
    if min(V[1], V[5]) < min(V[2], V[4]):
        tets = [(V[0], V[1], V[2], V[5]), (V[0], V[1], V[5], V[4]), (V[0], V[4], V[5], V[3])]
    else:
        tets = [(V[0], V[1], V[2], V[4]), (V[0], V[4], V[2], V[5]), (V[0], V[4], V[5], V[3])]
    return [t if tet_volume(t) > 0 else (t[0], t[2], t[1], t[3]) for t in tets]


tool_tets = []
for level in range(len(levels) - 1):
    for tri in triangles:
        bottom = [tool_id(level, ring, a) for ring, a in tri]
        top = [tool_id(level + 1, ring, a) for ring, a in tri]
        tool_tets += prism_tets(bottom + top)

# ---- the deck --------------------------------------------------------------------------------------------
region = "FEM with erosion" if args.fem_only else "SPG centre, FEM ring"
w("*KEYWORD")
w("*TITLE")
w(f"Friction drilling of AISI 304 ({args.material}, {region}), mu {args.mu:g}, time scale {args.time_scale:g}")
w("$ Units: m, s, kg, N, Pa. Generated by tools/make_drilling_deck.py " +
  " ".join(f"--{k.replace('_', '-')}={v}" for k, v in vars(args).items() if not isinstance(v, bool)) +
  (" --fem-only" if args.fem_only else ""))
w(f"$ Plunge {feed * 1e3:g} mm/s, the test's 100 mm/min sped up {args.time_scale:g} times; spindle "
  f"{omega * 60 / (2 * math.pi):.6g} rpm, its surface {omega * TOOL_RADIUS:.4g} m/s "
  f"({omega * TOOL_RADIUS / feed:.4g} x the plunge speed; the test's {RPM:g} rpm: 510 x).")
w("*CONTROL_TERMINATION")
card(real(end_time))
w("*CONTROL_TIMESTEP")
w("$#  dtinit    tssfac      isdo    tslimt     dt2ms")
card("0.0", "0.9", 0, "0.0", real(args.dt2ms) if args.dt2ms else "0.0")
w("*DATABASE_BINARY_D3PLOT")
card(real(end_time / args.outputs))
# SPCFORC: the clamp's reaction, what a dynamometer under the fixture reads; MATSUM: where the work
# goes, the SPG core's and the FEM ring's internal energy and the tool's kinetic energy.
for keyword in ("*DATABASE_GLSTAT", "*DATABASE_RCFORC", "*DATABASE_RBDOUT", "*DATABASE_SPCFORC", "*DATABASE_MATSUM"):
    w(keyword)
    card(real(end_time / args.histories))

w("$ The workpiece: AISI 304, Johnson-Cook (A the seed's yield; B n C m from the AISI 304 machining set")
w("$ of shared/reference/spg.md §8.2, placeholders) with a linear EOS of bulk modulus K = E / (3 (1 - 2 nu)).")
w("*MAT_JOHNSON_COOK")
w("$#     mid        ro         g         e        pr")
card(1, real(density), real(shear), real(young), f"{poisson:g}")
w("$#       a         b         n         c         m        tm        tr      epso")
card(real(yield_stress), real(1000e6), "0.65", "0.07", "1.0", "1673.0", "293.0", "1.0")
w("$#      cp        pc     spall        it        d1        d2        d3        d4")
card("500.0", "-1.0e20", "2.0", "0.0", "0.0", "0.0", "0.0", "0.0")
w("$#      d5")
card("0.0")
w("*EOS_LINEAR_POLYNOMIAL")
w("$#   eosid        c0        c1")
card(1, "0.0", real(bulk))

w("*PART")
w("workpiece centre" + (" (FEM)" if args.fem_only else " (SPG)"))
card(1, 1, 1, 1)
if args.fem_only:
    w("*SECTION_SOLID")
    card(1, 2)
    w("*MAT_ADD_EROSION")
    w("$#     mid      excl    mxpres     mneps    effeps    voleps    numfip       ncs")
    card(1, "0.0", "0.0", "0.0", f"{args.erosion_strain:g}", "0.0", 1, 1)
else:
    w("*SECTION_SOLID_SPG")
    w("$#   secid    elform       aet")
    card(1, 47, 0)
    w("$#      dx        dy        dz   ispline    kernel    lscale    smstep")
    w("$ KERNEL 1: the Eulerian kernel, updated every SMSTEP steps (seed 001 Fig. 2)")
    card(f"{args.support:g}", f"{args.support:g}", f"{args.support:g}", 0, 1, "", args.smstep)
    w("$#    idam        fs   stretch       itb")
    w("$ bonds fail at the effective plastic strain FS and a stretch above the seed's Fig. 2 STRETCH")
    card(1, f"{args.fail_strain:g}", "1.25", 1)
w("*PART")
w("workpiece ring (FEM)")
card(2, 2, 1, 1)
w("*SECTION_SOLID")
card(2, 2)

w("$ The tool: a rigid friction drill (tetrahedra); x, y and the tilts held, the plunge and the spin prescribed.")
w("*PART")
w("friction drill")
card(3, 3, 3)
w("*SECTION_SOLID")
card(3, 10)
w("*MAT_RIGID")
w("$#     mid        ro         e        pr")
w("$ tungsten carbide (placeholders: E and PR set the contact stiffness of its faces)")
card(3, "14500.0", "6.0e11", "0.22")
w("$#     cmo      con1      con2")
card("1.0", 4, 4)

w("*NODE")
for nid in sorted(positions):
    node(nid, *positions[nid])
w("*ELEMENT_SOLID")
eid = 1
for corners in square_elements:
    solid(eid, 1, corners)
    eid += 1
eid = 100001
for corners in ring_elements:
    solid(eid, 2, corners)
    eid += 1
eid = 200001
for t in tool_tets:
    solid(eid, 3, list(t) + [t[3]] * 4)
    eid += 1

w("$ The rim is clamped.")
w("*SET_NODE_LIST")
card(1)
id_list(rim)
w("*BOUNDARY_SPC_SET")
w("$#    nsid       cid      dofx      dofy      dofz     dofrx     dofry     dofrz")
card(1, 0, 1, 1, 1, 1, 1, 1)

w("$ Plunge (velocity along -z) and spindle speed (rad/s about z), constant from the start.")
w("*DEFINE_CURVE")
card(1)
card(real(0.0), real(-feed), width=20)
card(real(10 * end_time), real(-feed), width=20)
w("*DEFINE_CURVE")
card(2)
card(real(0.0), real(omega), width=20)
card(real(10 * end_time), real(omega), width=20)
w("*BOUNDARY_PRESCRIBED_MOTION_RIGID")
w("$#     pid       dof       vad      lcid        sf")
card(3, 3, 0, 1, "1.0")
w("*BOUNDARY_PRESCRIBED_MOTION_RIGID")
card(3, 7, 0, 2, "1.0")

w("$ The workpiece's nodes (both parts) are the slave nodes, the drill's faces the segments.")
w("*SET_PART_LIST")
card(1)
card(1, 2)
w("*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID")
w("$#     cid")
card(1)
w("$#   surfa     surfb  surfatyp  surfbtyp")
card(1, 3, 2, 3)
w("$#      fs        fd        dc        vc       vdc")
card(f"{args.mu:g}", f"{args.mu:g}", "0.0", "0.0", "20.0")
w("$#    sfsa      sfsb")
card("1.0", "1.0")
w("$#    soft    sofscl")
card(1, "0.1")
w("$#  penmax")
w("$ Nodes are let go one segment thickness deep (default 0.4): the drill is solid, a node inside is to be")
w("$ pushed out; with 0.4 the tip ran over the particles on its axis.")
card("1.0")
w("$ Moments about the drill's tip node, on its axis: the torque is the z moment of side 2.")
w("*DATABASE_RCFORC_MOMENT")
w("$#     cid    nodesa    nodesb")
card(1, 0, tool_id(0, 0, 0))
w("*END")
print("\n".join(out))
