#!/usr/bin/env bash
# The SPH fluid on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"): the 2D dam
# break of examples/dam_break cut to 0.05 s (330 steps) and the 3D one cut to 0.02 s, run as one
# process and under mpirun as 1, 2, 3 and 4 ranks (oversubscribed on 2 cores), with 1 or 2 threads
# each: glstat.csv is byte for byte the single process's, and the field output (a .pvtu per output
# time, each rank's piece a .vtu) holds its .vtu files' points and fields bit for bit. Rank 0 writes
# the restart files with the whole state: a 2-rank run's last runrsf, continued on one process, ends
# as the uninterrupted run, also when a rank was killed mid-run. `spall surface` of a 2-rank run's
# output is the single process's, byte for byte. A rank that cannot write its piece
# stops every rank (exit 4).
# (test_mpi_solid: the solids; test_mpi_contact: contact and rigid bodies.)
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
# spall surface reads the 2-rank run's .pvtu (its pieces joined) as the single process's .vtu.
for run in d3.serial d3.serial.np2.t1; do
  "$cli" surface "$work/$run" --threads 1 >"$work/$run.surface.log" 2>&1 ||
    { cat "$work/$run.surface.log"; fail "surface of $run"; }
done
for f in $(cd "$work/d3.serial" && ls surface_*); do
  cmp -s "$work/d3.serial/$f" "$work/d3.serial.np2.t1/$f" || fail "surface of the 2-rank run: $f differs"
done

# The 2-rank run's last restart file (rank 0 wrote it), continued on one process.
[ -s "$work/d2.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run"
"$cli" run --restart "$work/d2.serial.np2.t1" --threads 1 2>"$work/restart.log" || { cat "$work/restart.log"; fail "restart"; }
grep -q 'continuing from' "$work/restart.log" || fail "the restart did not continue"
same_folder "$work/d2.serial" "$work/d2.serial.np2.t1" "2 ranks, continued on one process"

# One rank killed (SIGKILL) at a random moment of a 2-rank run, four times: mpirun ends the others,
# the folder is whole (every .pvtu the .pvd lists has its pieces: tools/check_output.py), and the
# newest restart file, continued on one process, ends as the uninterrupted run.
for k in 1 2 3 4; do
  delay=$(awk -v r="$RANDOM" 'BEGIN { printf "%.2f", 0.2 + 1.2 * r / 32767 }')
  mpirun -np 2 "$cli" run "$work/d2.k" -o "$work/killed" --threads 1 >/dev/null 2>&1 &
  launcher=$!
  sleep "$delay"
  kill -KILL "$(pgrep -P "$launcher" | tail -n 1)" 2>/dev/null || true
  wait "$launcher" 2>/dev/null || true
  /usr/bin/python3 "$source_dir/tools/check_output.py" "$work/killed" >"$work/check.log" ||
    { cat "$work/check.log"; fail "a rank killed after $delay s: a file is not whole"; }
  if [ -e "$work/killed/runrsf" ]; then
    "$cli" run --restart "$work/killed" --threads 1 2>"$work/restart.log" ||
      { cat "$work/restart.log"; fail "restart after a rank was killed at $delay s"; }
    same_folder "$work/d2.serial" "$work/killed" "a rank killed at $delay s, continued on one process"
    echo "a rank killed at $delay s: whole; continued from $(grep -o 'at step [0-9]*' "$work/restart.log")"
  else
    echo "a rank killed at $delay s: whole (before the first restart file)"
  fi
  rm -rf "$work/killed"
done

# A rank that cannot write its piece of the third output (its temporary file is /dev/full, where
# every write fails as on a full disk) stops every rank with exit 4 and a line naming the file;
# the .pvd lists the two states before, which stay whole (tools/check_output.py).
if [ -w /dev/full ]; then
  mkdir -p "$work/full/d3plot_00002"
  ln -s /dev/full "$work/full/d3plot_00002/d3plot_00002_1.vtu.tmp"
  code=0
  mpirun -np 2 "$cli" run "$work/d2.k" -o "$work/full" --threads 1 >"$work/full.log" 2>&1 || code=$?
  [ "$code" -eq 4 ] || { cat "$work/full.log"; fail "full disk on rank 1: exit $code, expected 4"; }
  grep -q "cannot write .*d3plot_00002_1.vtu: No space left on device" "$work/full.log" ||
    { cat "$work/full.log"; fail "full disk on rank 1: the message"; }
  [ "$(grep -c '<DataSet' "$work/full/d3plot.pvd")" -eq 2 ] || fail "full disk on rank 1: the .pvd"
  /usr/bin/python3 "$source_dir/tools/check_output.py" "$work/full" >/dev/null || fail "full disk on rank 1: not whole"
  grep -q '"status": "output_failed"' "$work/full/run.json" || fail "full disk on rank 1: run.json status"
fi
# Continuing on several ranks is refused with one line (exit 2).
set +e
mpirun -np 2 "$cli" run --restart "$work/d2.serial.np2.t1" >"$work/restart2.log" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] && grep -q 'a run continues on one process' "$work/restart2.log" ||
  fail "restart on 2 ranks: exit $code, $(cat "$work/restart2.log")"
echo "mpi fluid: OK"
