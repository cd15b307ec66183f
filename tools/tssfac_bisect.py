#!/usr/bin/env python3
"""Largest stable TSSFAC of a deck by bisection (issue 4's time-step experiment).

A run at a given TSSFAC is stable when
  1. `spall run` exits 0 (this includes the solver's own runaway check: it stops with exit 3 when
     a node moves faster than 10 x (fastest wave speed + fastest initial speed), or the step falls
     below DTMIN x the first);
  2. the energy balance of glstat.csv closes within --energy-tolerance at every row: |total -
     (initial total + external work)| over the largest initial total + external work (the energy
     ratio's error, also for a body that starts at rest and is loaded by walls);
  3. with --max-speed V, no particle of any field output (d3plot_*.vtu) is faster than V
     (needs Debian's python3-vtk9: run the tool with /usr/bin/python3).

    tools/tssfac_bisect.py DECK [--treat 0|1] [--form 0|1] [--rule 0|1] [--end-time T]
                                [--set KEYWORD,CARD,FIELD,VALUE ...] [--low 0.1] [--high 4]

Each trial copies the deck next to the original (so that includes resolve) with TSSFAC set in
*CONTROL_TIMESTEP and the requested fields changed; a keyword the deck lacks is added before *END
with its other fields blank (their defaults):
  --treat T   TREAT of every *SPALL_SPH_COLOUR_FIELD card (PID 0 card added when there is none)
  --form F    FORM of *CONTROL_SPH
  --rule R    RULE of *SPALL_SPH_TIMESTEP (0 the correction-aware step, 1 LS-DYNA's h/(c + |v|))
  --end-time  ENDTIM of *CONTROL_TERMINATION
  --set K,C,F,V  field F (1-based, 10 columns wide) of data card C (1-based; 0: every card) of
              keyword K, e.g. --set '*SPALL_SPH_COLOUR_FIELD,0,5,2' for two inner layers
Prints one line per trial and the result.
"""
import argparse
import csv
import glob
import os
import subprocess
import sys
import tempfile


def is_keyword(line):
    return line.startswith("*")


def is_data(line):
    return not is_keyword(line) and not line.startswith("$") and line.strip() != ""


def set_field(lines, keyword, card, field, value):
    """Sets a fixed-format field (10 columns) of data card `card` (0: every card) of every block
    of `keyword`; adds the keyword with one card before *END when the deck lacks it."""
    keyword = keyword.upper()
    text = f"{value:>10}"[:10] if not isinstance(value, float) else f"{value:>10.4g}"
    if len(text) > 10:
        sys.exit(f"{value} does not fit a 10-column field")
    out, in_block, index, found = [], False, 0, False
    for line in lines:
        if is_keyword(line):
            in_block = line.strip().upper().split()[0] == keyword
            found = found or in_block
            index = 0
        elif in_block and is_data(line):
            index += 1
            if card in (0, index):
                if "," in line:
                    sys.exit(f"{keyword}: comma-separated cards are not supported by this tool")
                padded = line.ljust(10 * field)
                line = padded[: 10 * (field - 1)] + text + padded[10 * field:]
                line = line.rstrip()
        out.append(line)
    if not found:
        end = next((k for k, l in enumerate(out) if l.strip().upper() == "*END"), len(out))
        new_card = " " * (10 * (field - 1)) + text
        out[end:end] = [keyword, new_card]
    return out


def fastest_particle(work):
    import vtk  # Debian's python3-vtk9
    from vtk.util.numpy_support import vtk_to_numpy
    import numpy

    fastest = 0.0
    for path in sorted(glob.glob(os.path.join(work, "d3plot_*.vtu"))):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(path)
        reader.Update()
        v = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("velocity"))
        fastest = max(fastest, float(numpy.sqrt((v * v).sum(axis=1)).max()))
    return fastest


def energy_error(glstat):
    """Largest |total - (initial total + external work)| over the run, relative to the largest
    initial total + external work: |energy ratio - 1| when nothing works on the body, and still
    defined when the body starts at rest and the walls put the energy in."""
    with open(glstat) as f:
        rows = list(csv.DictReader(f))
    value = lambda row, name: float(next(v for k, v in row.items() if k.split(" ")[0] == name))
    initial = value(rows[0], "total_energy")
    budgets = [initial + value(r, "external_work") for r in rows]
    scale = max(abs(b) for b in budgets)
    return max(abs(value(r, "total_energy") - b) for r, b in zip(rows, budgets)) / scale


