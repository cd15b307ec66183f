#!/usr/bin/env python3
"""Thrust force and torque of friction-drilling runs (examples/friction_drilling), against the plunge depth.

From each run's rcforc.csv (contact 1, side 2: the drill) and rbdout.csv (the drill's centre): the
thrust F = Fz, the force the workpiece pushes the drill back with (+ when it resists the plunge), and
the torque T = -Mz about the drill's axis, the moment the workpiece puts on the drill against its
turning (seed 001 §3.2: from friction alone); the depth is how far the drill's tip is below the top
face, from the drill's travel since the start minus its start height GAP. rcforc holds the force of
single steps, which rings as the drill meets particle after particle, so both are averaged over
WINDOW of depth (a moving box filter, as LS-DYNA users filter rcforc).
Prints per run: the peak thrust and peak torque of the averaged curves, and the mean torque over the
last fifth of the plunge ("steady"); with --csv, writes the averaged histories; with -o, plots them
(seed 001 Fig. 4a), with the test's 2.5 N m marked.
The numbers need only the standard library; the plot needs matplotlib (Debian: /usr/bin/python3).
Usage: drilling_forces.py RUN [RUN ...] [--label L ...] [--csv out.csv] [-o out.png]
"""
import argparse
import csv
import os
import sys

TEST_TORQUE = 2.5  # N m, Krasauskas et al. (2014) as seed 001 §3.2 quotes it

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("runs", nargs="+", help="run output folders (with rcforc.csv and rbdout.csv)")
p.add_argument("--label", action="append", help="a label per run, in order (default: the folder's name)")
p.add_argument("--gap", type=float, default=0.1e-3, help="the tip's start height above the sheet (m)")
p.add_argument("--window", type=float, default=0.25e-3, help="depth over which the forces are averaged (m)")
p.add_argument("--csv", help="write the averaged histories here")
p.add_argument("--title", default="")
p.add_argument("-o", "--output", help="PNG to write")
args = p.parse_intermixed_args()  # RUN --label L RUN --label L ...
labels = args.label or [os.path.basename(os.path.normpath(r)) for r in args.runs]
if len(labels) != len(args.runs):
    sys.exit("give one --label per run")


def read(path):
    if not os.path.exists(path):
        sys.exit(f"{path}: no such file")
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = [h.split(" [")[0] for h in next(reader)]
        return [dict(zip(header, map(float, row))) for row in reader]


def history(run):
    """(depth, thrust, torque) per rcforc row of the drill's side."""
    forces = [r for r in read(os.path.join(run, "rcforc.csv")) if r["contact"] == 1 and r["side"] == 2]
    bodies = read(os.path.join(run, "rbdout.csv"))
    z0 = bodies[0]["z"]
    height = {r["time"]: r["z"] for r in bodies}
    rows = []
    for r in forces:
        z = height.get(r["time"])
        if z is None:  # rbdout at another interval: the nearest earlier row
            z = min(bodies, key=lambda b: (abs(b["time"] - r["time"])))["z"]
        rows.append((z0 - z - args.gap, r["fz"], -r["mz"]))
    return rows


def averaged(rows):
    """The box average over `window` of depth, centred on each row."""
    out = []
    lo = hi = 0
    total_f = total_t = 0.0
    for depth, _, _ in rows:
        while hi < len(rows) and rows[hi][0] <= depth + args.window / 2:
            total_f += rows[hi][1]
            total_t += rows[hi][2]
            hi += 1
        while rows[lo][0] < depth - args.window / 2:
            total_f -= rows[lo][1]
            total_t -= rows[lo][2]
            lo += 1
        n = hi - lo
        out.append((depth, total_f / n, total_t / n))
    return out


curves = []
for run, label in zip(args.runs, labels):
    rows = averaged(history(run))
    inside = [r for r in rows if r[0] > 0]
    if not inside:
        sys.exit(f"{run}: the drill never reached the sheet")
    peak_f = max(inside, key=lambda r: r[1])
    peak_t = max(inside, key=lambda r: r[2])
    last = [r for r in inside if r[0] >= 0.8 * inside[-1][0]]
    steady = sum(r[2] for r in last) / len(last)
    print(f"{label}: peak thrust {peak_f[1]:.4g} N at {peak_f[0] * 1e3:.3g} mm, peak torque {peak_t[2]:.4g} N m at "
          f"{peak_t[0] * 1e3:.3g} mm, steady torque {steady:.4g} N m (test {TEST_TORQUE} N m), "
          f"mean torque {sum(r[2] for r in inside) / len(inside):.4g} N m, mean thrust "
          f"{sum(r[1] for r in inside) / len(inside):.4g} N")
    curves.append((label, rows))

if args.csv:
    with open(args.csv, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["run", "depth [m]", "thrust [N]", "torque [N m]"])
        for label, rows in curves:
            for depth, thrust, torque in rows:
                out.writerow([label, f"{depth:.6e}", f"{thrust:.6e}", f"{torque:.6e}"])
    print(f"wrote {args.csv}")

if args.output:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.6))
    for label, rows in curves:
        depth = [r[0] * 1e3 for r in rows]
        a.plot(depth, [r[1] for r in rows], label=label)
        b.plot(depth, [r[2] for r in rows], label=label)
    b.axhline(TEST_TORQUE, color="k", ls="--", lw=1, label=f"test, {TEST_TORQUE} N m")
    a.set_ylabel("thrust force (N)")
    b.set_ylabel("torque (N m)")
    b.set_xlabel("depth of the drill's tip below the top face (mm)")
    for ax in (a, b):
        ax.grid(alpha=0.3)
        ax.axvline(0, color="0.6", lw=0.8)
    b.legend(fontsize=8)
    if len(curves) > 1:
        a.legend(fontsize=8)
    if args.title:
        a.set_title(args.title)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")
