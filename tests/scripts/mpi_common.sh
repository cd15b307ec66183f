# What the MPI scripts (test_mpi_*.sh) share; sourced after `cli`, `source_dir`, `work` and fail() are set.
# Skips the script (exit 0) where spall was built without MPI or mpirun is missing.
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

# DECK END_TIME [RUNRSF_CYCLES]: the deck with its end time cut, and restart files.
cut_deck() {
  python3 - "$@" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
text = re.sub(r"(\*CONTROL_TERMINATION\n(?:\$.*\n)*)\s*\S+", lambda m: m.group(1) + f"{float(sys.argv[2]):10g}", text)
if len(sys.argv) > 3:
    text = text.replace("*END", f"*DATABASE_BINARY_RUNRSF\n{int(sys.argv[3]):10d}\n*END")
sys.stdout.write(text)
PY
}

# NAME [MIN_STEPS]: $work/NAME.k run as one process on one thread into $work/NAME.serial, which
# must take at least MIN_STEPS steps.
run_serial() {
  "$cli" run "$work/$1.k" -o "$work/$1.serial" --threads 1 2>"$work/$1.log" || { cat "$work/$1.log"; fail "$1"; }
  local steps
  steps=$(grep -o '"steps": [0-9]*' "$work/$1.serial/run.json" | grep -o '[0-9]*$')
  [ "$steps" -ge "${2:-1}" ] || fail "$1: only $steps steps"
}

# SERIAL OTHER WHAT: every history the single process wrote is byte for byte the same in the other
# run's folder, and the other run's field output (under MPI a .pvtu of the ranks' pieces per output
# time) holds the same times, points and fields bit for bit (tools/same_fields.py, with VTK's readers).
same_folder() {
  local f
  for f in $(cd "$1" && ls *.csv); do
    cmp -s "$1/$f" "$2/$f" || fail "$f differs from the single process's ($3)"
  done
  /usr/bin/python3 "$source_dir/tools/same_fields.py" "$1" "$2" >"$2.fields" 2>&1 ||
    { cat "$2.fields"; fail "field output ($3)"; }
}

# FOLDER RANKS SERIAL: the run in $work/FOLDER continued from its newest restart file on RANKS ranks
# (1: one process), which then holds the same results as the single process's run in $work/SERIAL.
continue_run() {
  mpirun -np "$2" "$cli" run --restart "$work/$1" --threads 1 >"$work/$1.restart.log" 2>&1 ||
    { cat "$work/$1.restart.log"; fail "restart of $1 on $2 ranks"; }
  grep -q 'continuing from' "$work/$1.restart.log" || fail "the restart of $1 on $2 ranks did not continue"
  same_folder "$work/$3" "$work/$1" "$1, continued on $2 ranks"
}

# DECK SERIAL_FOLDER "RANKS THREADS" ...: the deck under mpirun on each count of ranks and threads,
# every file as the single process's, a piece of field output per rank, and run.json naming the ranks.
# "RANKS THREADS rebalanced" deals the nodes out anew every 5 steps (--balance-threshold 0), which
# must happen and change no bit either; "RANKS THREADS fixed" never deals them anew (the first
# partition stays, or the first regions, between which the nodes then move: migration alone);
# "RANKS THREADS checkpointed" is fixed and writes a restart file at every step, which must change
# no bit either.
same_on_ranks() {
  local deck=$1 serial=$2 run out balance
  shift 2
  for run in "$@"; do
    set -- $run
    out="$serial.np$1.t$2${3:+.$3}"
    balance=()
    [ "${3:-}" = rebalanced ] && balance=(--balance-every 5 --balance-threshold 0)
    [ "${3:-}" = fixed ] && balance=(--balance-threshold 1e300)
    [ "${3:-}" = checkpointed ] && balance=(--balance-threshold 1e300 --checkpoint-every 1)
    mpirun -np "$1" "$cli" run "$deck" -o "$out" --threads "$2" "${balance[@]}" >"$out.log" 2>&1 ||
      { tail -20 "$out.log"; fail "$deck on $1 ranks x $2 threads ${3:-}"; }
    same_folder "$serial" "$out" "$deck on $1 ranks x $2 threads ${3:-}"
    if [ "$1" -gt 1 ]; then
      [ "$(ls "$out/d3plot_00000" | wc -l)" -eq "$1" ] || fail "not a piece per rank ($deck, $1 ranks)"
    fi
    grep -q "\"ranks\": $1," "$out/run.json" || fail "run.json ranks ($deck, $1 ranks)"
    if [ "${3:-}" = rebalanced ]; then
      grep -q '"rebalances": [1-9]' "$out/run.json" || fail "no rebalancing ($deck, $1 ranks): $(grep rebal "$out/run.json")"
    fi
    if [ "${3:-}" = fixed ]; then
      grep -q '"rebalances": 0,' "$out/run.json" || fail "rebalanced ($deck, $1 ranks, fixed): $(grep rebal "$out/run.json")"
    fi
  done
}

# FOLDER: each output time's points a rank's piece holds (the nodes it computed then), a line per
# output time in time order, a column per rank.
piece_points() {
  local d r
  for d in $(ls -d "$1"/d3plot_[0-9]*/ | sort); do
    for ((r = 0; ; r++)); do
      [ -e "$d$(basename "$d")_$r.vtu" ] || break
      grep -ao 'NumberOfPoints="[0-9]*"' "$d$(basename "$d")_$r.vtu" | head -n 1 | tr -dc '0-9'
      printf ' '
    done
    echo
  done
}
