#!/usr/bin/env bash
# The SPH fluid on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"): the 2D dam
# break of examples/dam_break cut to 0.05 s (330 steps) and the 3D one cut to 0.02 s, run as one
# process and under mpirun as 1, 2, 3 and 4 ranks (oversubscribed on 2 cores), with 1 or 2 threads
# each: glstat.csv, the .pvd and every .vtu are byte for byte the single process's. Rank 0 writes the
# restart files with the whole state: a 2-rank run's last runrsf, continued on one process, ends as
# the uninterrupted run.
# (test_cli: a deck with what is not distributed, FEM, is refused on 2 ranks; test_mpi_solid: the solids.)
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

source "$source_dir/tests/scripts/mpi_common.sh"

cut_deck "$source_dir/examples/dam_break/dam_break_2d.k" 0.05 100 >"$work/d2.k"
cut_deck "$source_dir/examples/dam_break/dam_break.k" 0.02 >"$work/d3.k"
run_serial d2 100
run_serial d3 100
same_on_ranks "$work/d2.k" "$work/d2.serial" "1 1" "2 1" "3 1" "4 1" "2 2"
same_on_ranks "$work/d3.k" "$work/d3.serial" "2 1" "3 2"

# The 2-rank run's last restart file (rank 0 wrote it), continued on one process.
[ -s "$work/d2.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run"
"$cli" run --restart "$work/d2.serial.np2.t1" --threads 1 2>"$work/restart.log" || { cat "$work/restart.log"; fail "restart"; }
grep -q 'continuing from' "$work/restart.log" || fail "the restart did not continue"
same_folder "$work/d2.serial" "$work/d2.serial.np2.t1" "2 ranks, continued on one process"
# Continuing on several ranks is refused with one line (exit 2).
set +e
mpirun -np 2 "$cli" run --restart "$work/d2.serial.np2.t1" >"$work/restart2.log" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] && grep -q 'a run continues on one process' "$work/restart2.log" ||
  fail "restart on 2 ranks: exit $code, $(cat "$work/restart2.log")"
echo "mpi fluid: OK"
