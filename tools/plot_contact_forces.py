#!/usr/bin/env python3
"""Plots a contact's force and torque histories from a run's rcforc.csv (docs/OUTPUT.md).

For one contact and side (2, the segments: the tool, by default): the contact force on that side
along an axis (for a tool fed along -z, +Fz is the thrust the workpiece pushes back with) and the
moment about that axis through the side's reference point (the tool's centre): the torque the
workpiece puts on the tool, against its turning. Prints the mean over the last quarter of the run, and the ratio
T / (mu F R) when --mu and --radius are given (2/3 for a flat face under uniform pressure).
Run with Debian's interpreter (matplotlib): /usr/bin/python3 tools/plot_contact_forces.py RUN_DIR -o out.png
"""
import argparse
import csv
import os
import sys

p = argparse.ArgumentParser(description=__doc__)
p.add_argument("run", help="a run's output folder (with rcforc.csv) or the file itself")
p.add_argument("--contact", type=int, default=1)
p.add_argument("--side", type=int, default=2, help="1 SURFA (the nodes), 2 SURFB (the segments)")
p.add_argument("--axis", choices="xyz", default="z")
p.add_argument("--mu", type=float, help="Coulomb coefficient, for T / (mu F R)")
p.add_argument("--radius", type=float, help="the tool's radius R, for T / (mu F R)")
p.add_argument("--time-unit", choices=["s", "ms", "us"], default="us")
p.add_argument("-o", "--output", help="PNG to write (none: only the numbers)")
args = p.parse_args()

path = os.path.join(args.run, "rcforc.csv") if os.path.isdir(args.run) else args.run
if not os.path.exists(path):
    sys.exit(f"{path}: no such file (a run writes rcforc.csv only when its deck has contacts)")
with open(path, newline="") as f:
    reader = csv.reader(f)
    header = [h.split(" [")[0] for h in next(reader)]
    rows = [dict(zip(header, map(float, r))) for r in reader]
rows = [r for r in rows if int(r["contact"]) == args.contact and int(r["side"]) == args.side]
if not rows:
    sys.exit(f"{path}: no rows for contact {args.contact}, side {args.side}")
time = [r["time"] for r in rows]
thrust = [r["f" + args.axis] for r in rows]
torque = [r["m" + args.axis] for r in rows]

tail = [k for k, t in enumerate(time) if t >= 0.75 * time[-1]]
mean_thrust = sum(thrust[k] for k in tail) / len(tail)
mean_torque = sum(torque[k] for k in tail) / len(tail)
print(f"last quarter: F{args.axis} {mean_thrust:.6g} N, M{args.axis} {mean_torque:.6g} N m")
if args.mu and args.radius:
    print(f"T / (mu F R) = {abs(mean_torque / (args.mu * mean_thrust * args.radius)):.4f} (2/3 for uniform pressure)")

if args.output:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scale = {"s": 1.0, "ms": 1e3, "us": 1e6}[args.time_unit]
    t = [x * scale for x in time]
    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.2))
    a.plot(t, thrust, color="tab:blue")
    a.set_ylabel(f"force F{args.axis} (N)")
    b.plot(t, torque, color="tab:red")
    b.set_ylabel(f"moment M{args.axis} (N m)")
    b.set_xlabel(f"time ({'µs' if args.time_unit == 'us' else args.time_unit})")
    for ax in (a, b):
        ax.grid(alpha=0.3)
    a.set_title(f"contact {args.contact}, side {args.side}")
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")