def trial(deck_lines, deck_dir, tssfac, a):
    lines = set_field(deck_lines, "*CONTROL_TIMESTEP", 1, 2, f"{tssfac:.4f}")
    with tempfile.TemporaryDirectory() as work:
        deck = os.path.join(deck_dir, f".tssfac_{os.getpid()}.k")
        with open(deck, "w") as f:
            f.write("\n".join(lines) + "\n")
        try:
            result = subprocess.run([a.spall, "run", deck, "-o", work, "--threads", str(a.threads)],
                                    capture_output=True, text=True)
        finally:
            os.remove(deck)
        if result.returncode != 0:
            errors = [l for l in result.stderr.splitlines() if l.startswith("error:")] or [""]
            return False, f"exit {result.returncode}: {errors[0][:160]}"
        worst = energy_error(os.path.join(work, "glstat.csv"))
        why = f"energy error {worst:.3g}"
        ok = worst <= a.energy_tolerance
        if a.max_speed is not None:
            fastest = fastest_particle(work)
            why += f", fastest particle {fastest:.4g}"
            ok = ok and fastest <= a.max_speed
        return ok, why


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("deck")
    p.add_argument("--spall", default="build/release/bin/spall")
    p.add_argument("--treat", type=int, choices=(0, 1))
    p.add_argument("--form", type=int, choices=(0, 1))
    p.add_argument("--rule", type=int, choices=(0, 1))
    p.add_argument("--end-time", type=float)
    p.add_argument("--set", action="append", default=[], metavar="KEYWORD,CARD,FIELD,VALUE")
    p.add_argument("--low", type=float, default=0.1, help="a TSSFAC known to be stable")
    p.add_argument("--high", type=float, default=4.0, help="a TSSFAC known to be unstable")
    p.add_argument("--energy-tolerance", type=float, default=0.05)
    p.add_argument("--max-speed", type=float, help="speed bound on every field output's particles")
    p.add_argument("--threads", type=int, default=1, help="OpenMP threads of each run")
    p.add_argument("--resolution", type=float, default=0.02, help="stop when high - low is below this")
    a = p.parse_args()
    with open(a.deck) as f:
        lines = f.read().splitlines()
    if a.treat is not None:
        lines = set_field(lines, "*SPALL_SPH_COLOUR_FIELD", 0, 2, a.treat)
    if a.form is not None:
        lines = set_field(lines, "*CONTROL_SPH", 1, 6, a.form)
    if a.rule is not None:
        lines = set_field(lines, "*SPALL_SPH_TIMESTEP", 1, 1, a.rule)
    if a.end_time is not None:
        lines = set_field(lines, "*CONTROL_TERMINATION", 1, 1, f"{a.end_time:.4e}")
    for item in a.set:
        keyword, card, field, value = item.split(",")
        lines = set_field(lines, keyword, int(card), int(field), value)
    deck_dir = os.path.dirname(os.path.abspath(a.deck))
    ok, why = trial(lines, deck_dir, a.low, a)
    print(f"TSSFAC {a.low:.4f}: {'stable' if ok else 'unstable'} ({why})", flush=True)
    if not ok:
        sys.exit(f"--low {a.low} is not stable")
    low, high = a.low, a.high
    ok, why = trial(lines, deck_dir, high, a)
    print(f"TSSFAC {high:.4f}: {'stable' if ok else 'unstable'} ({why})", flush=True)
    if ok:
        sys.exit(f"--high {a.high} is stable")
    while high - low > a.resolution:
        mid = 0.5 * (low + high)
        ok, why = trial(lines, deck_dir, mid, a)
        print(f"TSSFAC {mid:.4f}: {'stable' if ok else 'unstable'} ({why})", flush=True)
        low, high = (mid, high) if ok else (low, mid)
    print(f"largest stable TSSFAC: {low:.4f} (unstable at {high:.4f})")


if __name__ == "__main__":
    main()
