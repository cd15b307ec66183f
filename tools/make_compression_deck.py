#!/usr/bin/env python3
"""Writes the compression decks of examples/compression_ductile and examples/compression_iron.

A metal specimen stands on a fixed rigid wall (z = 0) and is squeezed by a heavy rigid wall that
moves down from its top face at constant speed (*RIGIDWALL_PLANAR_MOVING: a wall of MASS far above
the specimen's, started at V0, hardly slows down). The scenes of seed 000 (Kayar), Figures 1 and 3:

  --scene ductile   a 10 mm cube of an elastic-perfectly-plastic metal (*MAT_PLASTIC_KINEMATIC,
                    sigma_y 100 MPa), frictionless walls: it stays a cuboid, and the wall force is
                    sigma_y times the current area, A0 H0 / H. Units kg, mm, ms (kN, GPa).
  --scene iron      a cylinder of Armco iron, D0 = H0 = 10 mm (*MAT_PIECEWISE_LINEAR_PLASTICITY,
                    the quasi-static hardening curve sigma_y = A + B eps_p^n of Johnson & Cook
                    1983), walls without sliding (FRIC 1): it barrels, and the wall force exceeds
                    sigma_y A by the friction hill. Units tonne, mm, s (N, MPa).

Usage: make_compression_deck.py --scene ductile|iron [--across N] [--speed V] [--strain E] > deck.k
(--speed in m/s; --strain is the final engineering strain 1 - G/G0 of the wall gap G).

Load and unload (issue 4's residual-stress experiment): --relax T adds T (a fraction of the
squeeze time) after the squeeze, with both walls removed when the squeeze ends (their DEATH): the
block springs back freely, *DAMPING_GLOBAL --damping D (per unit time, in 1/ms) takes its
ringing away (from the end of the squeeze on: a curve), and the residual stress is what stays (residual.csv). --treat 0|1 adds
*SPALL_SPH_COLOUR_FIELD with that TREAT (categories in the output and in residual.csv).
"""
import argparse
import math

# Consistent unit systems (shared/reference/keywords.md §9): the SI size of one unit of mass,
# length and time.
UNITS = {
    "kg-mm-ms": {"mass": 1.0, "length": 1e-3, "time": 1e-3,
                 "text": "kg, mm, ms; force kN, stress GPa, energy J, speed m/s"},
    "t-mm-s": {"mass": 1e3, "length": 1e-3, "time": 1.0,
               "text": "tonne, mm, s; force N, stress MPa, energy mJ, speed mm/s"},
}

# The scenes in SI. Armco iron: Johnson & Cook 1983 (Proc. 7th Int. Symp. on Ballistics, The
# Hague, Table 1): rho 7890 kg/m^3, A 175 MPa, B 380 MPa, n 0.32; E 211 GPa and nu 0.29 are
# handbook values for pure iron.
SCENES = {
    "ductile": {"shape": "block", "units": "kg-mm-ms", "material": "plastic_kinematic",
                "rho": 2700.0, "E": 70e9, "nu": 0.33, "sigma_y": 100e6, "friction": 0.0,
                "title": "Ductile block between a fixed and a moving rigid wall (seed 000 Figure 1)"},
    "iron": {"shape": "cylinder", "units": "t-mm-s", "material": "piecewise_linear",
             "rho": 7890.0, "E": 211e9, "nu": 0.29, "A": 175e6, "B": 380e6, "n": 0.32,
             "friction": 1.0,
             "title": "Iron cylinder upset between a fixed and a moving rigid wall (seed 000 Figure 3)"},
}

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--scene", choices=SCENES, required=True)
p.add_argument("--size", type=float, default=10e-3, help="edge of the cube / D0 = H0 of the cylinder, m")
p.add_argument("--across", type=int, default=16, help="particles across the size (spacing size/N)")
p.add_argument("--speed", type=float, default=20.0, help="speed of the moving wall, m/s")
p.add_argument("--strain", type=float, default=0.4, help="final engineering strain 1 - G/G0 of the wall gap")
p.add_argument("--outputs", type=int, default=20, help="field outputs (VTU files) over the run")
p.add_argument("--relax", type=float, default=0.0,
               help="free relaxation after the squeeze, as a fraction of the squeeze time (walls die)")
