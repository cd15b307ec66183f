#!/usr/bin/env bash
# Two runs at once on one machine (a parameter study, two users): each run's wall time alone and
# with a second copy running beside it, for the elastic-bar example and the Taylor bar of the
# benchmark (D0/35, 105 084 particles), with the default settings. docs/PERFORMANCE.md keeps the
# table ("Two runs on one machine").
# Usage: bench/two_runs.sh [SPALL] [ROUNDS]   (SPALL defaults to build/release/bin/spall)
# Extra environment (OMP_WAIT_POLICY=..., GOMP_SPINCOUNT=...) passes through to every run.
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/.." && pwd)
spall=${1:-$source_dir/build/release/bin/spall}
rounds=${2:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

/usr/bin/python3 "$source_dir/tools/make_taylor_bar_deck.py" --across 35 --end-time 8e-6 --outputs 1 >"$work/taylor_bar.k"
seconds() {  # seconds DECK OUT: the wall time of one run
  local start end
  start=$(date +%s.%N)
  "$spall" run "$1" -o "$2" >/dev/null 2>&1
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
printf "%-12s %5s %9s %14s %14s %7s\n" scene round alone "together (1)" "together (2)" ratio
for deck in "$source_dir/examples/elastic_bar/bar.k" "$work/taylor_bar.k"; do
  name=$(basename "$deck" .k)
  for round in $(seq 1 "$rounds"); do
    alone=$(seconds "$deck" "$work/alone")
    seconds "$deck" "$work/one" >"$work/t1" &
    seconds "$deck" "$work/two" >"$work/t2" &
    wait
    t1=$(cat "$work/t1") t2=$(cat "$work/t2")
    ratio=$(echo "scale=2; ($t1 + $t2) / 2 / $alone" | bc)
    printf "%-12s %5d %9.2f %14.2f %14.2f %7s\n" "$name" "$round" "$alone" "$t1" "$t2" "$ratio"
  done
done
