#!/usr/bin/env bash
# Weak scaling of the SPH fluid under MPI (docs/SCALING.md, "Weak scaling, measured"): the 3D dam
# break of tools/make_dam_break_deck.py at 32 particles across the column, its tank P columns deep on
# P ranks, so that each rank carries the same water (65 536 particles) and the tank's floor and end
# walls under it (the two side walls are shared by all). One rank per core, one thread a rank.
# SCENE=taylor_bar: the SPH solid instead, the Taylor bar at 32 P^(1/3) particles across on P ranks
# (about 80 000 particles a rank) to 3e-6 s x 32 / across (about 87 steps).
# SCENE=spg_bar: SPG, the tensile bar of tools/make_spg_tension_deck.py at SPG_ELEMENTS P^(1/3)
# elements along it on P ranks (SPG_ELEMENTS=80: 23 000 particles a rank; 100: 44 500), pulled at
# 100 m/s for about 50 steps (three kernel updates), one output at the end; the deck of SPG alone
# holds a window of the nodes (docs/SCALING.md §3).
# Then the busy node's baseline: B one-rank runs of the one-column deck at once, one a core, so that
# the ranks' shared memory bandwidth and clocks are in the baseline too (docs/SCALING.md §4).
# Prints a row a run: the time in the step without output (each rank's, the slowest counted by the
# collectives), node-steps a second a rank, the time a rank waited in the collectives (mean and
# largest over the ranks), the rows a rank holds (mean, largest) and the rebalances.
# Usage: tools/weak_scaling.sh [OUT]   (RANKS="1 2 4 8 16", BUSY=16, END=0.015 s: about 193 steps;
# MPIRUN, SPALL and EXTRA, more options for spall run, e.g. "--balance-every 20")
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
spall=${SPALL:-$here/../build/release/bin/spall}
mpirun=${MPIRUN:-mpirun}
out=${1:-results/weak_scaling}
mkdir -p "$out"
cd "$out"
deck() {
  if [ "${SCENE:-dam_break}" = spg_bar ]; then
    local elements
    elements=$(python3 -c "print(round(${SPG_ELEMENTS:-80} * $1 ** (1 / 3)))")
    python3 "$here/make_spg_tension_deck.py" --elements "$elements" --speed 100 \
      --end-time "$(python3 -c "print(3.8e-5 / $elements)")" |
      python3 -c "import re, sys; t = sys.stdin.read(); print(re.sub(r'(\*DATABASE_BINARY_D3PLOT\n)\S+', r'\g<1>1.0', t), end='')" \
      > "columns$1.k"
  elif [ "${SCENE:-dam_break}" = taylor_bar ]; then
    local across
    across=$(python3 -c "print(round(32 * $1 ** (1 / 3)))")
    python3 "$here/make_taylor_bar_deck.py" --across "$across" --end-time "$(python3 -c "print(3e-6 * 32 / $across)")" \
      --outputs 1 > "columns$1.k"
  else
    python3 "$here/make_dam_break_deck.py" --particles-across 32 --depth "$(python3 -c "print(0.146 * $1)")" \
      --end-time "${END:-0.015}" --output-interval 1 > "columns$1.k"
  fi
}
row() {
  python3 - "$1" "$2" <<'PY'
import json, sys
d = json.load(open(sys.argv[2] + "/run.json"))
step = sum(t for phase, t in d["phases"].items() if phase != "output")
wait, rows = d["communicating_seconds"], d["node_rows"]
print(f'{sys.argv[1]:>8} {d["ranks"]:>5} {d["nodes"]:>8} {d["steps"]:>5} {step:>8.2f} '
      f'{d["nodes"] * d["steps"] / step / d["ranks"]:>10.3g} {wait["mean"]:>6.2f} {wait["max"]:>6.2f} '
      f'{rows["mean"]:>8.0f} {rows["max"]:>8} {d["rebalances"]:>3}')
PY
}
echo "     run ranks    nodes steps   step_s node-st/s/r wait_m wait_x   rows_m   rows_x reb" | tee table.txt
for p in ${RANKS:-1 2 4 8 16}; do
  deck "$p"
  if [ "$p" = 1 ]; then
    taskset -c 0 "$spall" run columns1.k --threads 1 -o ranks1 ${EXTRA:-} > ranks1.log 2>&1 || { tail -5 ranks1.log; exit 1; }
  else
    "$mpirun" -np "$p" --bind-to core --map-by core "$spall" run "columns$p.k" --threads 1 -o "ranks$p" ${EXTRA:-} \
      > "ranks$p.log" 2>&1 || { tail -5 "ranks$p.log"; exit 1; }
  fi
  row alone "ranks$p" | tee -a table.txt
done
busy=${BUSY:-16}
[ -f columns1.k ] || deck 1
pids=()
for i in $(seq 0 $((busy - 1))); do
  taskset -c "$i" "$spall" run columns1.k --threads 1 -o "busy$i" > "busy$i.log" 2>&1 &
  pids+=($!)
done
wait "${pids[@]}"
for i in $(seq 0 $((busy - 1))); do row "busy$busy" "busy$i"; done | tee -a table.txt
