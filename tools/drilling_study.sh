#!/usr/bin/env bash
# Seed 001 §3.2's parameter studies of the friction drilling (examples/friction_drilling), with the
# scaling check and the FEM-with-erosion comparison (Fig. 4b), in one command: writes the decks with
# tools/make_drilling_deck.py, runs them two at a time, and draws each figure's thrust and torque with
# tools/drilling_forces.py (numbers in OUT/*.txt, plots in OUT/*.png).
#   Fig. 6: bond failure at effective plastic strain 0.4 vs 0.7 (m1, COF 0.3)
#   Fig. 7: COF 0.15 vs 0.20, materials m1 and m2
#   Fig. 8: kernel update every 15 (full: 5) vs 30 steps;  Fig. 9: support 1.6 vs 1.8 (m2, COF 0.2)
#   scaling: the plunge 2000 vs 1000 times the test's (the example's deck and the coarse base: 2000)
#   Fig. 4b: the whole disk in FEM with erosion at effective strain 0.4 vs the coupled model
# Usage: tools/drilling_study.sh [OUT]   (LEVEL=coarse, the default: 0.4 mm particles, about 2 min a run on one
# core; LEVEL=full: the example's 0.2 mm, about 40 minutes a run on two, the slower plunge twice that)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
spall=${SPALL:-$here/../build/release/bin/spall}
out=${1:-results/drilling_study}
level=${LEVEL:-coarse}
mkdir -p "$out"
case $level in
  coarse) smstep=15
          mesh=(--spacing 0.4e-3 --layers 4 --ring-layers 3 --segments 24 --dt2ms=-2e-7 --outputs 8 --histories 200)
          fast=2000 ;;
  full) smstep=5; mesh=(--outputs 20); fast=2000 ;;
  *) echo "LEVEL is coarse or full" >&2; exit 2 ;;
esac

# name: options (on top of the mesh's; the default is m2, COF 0.2, FS 0.4, DX 1.6). The coarse runs update the
# kernel every 15 steps, seed 001 §3's value and the base of its Fig. 8; the full ones every 5, its Fig. 2's card
# and the example's deck (examples/friction_drilling/README.md).
mesh+=(--smstep "$smstep")
runs=(
  "base:--time-scale $fast"
  "m1_cof0.3_fs0.4:--time-scale $fast --material m1 --mu 0.3"
  "m1_cof0.3_fs0.7:--time-scale $fast --material m1 --mu 0.3 --fail-strain 0.7"
  "m1_cof0.15:--time-scale $fast --material m1 --mu 0.15"
  "m1_cof0.2:--time-scale $fast --material m1 --mu 0.2"
  "m2_cof0.15:--time-scale $fast --mu 0.15"
  "smstep30:--time-scale $fast --smstep 30"
  "support1.8:--time-scale $fast --support 1.8"
  "slower:--time-scale $((fast / 2))"
  "fem_erosion:--time-scale $fast --fem-only"
)
for run in "${runs[@]}"; do
  name=${run%%:*}
  # shellcheck disable=SC2086
  python3 "$here/make_drilling_deck.py" "${mesh[@]}" ${run#*:} >"$out/$name.k"
done
start=$(date +%s)
printf '%s\n' "${runs[@]%%:*}" | xargs -P 2 -I{} sh -c \
  "'$spall' run '$out/{}.k' -o '$out/{}' --threads 1 >'$out/{}.log' 2>&1 || echo 'run {} failed: $out/{}.log' >&2"
echo "the runs took $(( $(date +%s) - start )) s"

plot() {  # figure title run label [run label ...]
  local figure=$1 title=$2
  shift 2
  local args=()
  while [ $# -gt 0 ]; do
    args+=("$out/$1" --label "$2")
    shift 2
  done
  /usr/bin/python3 "$here/drilling_forces.py" "${args[@]}" --title "$title" -o "$out/$figure.png" | tee "$out/$figure.txt"
}
plot fig6_failure_strain "bond failure strain (m1, COF 0.3)" m1_cof0.3_fs0.4 "FS 0.4" m1_cof0.3_fs0.7 "FS 0.7"
plot fig7_friction "friction (m1, m2)" m1_cof0.15 "m1, COF 0.15" m1_cof0.2 "m1, COF 0.20" m2_cof0.15 "m2, COF 0.15" \
  base "m2, COF 0.20"
plot fig8_kernel_update "kernel update interval (m2, COF 0.2)" base "every $smstep steps" smstep30 \
  "every 30 steps"
plot fig9_support "normalized support (m2, COF 0.2)" base "1.6" support1.8 "1.8"
plot scaling "time scaling (m2, COF 0.2)" base "plunge x $fast" slower "plunge x $((fast / 2))"
plot fig4b_fem_erosion "coupled SPG/FEM vs FEM with erosion (m2, COF 0.2)" base "SPG centre" fem_erosion \
  "FEM, erosion at 0.4"
for name in base fem_erosion; do
  /usr/bin/python3 "$here/drilling_particles.py" "$(ls "$out/$name"/d3plot_*.vtu | tail -n 1)" || true
  grep -o '"eroded_mass": [^,}]*' "$out/$name/run.json" || true
done
