#!/usr/bin/env bash
# Output that survives the worst (issue 36; docs/RELIABILITY.md): a run killed with SIGKILL at ten
# random moments leaves every file it lists whole (the .pvd parses and every .vtu it names opens in
# VTK's reader; every .csv row complete: tools/check_output.py), and its newest restart file
# continues it to the uninterrupted run's results byte for byte; a full disk (a file that is
# /dev/full) is one line naming the file, exit code 4, and the states written before stay whole.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
check=("/usr/bin/python3" "$source_dir/tools/check_output.py")

# The SPH bar (10 000 particles, about 340 steps, 3 s on one core), restart files every 25 steps.
python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.01 --periods 1 >"$work/bar.k"
sed 's/^\*END$/*DATABASE_BINARY_RUNRSF\n        25\n*END/' "$work/bar.k" >"$work/rsf.k"
"$cli" run "$work/rsf.k" -o "$work/reference" --threads 1 2>/dev/null || fail "reference run"
"${check[@]}" "$work/reference" >/dev/null || fail "the reference run's folder"

for k in $(seq 1 10); do
  delay=$(awk -v r="$RANDOM" 'BEGIN { printf "%.2f", 0.2 + 2.6 * r / 32767 }')
  "$cli" run "$work/rsf.k" -o "$work/killed" --threads 1 2>/dev/null &
  pid=$!
  sleep "$delay"
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  "${check[@]}" "$work/killed" >"$work/check.log" || { cat "$work/check.log"; fail "killed after $delay s: a file is not whole"; }
  if [ -e "$work/killed/runrsf" ]; then
    "$cli" run --restart "$work/killed" 2>"$work/restart.log" || { cat "$work/restart.log"; fail "restart after SIGKILL at $delay s"; }
    for f in glstat.csv d3plot.pvd $(cd "$work/reference" && ls d3plot_*.vtu); do
      cmp -s "$work/reference/$f" "$work/killed/$f" || fail "killed at $delay s and continued: $f differs"
    done
    echo "SIGKILL at $delay s: whole; continued from $(grep -o 'at step [0-9]*' "$work/restart.log")"
  else
    echo "SIGKILL at $delay s: whole (before the first restart file)"
  fi
  rm -rf "$work/killed"
done

# A full disk: the fourth field file cannot be written. Its temporary is /dev/full, where every
# write fails with ENOSPC as on a full disk.
if [ -w /dev/full ]; then
  mkdir -p "$work/full"
  ln -s /dev/full "$work/full/d3plot_00003.vtu.tmp"
  code=0
  "$cli" run "$work/bar.k" -o "$work/full" --threads 1 2>"$work/full.log" || code=$?
  [ "$code" -eq 4 ] || { cat "$work/full.log"; fail "full disk: exit $code, expected 4"; }
  grep -q "cannot write .*d3plot_00003.vtu: No space left on device" "$work/full.log" ||
    { cat "$work/full.log"; fail "full disk: the message"; }
  [ "$(grep -c 'error' "$work/full.log")" -eq 1 ] || { cat "$work/full.log"; fail "full disk: more than one error line"; }
  [ "$(grep -c '<DataSet' "$work/full/d3plot.pvd")" -eq 3 ] || fail "full disk: the .pvd should list the 3 states before"
  "${check[@]}" "$work/full" >/dev/null || fail "full disk: the states before are not whole"
  grep -q '"status": "output_failed"' "$work/full/run.json" || fail "full disk: run.json status"
  # The history itself on a full disk.
  mkdir -p "$work/full_csv"
  ln -s /dev/full "$work/full_csv/glstat.csv"
  code=0
  "$cli" run "$work/bar.k" -o "$work/full_csv" --threads 1 2>"$work/full_csv.log" || code=$?
  [ "$code" -eq 4 ] || { cat "$work/full_csv.log"; fail "full disk (glstat.csv): exit $code"; }
  grep -q "cannot write .*glstat.csv: No space left on device" "$work/full_csv.log" || { cat "$work/full_csv.log"; fail "glstat.csv message"; }
else
  echo "no /dev/full on this machine: the full-disk case is not tested"
fi
# An output folder that cannot be made (its path runs through a file): one line naming the folder
# and the reason, exit 4, as for any output that cannot be written (not an internal error).
code=0
"$cli" run "$work/bar.k" -o "$work/bar.k/out" --threads 1 2>"$work/folder.log" || code=$?
[ "$code" -eq 4 ] || { cat "$work/folder.log"; fail "an output folder under a file: exit $code, expected 4"; }
grep -q "cannot write the output folder .*bar.k/out: Not a directory" "$work/folder.log" ||
  { cat "$work/folder.log"; fail "an output folder under a file: the message"; }
echo "output safety tests passed"
