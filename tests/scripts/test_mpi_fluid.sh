#!/usr/bin/env bash
# The SPH fluid on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"): the 2D dam
# break of examples/dam_break cut to 0.05 s (330 steps) and the 3D one cut to 0.02 s, run as one
# process and under mpirun as 1, 2, 3 and 4 ranks (oversubscribed on 2 cores), with 1 or 2 threads
# each: glstat.csv, the .pvd and every .vtu are byte for byte the single process's. Rank 0 writes the
# restart files with the whole state: a 2-rank run's last runrsf, continued on one process, ends as
# the uninterrupted run.
# (test_cli: a deck with what is not distributed, an SPH solid, is refused on 2 ranks.)
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

if ! "$cli" --version | grep -q '(MPI)' || ! command -v mpirun >/dev/null; then
  echo "skipped: spall built without MPI, or no mpirun"
  exit 0
fi
# Open MPI refuses root (containers, CI) and more ranks than cores unless told; its shared-memory
# transport's single-copy mode needs ptrace rights that containers often lack.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMP_WAIT_POLICY=passive
# Under the sanitizers: Open MPI's plugins, unloaded by MPI_Finalize, leave allocations that
# LeakSanitizer can name only as "unknown module"; address and UB checks stay on.
mpirun() { ASAN_OPTIONS=detect_leaks=0 command mpirun "$@"; }

# DECK END_TIME [RUNRSF_CYCLES]: the example deck with its end time cut, and restart files.
cut_deck() {
  python3 - "$@" <<'EOF'
import re, sys
text = open(sys.argv[1]).read()
text = re.sub(r"(\*CONTROL_TERMINATION\n(?:\$.*\n)*)\s*\S+", lambda m: m.group(1) + f"{float(sys.argv[2]):10g}", text)
if len(sys.argv) > 3:
    text = text.replace("*END", f"*DATABASE_BINARY_RUNRSF\n{int(sys.argv[3]):10d}\n*END")
sys.stdout.write(text)
EOF
}
same_folder() {  # every file the single process wrote, the same in the other folder
  for f in glstat.csv d3plot.pvd $(cd "$1" && ls d3plot_*.vtu); do
    cmp -s "$1/$f" "$2/$f" || fail "$f differs from the single process's ($3)"
  done
  ls "$2"/d3plot_*.vtu | wc -l | grep -qx "$(ls "$1"/d3plot_*.vtu | wc -l)" || fail "field files ($3)"
}

cut_deck "$source_dir/examples/dam_break/dam_break_2d.k" 0.05 100 >"$work/d2.k"
cut_deck "$source_dir/examples/dam_break/dam_break.k" 0.02 >"$work/d3.k"
for deck in d2 d3; do
  "$cli" run "$work/$deck.k" -o "$work/$deck.serial" --threads 1 2>"$work/$deck.log" ||
    { cat "$work/$deck.log"; fail "$deck"; }
  steps=$(grep -o '"steps": [0-9]*' "$work/$deck.serial/run.json" | grep -o '[0-9]*$')
  [ "$steps" -gt 100 ] || fail "$deck: only $steps steps"
done
for run in "d2 1 1" "d2 2 1" "d2 3 1" "d2 4 1" "d2 2 2" "d3 2 1" "d3 3 2"; do
  set -- $run
  out="$work/$1.np$2.t$3"
  mpirun -np "$2" "$cli" run "$work/$1.k" -o "$out" --threads "$3" >"$out.log" 2>&1 ||
    { tail -20 "$out.log"; fail "$1 on $2 ranks x $3 threads"; }
  same_folder "$work/$1.serial" "$out" "$1 on $2 ranks x $3 threads"
  grep -q "\"ranks\": $2," "$out/run.json" || fail "run.json ranks ($1, $2 ranks)"
done

# The 2-rank run's last restart file (rank 0 wrote it), continued on one process.
[ -s "$work/d2.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run"
"$cli" run --restart "$work/d2.np2.t1" --threads 1 2>"$work/restart.log" || { cat "$work/restart.log"; fail "restart"; }
grep -q 'continuing from' "$work/restart.log" || fail "the restart did not continue"
same_folder "$work/d2.serial" "$work/d2.np2.t1" "2 ranks, continued on one process"
# Continuing on several ranks is refused with one line (exit 2).
set +e
mpirun -np 2 "$cli" run --restart "$work/d2.np2.t1" >"$work/restart2.log" 2>&1
code=$?
set -e
[ "$code" -eq 2 ] && grep -q 'a run continues on one process' "$work/restart2.log" ||
  fail "restart on 2 ranks: exit $code, $(cat "$work/restart2.log")"
echo "mpi fluid: OK"
