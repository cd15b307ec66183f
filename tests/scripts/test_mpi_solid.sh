#!/usr/bin/env bash
# The SPH solid and SPG on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"), run
# as one process and under mpirun as 1-4 ranks (oversubscribed on 2 cores) with 1 or 2 threads each:
# every history (glstat.csv, rwforc.csv) is byte for byte the single process's, and the field output
# (a .pvtu per output time of each rank's .vtu piece) holds its .vtu files' points and fields bit for
# bit.
#  - the Taylor bar of examples/taylor_bar, cut short: Johnson-Cook, the corrected gradient, a rigid
#    wall whose force every rank finds whole, the force pass taking each pair once (in blocks, of
#    which each rank runs its own and the one before);
#  - the brittle spall of examples/brittle_spall, cut short: the colour-field categorization (which
#    reads the neighbours' colour field of every rank) and prescribed motion;
#  - two particles of a bar on three ranks: a rank with none;
#  - the SPG tensile bar of examples/spg_tension, coarse and pulled fast enough that bonds break
#    within the run (their broken state is every rank's), with KERNEL 0 and ITB 1 as in the example
#    and with KERNEL 1 (bonds searched anew at each update) and ITB 2.
# Rank 0 writes the restart files with the whole state: the Taylor bar's 2-rank runrsf, continued
# on one process, ends as the uninterrupted run.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
read_vtu=("/usr/bin/python3" "$source_dir/tools/read_vtu.py")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

source "$source_dir/tests/scripts/mpi_common.sh"

cut_deck "$source_dir/examples/taylor_bar/taylor_bar.k" 1e-5 20 >"$work/taylor.k"
cut_deck "$source_dir/examples/brittle_spall/brittle_spall.k" 0.01 >"$work/spall.k"
run_serial taylor 40
run_serial spall 40
[ -s "$work/taylor.serial/rwforc.csv" ] || fail "the Taylor bar wrote no rwforc.csv"
same_on_ranks "$work/taylor.k" "$work/taylor.serial" "2 1" "3 1" "4 1" "2 2"
same_on_ranks "$work/spall.k" "$work/spall.serial" "2 1" "3 2"
# Two particles on three ranks: rank 0, which writes every file, owns neither.
python3 "$source_dir/tools/make_bar_deck.py" --length 0.05 --width 0.025 --spacing 0.025 --periods 2 >"$work/two.k"
run_serial two
same_on_ranks "$work/two.k" "$work/two.serial" "3 1"
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 16 --speed 100 --end-time 4e-5 >"$work/spg.k"
sed -E 's/^( +1\.6){3} +0 +0 +0\.0 +15 +0\.0$/       1.6       1.6       1.6         0         1       0.0        15       0.0/;
        s/^( +1 +0\.6 +1\.2) +1$/\1         2/' "$work/spg.k" >"$work/spg_k1.k"
[ "$(diff "$work/spg.k" "$work/spg_k1.k" | grep -c '^>')" -eq 2 ] || fail "the KERNEL 1, ITB 2 deck"
for deck in spg spg_k1; do
  run_serial $deck 400
  "${read_vtu[@]}" "$(ls "$work/$deck.serial"/d3plot_*.vtu | tail -n 1)" --field broken_bonds >"$work/$deck.bonds"
  grep -Eq '^broken_bonds max [1-9]' "$work/$deck.bonds" || fail "$deck: no bond broke ($(cat "$work/$deck.bonds"))"
done
same_on_ranks "$work/spg.k" "$work/spg.serial" "2 1" "3 2"
same_on_ranks "$work/spg_k1.k" "$work/spg_k1.serial" "3 1"

# The 2-rank run's last restart file (rank 0 wrote it), continued on one process.
[ -s "$work/taylor.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run"
"$cli" run --restart "$work/taylor.serial.np2.t1" --threads 1 2>"$work/restart.log" ||
  { cat "$work/restart.log"; fail "restart"; }
grep -q 'continuing from' "$work/restart.log" || fail "the restart did not continue"
same_folder "$work/taylor.serial" "$work/taylor.serial.np2.t1" "2 ranks, continued on one process"
echo "mpi solid: OK"