p.add_argument("--damping", type=float, default=0.0, help="*DAMPING_GLOBAL VALDMP, 1/ms (with --relax)")
p.add_argument("--treat", type=int, choices=[0, 1], help="add *SPALL_SPH_COLOUR_FIELD with this TREAT")
args = p.parse_args()

scene = SCENES[args.scene]
units = UNITS[scene["units"]]
M, L, T = units["mass"], units["length"], units["time"]


def length(x):
    return x / L


def time(x):
    return x / T


def speed(x):
    return x * T / L


def mass(x):
    return x / M


def density(x):
    return x * L**3 / M


def stress(x):
    return x * L * T**2 / M


size = args.size
dx = size / args.across
# The moving wall's position as the deck writes it; the top layer lies exactly on it (a node
# behind a wall by a rounding error would never be caught), the layers spaced evenly below.
wall_text = f"{length((args.across - 1) * dx):10.6g}"
gap = float(wall_text) * L
dz = gap / (args.across - 1)
squeeze_time = args.strain * gap / args.speed
end_time = squeeze_time * (1 + args.relax)
# The walls die when the squeeze ends if the block is to relax afterwards (0: never, LS-DYNA's
# blank).
death = f"{time(squeeze_time):10.4e}" if args.relax > 0 else "       0.0"
# The specimen on a lattice of spacing dx, its cells filling the size. The walls pass through the
# centres of the bottom and top layers, where the kinematic wall keeps the particles it pushes, so
# that the squeeze starts at once: the wall gap starts at (N - 1) dx.
positions = []
for k in range(args.across):
    for j in range(args.across):
        for i in range(args.across):
            x, y, z = (i + 0.5) * dx, (j + 0.5) * dx, k * dz
            if scene["shape"] == "cylinder":
                x, y = x - size / 2, y - size / 2
                if x * x + y * y >= (size / 2) ** 2:
                    continue
            positions.append((x, y, z))
volume = size**3 if scene["shape"] == "block" else math.pi * size**3 / 4
particle_mass = scene["rho"] * volume / len(positions)
wall_mass = 1e6 * scene["rho"] * volume  # a million times the specimen: slows by < 0.1 %

out = []
w = out.append
w("*KEYWORD")
w("*TITLE")
w(f"{scene['title']}, {len(positions)} particles")
w(f"$ Units: {units['text']}.")
extra = (f" --relax {args.relax:g} --damping {args.damping:g}" if args.relax > 0 else "") + \
    (f" --treat {args.treat}" if args.treat is not None else "")
w(f"$ Generated by tools/make_compression_deck.py --scene {args.scene} --across {args.across} "
  f"--speed {args.speed:g} --strain {args.strain:g}{extra}")
w("*CONTROL_TERMINATION")
w("$#  endtim    endcyc     dtmin    endeng    endmas")
w(f"{time(end_time):10.4e}         0       0.0       0.0       0.0")
w("*CONTROL_TIMESTEP")
w("$#  dtinit    tssfac")
w("       0.0       0.9")
w("*DATABASE_BINARY_D3PLOT")
w(f"{time(end_time / args.outputs):10.4e}")
w("*DATABASE_GLSTAT")
w(f"{time(end_time / 200):10.4e}")
w("*DATABASE_RWFORC")
w(f"{time(end_time / 400):10.4e}")
w("*PART")
w("specimen")
w("$#     pid     secid       mid")
w("         1         1         1")
w("*SECTION_SPH")
w("$#   secid      cslh      hmin      hmax")
w("         1       1.2       0.2       2.0")
rho, E, nu = density(scene["rho"]), stress(scene["E"]), scene["nu"]
if scene["material"] == "plastic_kinematic":
    w("*MAT_PLASTIC_KINEMATIC")
    w("$ elastic-perfectly-plastic (ETAN 0), isotropic (BETA 1)")
    w("$#     mid        ro         e        pr      sigy      etan      beta")
    w(f"         1{rho:10.4e}{E:10.4g}{nu:10.2f}{stress(scene['sigma_y']):10.4g}       0.0       1.0")
