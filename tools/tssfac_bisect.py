#!/usr/bin/env python3
"""Largest stable TSSFAC of a deck by bisection (issue 4's time-step experiment).

A run is stable when `spall run` exits 0 (no runaway particle: the solver stops with exit 3 when a
particle moves faster than ten times the fastest wave plus the fastest initial motion) and the
energy ratio of glstat.csv stays within --energy-tolerance of 1 at every row.

    tools/tssfac_bisect.py DECK [--with-treatment | --without-treatment] [--low 0.1] [--high 4]

The deck is copied with its *CONTROL_TIMESTEP card replaced (added when missing); with
--without-treatment every *SPALL_SPH_COLOUR_FIELD TREAT is set to 0, with --with-treatment to 1.
Prints one line per trial and the result.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile


def set_card(lines, keyword, card):
    """Replaces the first data card of `keyword` (adds the keyword before *END when missing)."""
    out, i, found = [], 0, False
    while i < len(lines):
        line = lines[i]
        out.append(line)
        if line.strip().upper().startswith(keyword) and not found:
            found = True
            i += 1
            while i < len(lines) and lines[i].startswith("$"):
                out.append(lines[i])
                i += 1
            out.append(card)
            i += 1  # the replaced card
            continue
        i += 1
    if not found:
        end = next((k for k, l in enumerate(out) if l.strip().upper() == "*END"), len(out))
        out[end:end] = [keyword, card]
    return out


def set_treatment(lines, treat):
    out, in_card = [], False
    for line in lines:
        if line.strip().upper().startswith("*"):
            in_card = line.strip().upper().startswith("*SPALL_SPH_COLOUR_FIELD")
            out.append(line)
        elif in_card and line.strip() and not line.startswith("$"):
            out.append(line[:10].ljust(10) + f"{treat:>10d}" + line[20:])
        else:
            out.append(line)
    return out


def stable(deck_lines, deck_dir, tssfac, spall, tolerance):
    lines = set_card(deck_lines, "*CONTROL_TIMESTEP", f"{0.0:>10}{tssfac:>10.4f}")
    with tempfile.TemporaryDirectory() as work:
        deck = os.path.join(deck_dir, f".tssfac_{os.getpid()}.k")
        with open(deck, "w") as f:
            f.write("\n".join(lines) + "\n")
        try:
            result = subprocess.run([spall, "run", deck, "-o", work], capture_output=True, text=True)
        finally:
            os.remove(deck)
        if result.returncode != 0:
            return False, f"exit {result.returncode}"
        worst = 0.0
        with open(os.path.join(work, "glstat.csv")) as f:
            for row in csv.DictReader(f):
                worst = max(worst, abs(float(row["energy_ratio"]) - 1))
        return worst <= tolerance, f"energy error {worst:.3g}"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("deck")
    p.add_argument("--spall", default="build/release/bin/spall")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--with-treatment", action="store_true")
    g.add_argument("--without-treatment", action="store_true")
    p.add_argument("--low", type=float, default=0.1, help="a TSSFAC known to be stable")
    p.add_argument("--high", type=float, default=4.0, help="a TSSFAC known to be unstable")
    p.add_argument("--energy-tolerance", type=float, default=0.05)
    p.add_argument("--resolution", type=float, default=0.02, help="stop when high - low is below this")
    a = p.parse_args()
    with open(a.deck) as f:
        lines = f.read().splitlines()
    if a.with_treatment:
        lines = set_treatment(lines, 1)
    if a.without_treatment:
        lines = set_treatment(lines, 0)
    deck_dir = os.path.dirname(os.path.abspath(a.deck))
    ok, why = stable(lines, deck_dir, a.low, a.spall, a.energy_tolerance)
    print(f"TSSFAC {a.low:.4f}: {'stable' if ok else 'unstable'} ({why})")
    if not ok:
        sys.exit(f"--low {a.low} is not stable")
    low, high = a.low, a.high
    while high - low > a.resolution:
        mid = 0.5 * (low + high)
        ok, why = stable(lines, deck_dir, mid, a.spall, a.energy_tolerance)
        print(f"TSSFAC {mid:.4f}: {'stable' if ok else 'unstable'} ({why})", flush=True)
        low, high = (mid, high) if ok else (low, mid)
    print(f"largest stable TSSFAC: {low:.4f} (unstable at {high:.4f})")


if __name__ == "__main__":
    main()
