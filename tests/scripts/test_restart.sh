#!/usr/bin/env bash
# Restart files and interruption (issue 36; docs/RELIABILITY.md), as a user meets them: a run with
# *DATABASE_BINARY_RUNRSF writes runrsf; `spall run --restart DIR` continues from it and leaves the
# folder as the uninterrupted run left it, byte for byte (glstat.csv, rwforc.csv, the .pvd and
# every .vtu); SIGTERM and SIGINT stop a run between steps with a restart file, the last state and
# run.json status "interrupted", exit 143 / 130, and the continued run again ends byte for byte as
# the uninterrupted one; bad restarts are one line and exit 2.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# The SPH bar of test_cli (10 000 particles) against a rigid wall (rwforc.csv too), restart files
# every 40 steps; about 680 steps, 5 s on one core: long enough to be stopped while it runs.
python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.01 --periods 2 >"$work/bar.k"
sed 's/^\*END$/*RIGIDWALL_PLANAR\n\n    0.5125       0.0       0.0       1.5       0.0       0.0\n*DATABASE_BINARY_RUNRSF\n        40\n*END/' \
  "$work/bar.k" >"$work/wall.k"
same_folder() {  # every file the uninterrupted run wrote, the same in the other folder
  for f in glstat.csv rwforc.csv d3plot.pvd $(cd "$1" && ls d3plot_*.vtu); do
    cmp -s "$1/$f" "$2/$f" || fail "$f differs from the uninterrupted run's ($3)"
  done
  ls "$2"/d3plot_*.vtu | wc -l | grep -qx "$(ls "$1"/d3plot_*.vtu | wc -l)" || fail "field files ($3)"
}

"$cli" run "$work/wall.k" -o "$work/a" --threads 1 2>"$work/a.log" || { cat "$work/a.log"; fail "run"; }
[ -s "$work/a/runrsf" ] || fail "no runrsf"
steps=$(grep -o '"steps": [0-9]*' "$work/a/run.json" | grep -o '[0-9]*$')
[ "$steps" -gt 200 ] || fail "only $steps steps"

# Continue the finished run from its last restart file (step 40 k < steps): the rows and fields
# after it are written again, the same.
cp -r "$work/a" "$work/b"
"$cli" run --restart "$work/b" --threads 2 2>"$work/b.log" || { cat "$work/b.log"; fail "restart"; }
grep -q "continuing from .*runrsf at step $((steps / 40 * 40))" "$work/b.log" || { cat "$work/b.log"; fail "restart step"; }
same_folder "$work/a" "$work/b" "continued from runrsf"
grep -q '"status": "completed"' "$work/b/run.json" || fail "run.json after the restart"

# NR 3: runrsf01..03 in turn; the restart takes the newest.
sed 's/^        40$/        40         3/' "$work/wall.k" >"$work/wall3.k"
"$cli" run "$work/wall3.k" -o "$work/c" --threads 1 2>/dev/null || fail "NR 3 run"
ls "$work/c"/runrsf0[123] >/dev/null || fail "NR 3 files: $(ls "$work/c")"
[ ! -e "$work/c/runrsf" ] || fail "runrsf written with NR 3"
"$cli" run --restart "$work/c" 2>"$work/c.log" || fail "NR 3 restart"
grep -q "at step $((steps / 40 * 40))" "$work/c.log" || { cat "$work/c.log"; fail "NR 3: not the newest file"; }

# Signals: stop the run when glstat.csv has a few rows, then continue it.
interrupt() {  # SIGNAL EXPECTED_CODE FOLDER
  "$cli" run "$work/wall.k" -o "$3" --threads 1 --checkpoint-every 100000 2>"$3.log" &
  local pid=$!
  for _ in $(seq 1 600); do
    [ -f "$3/glstat.csv" ] && [ "$(wc -l <"$3/glstat.csv")" -ge 30 ] && break
    sleep 0.05
  done
  kill -s "$1" "$pid" || fail "SIG$1: the run ended before the signal"
  local code=0
  wait "$pid" || code=$?
  [ "$code" -eq "$2" ] || { cat "$3.log"; fail "SIG$1: exit $code, expected $2"; }
  grep -q '"status": "interrupted"' "$3/run.json" || fail "SIG$1: run.json status"
  grep -q "interrupted" "$3.log" || fail "SIG$1: no message"
  [ -s "$3/runrsf" ] || fail "SIG$1: no runrsf"
  "$cli" run --restart "$3" 2>"$3.continued.log" || { cat "$3.continued.log"; fail "SIG$1: restart"; }
  same_folder "$work/a" "$3" "after SIG$1"
}
interrupt TERM 143 "$work/term"
interrupt INT 130 "$work/int"

# Bad restarts: one line, exit 2.
expect_bad() {  # MESSAGE ARGS...
  local message=$1
  shift
  local code=0
  "$cli" run "$@" 2>"$work/bad.log" || code=$?
  [ "$code" -eq 2 ] || { cat "$work/bad.log"; fail "exit $code for $*"; }
  grep -q "$message" "$work/bad.log" || { cat "$work/bad.log"; fail "message for $*"; }
}
expect_bad "not a folder" --restart "$work/none"
mkdir -p "$work/empty"
expect_bad "no restart file (runrsf)" --restart "$work/empty"
head -c 300 "$work/a/runrsf" >"$work/empty/runrsf"
expect_bad "empty/deck/wall.k: no such deck file" --restart "$work/empty"  # after the header: the deck is gone
cp -r "$work/a/deck" "$work/empty/"
head -c "$(($(stat -c %s "$work/a/runrsf") / 2))" "$work/a/runrsf" >"$work/empty/runrsf"
expect_bad "runrsf: the checkpoint ends early" --restart "$work/empty"
sed 's/^        40$/         0/' "$work/wall.k" >"$work/cycl0.k"
expect_bad "CYCL" "$work/cycl0.k" -o "$work/cycl0"
echo "restart tests passed ($steps steps)"