else:
    # Johnson & Cook's quasi-static curve at room temperature, sampled at eight plastic strains;
    # MAT_024 interpolates linearly between them and extends the last slope.
    strains = [0.0, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.8]
    flow = [scene["A"] + scene["B"] * e ** scene["n"] for e in strains]
    w("*MAT_PIECEWISE_LINEAR_PLASTICITY")
    w("$ Armco iron, sigma_y = A + B eps_p^n with A 175 MPa, B 380 MPa, n 0.32 (Johnson & Cook 1983)")
    w("$#     mid        ro         e        pr      sigy      etan      fail      tdel")
    w(f"         1{rho:10.4e}{E:10.4g}{nu:10.2f}       0.0       0.0       0.0       0.0")
    w("$#       c         p      lcss      lcsr        vp")
    w("       0.0       0.0         0         0       0.0")
    w("$#    eps1      eps2      eps3      eps4      eps5      eps6      eps7      eps8")
    w("".join(f"{e:10.3f}" for e in strains))
    w("$#     es1       es2       es3       es4       es5       es6       es7       es8")
    w("".join(f"{stress(s):10.4g}" for s in flow))
w("*NODE")
for nid, (x, y, z) in enumerate(positions, start=1):
    w(f"{nid:8d}{length(x):16.8e}{length(y):16.8e}{length(z):16.8e}")
w("*ELEMENT_SPH")
w("$#   nid     pid            mass")
for nid in range(1, len(positions) + 1):
    w(f"{nid:8d}{1:8d}{mass(particle_mass):16.8e}")
fric = f"{scene['friction']:10.1f}"
w("*RIGIDWALL_PLANAR_ID")
w("$#      id     title")
w("         1fixed wall z = 0 (through the bottom layer)")
w("$#    nsid    nsidex     boxid    offset     birth     death     rwksf")
w(f"         0         0         0       0.0       0.0{death}       1.0")
w("$#      xt        yt        zt        xh        yh        zh      fric")
w(f"       0.0       0.0       0.0       0.0       0.0       1.0{fric}")
w("*RIGIDWALL_PLANAR_MOVING_ID")
w("$#      id     title")
w("         2moving wall: starts on the top layer and moves down (its normal -z) at V0")
w("$#    nsid    nsidex     boxid    offset     birth     death     rwksf")
w(f"         0         0         0       0.0       0.0{death}       1.0")
w("$#      xt        yt        zt        xh        yh        zh      fric")
w(f"       0.0       0.0{wall_text}       0.0       0.0{float(wall_text) - 1:10.6g}{fric}")
w("$#    mass        v0")
w(f"{mass(wall_mass):10.4g}{speed(args.speed):10.4g}")
if args.relax > 0 and args.damping > 0:
    # Off while squeezing (a body force -D m v then would add to the wall's load), on once the
    # walls are gone: the curve steps from 0 to D at the end of the squeeze.
    w("*DAMPING_GLOBAL")
    w("$ takes the free block's ringing away after the walls die (mass-weighted, every node)")
    w("$#    lcid    valdmp")
    w("         1       0.0")
    w("*DEFINE_CURVE")
    w("$#    lcid")
    w("         1")
    d = args.damping / time(1e-3)
    for t, value in [(0.0, 0.0), (squeeze_time, 0.0), (1.001 * squeeze_time, d), (10 * end_time, d)]:
        w(f"{time(t):20.8e}{value:20.8e}")
if args.treat is not None:
    w("*SPALL_SPH_COLOUR_FIELD")
    w("$#     pid     treat     nfrac   nthresh    layers  interval")
    w(f"         1{args.treat:10d}       0.8       0.3         1         1")
w("*END")
print("\n".join(out))
