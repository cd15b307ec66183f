#!/usr/bin/env bash
# The SPH fluid on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"): the 2D dam
# break of examples/dam_break cut to 0.05 s (330 steps) and the 3D one cut to 0.02 s, run as one
# process and under mpirun as 1, 2, 3 and 4 ranks (oversubscribed on 2 cores), with 1 or 2 threads
# each: glstat.csv (and the 3D one's nodout.csv) is byte for byte the single process's, and the
# field output (a .pvtu per output time, each rank's piece a .vtu) holds its .vtu files' points and
# fields bit for bit. Rank 0 writes
# the restart files, every rank's own state in turn, which every rank reads back whole: a 2-rank
# run's last runrsf, continued on one process or on 3 ranks, and the single process's on 2 ranks,
# end as the uninterrupted run, also when a rank was killed mid-run; writing one at every step
# changes no bit and leaves no rank holding every node. `spall surface` of a 2-rank run's
# output is the single process's, byte for byte. A rank that cannot write its piece
# stops every rank (exit 4), as does rank 0 when it cannot write a history (the job aborted).
# The 2D dam break on 3 ranks once more with the nodes dealt out anew every 5 steps (the load
# balancing, forced): still bit for bit. A droplet that skims a resting water layer from end to end
# (every rank's halo planned anew around it as it passes), on 4 ranks and on 3 rebalanced, and the
# droplet over 4 particles of the layer on 10 ranks (two hold none): bit for bit. A deck of fluid
# alone is set up in blocks of the node order (each rank builds its block's rows; every case here
# starts so, on 10 ranks with ranks whose block is empty), dealt by region (RCB), and its particles
# migrate between the regions as they flow, a rank holding only the nodes near its region: with the regions fixed, the droplet passes from
# rank to rank across every boundary, and on 10 ranks the particles of a rank all leave it, bit
# for bit. Every rank keeps a share of the deck's node and particle cards: a bad particle card whose
# failure another rank finds stops every rank with exit 2 and the single process's line.
# (test_mpi_solid: the solids; test_mpi_contact: contact and rigid bodies.)
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

source "$source_dir/tests/scripts/mpi_common.sh"
read_vtu=("/usr/bin/python3" "$source_dir/tools/read_vtu.py")

cut_deck "$source_dir/examples/dam_break/dam_break_2d.k" 0.05 100 >"$work/d2.k"
cut_deck "$source_dir/examples/dam_break/dam_break.k" 0.02 >"$work/d3.k"
# History nodes (nodout.csv): a wall corner and two water particles, each from its region's rank.
sed -i 's/^\*END$/*DATABASE_HISTORY_NODE\n1,30000,37580\n*DATABASE_NODOUT\n0.002\n*END/' "$work/d3.k"
run_serial d2 100
run_serial d3 100
same_on_ranks "$work/d2.k" "$work/d2.serial" "1 1" "2 1" "3 1" "4 1" "2 2" "3 1 rebalanced"
same_on_ranks "$work/d3.k" "$work/d3.serial" "2 1" "3 2" "2 1 rebalanced" "2 1 checkpointed"
# The 2D dam break with its left wall a paddle (nodes 211-354, held in y and z) driven along x at
# 0.5 m/s (*BOUNDARY_PRESCRIBED_MOTION_SET, VAD 0): the ranks drive the paddle's particles in the
# rows their regions keep, which change at each rebuild (before, a rank drove the rows of the first
# deal, other nodes: the energies differed from the single process's by half). Its node 211 ends
# at u_x = 0.5 m/s x 0.05 s = 25 mm, to round-off; bndout.csv (the force that drives it, the work
# it does on the water) and matsum.csv (the water's compression and kinetic energy, each rank its
# own particles) are the single process's too.
python3 - "$work/d2.k" >"$work/paddle.k" <<'PY'
import sys
text = open(sys.argv[1]).read()
walls = """         1
         1       498
*BOUNDARY_SPC_SET
$#    nsid       cid      dofx      dofy      dofz
         1         0         1         1         1
"""
assert walls in text
sys.stdout.write(text.replace(walls, """         1
         1       210       355       498
*SET_NODE_LIST_GENERATE
         2
       211       354
*BOUNDARY_SPC_SET
         1         0         1         1         1
         2         0         0         1         1
*BOUNDARY_PRESCRIBED_MOTION_SET
         2         1         0         2       0.5
*DEFINE_CURVE
         2
                 0.0                 1.0
              1000.0                 1.0
*DATABASE_HISTORY_NODE
       211
*DATABASE_BNDOUT
     0.001
*DATABASE_MATSUM
     0.001
""").replace("*DATABASE_BINARY_RUNRSF", "*DATABASE_NODOUT\n     0.001\n*DATABASE_BINARY_RUNRSF"))
PY
run_serial paddle 100
awk -F, 'NR > 1 && $1 == 0.05 && $2 == 211 { found = 1; ok = ($3 - 0.025) ^ 2 < 1e-24 } END { exit !(found && ok) }' \
  "$work/paddle.serial/nodout.csv" ||
  fail "the paddle did not move 25 mm: $(tail -n 1 "$work/paddle.serial/nodout.csv")"
same_on_ranks "$work/paddle.k" "$work/paddle.serial" "3 1" "2 1 rebalanced"
# A deck of fluid alone: each rank keeps the rows of its region's nodes and of those its passes
# read (rows of its own, NodeStore), not every node: with the regions fixed (the rows then do not
# depend on the measured work), no rank of the 3D dam break on 2 ranks holds every node, though a
# restart file was written at every step (each rank's own rows and particles go to rank 0 in
# turn: core/pieces.hpp), and the two hold 1.33 of them together (measured: each node once, and a
# third more for the reach of 5.5 cell edges around the regions, large against this small deck),
# below the 1.5 checked. Each rank's largest resident set is reported too: at least what its rows
# take (ID, two positions, velocity, force and mass: 112 B a row).
python3 - "$work/d3.serial.np2.t1.checkpointed/run.json" <<'PY' || fail "the ranks of the 2-rank 3D dam break hold most nodes twice"
import json, sys
run = json.load(open(sys.argv[1]))
rows, nodes, peak = run["node_rows"], run["nodes"], run["peak_resident_bytes"]
print("2 ranks: %g rows a rank (at most %d) of the %d nodes; largest resident set %.1f MB (mean %.1f MB)"
      % (rows["mean"], rows["max"], nodes, peak["max"] / 1e6, peak["mean"] / 1e6))
sys.exit(0 if rows["max"] < nodes and 2 * rows["mean"] < 1.5 * nodes
         and peak["max"] >= peak["mean"] >= 112 * rows["mean"] else 1)
PY
# DROPLET_SPEED LAYER_COLUMNS: a 2D deck (no gravity) of a resting water layer 4 particles deep and
# LAYER_COLUMNS long, written column by column so that the ranks' blocks of nodes are stretches of
# it along x, and a 2 x 2 droplet written last (the last rank's) that skims it at DROPLET_SPEED
# along x, within the kernel's reach of the layer's top, from before its start to past its end.
# With a third argument "walled", the layer lies on a moving rigid wall (a floor of 1 kg, pushed
# down as the droplet passes) and a fixed one across its far end stops the droplet there; with
# "slider", the layer is lifted 3 cm and the droplet, coming down at 0.5 m/s, lands on a fixed
# floor that welds it (FRIC 2, WVEL 0.1 m/s) and slides along it (frictionless) under the layer;
# from 10 ms a body force pulls everything up (*LOAD_BODY_Y), which lifts the layer and leaves the
# welded droplet on the floor.
droplet_deck() {
  python3 - "$@" <<'PY'
import sys
speed, columns = float(sys.argv[1]), int(sys.argv[2])
mode = sys.argv[3] if len(sys.argv) > 3 else ""
walled, slider = mode == "walled", mode == "slider"
dx = 0.01
print("*KEYWORD\n*CONTROL_TERMINATION\n%10g" % ((columns + 6) * dx / speed))
print("*CONTROL_SPH\n%40d%20d" % (2, 0))
print("*DATABASE_BINARY_D3PLOT\n%10g\n*DATABASE_GLSTAT\n%10g" % (0.01, 0.001))
print("*PART\nwater\n%10d%10d%10d%10d" % (1, 1, 1, 1))
print("*SECTION_SPH\n%10d%10g%10g%10g" % (1, 1.3, 1.0, 1.0))
print("*MAT_NULL\n%10d%10g%10g%10g\n*EOS_MURNAGHAN\n%10d%10g%10g" % (1, 1000.0, 0.0, 1e-3, 1, 7.0, 81843.4))
lift = 0.03 if slider else 0.0
nodes = [(dx * i, lift + dx * j) for i in range(columns) for j in range(4)]
droplet = [(-3 * dx + dx * i, (0 if slider else 4.5 * dx) + dx * j) for i in range(2) for j in range(2)]
print("*NODE")
for k, (x, y) in enumerate(nodes + droplet):
    print("%8d%16g%16g%16g" % (k + 1, x, y, 0.0))
print("*ELEMENT_SPH")
for k in range(len(nodes + droplet)):
    print("%8d%8d%16g" % (k + 1, 1, 1000.0 * dx * dx))
print("*INITIAL_VELOCITY_NODE")
for k in range(len(droplet)):
    print("%10d%10g%10g%10g" % (len(nodes) + k + 1, speed, -0.5 if slider else 0.0, 0.0))
if walled:  # on every node: a floor of 1 kg under the layer (normal +y), free to move along its
    # normal, and a fixed wall across the layer's far end (normal -x)
    print("*RIGIDWALL_PLANAR_MOVING\n%10d\n" % 0 + "%10g" * 6 % (0, 0, 0, 0, 1, 0) + "\n%10g%10g" % (1.0, 0.0))
    print("*RIGIDWALL_PLANAR\n%10d\n" % 0 + "%10g" * 6 % (columns * dx, 0, 0, columns * dx - 1, 0, 0))
    print("*DATABASE_RWFORC\n%10g" % 0.001)
if slider:
    print("*RIGIDWALL_PLANAR\n%10d\n" % 0 + "%10g" * 8 % (0, 0, 0, 0, 1, 0, 2, 0.1))
    print("*LOAD_BODY_Y\n%10d%10g\n*DEFINE_CURVE\n%10d" % (1, 1.0, 1))
    for t, a in ((0, 0), (0.01, 0), (0.011, -30), (1, -30)):
        print("%20g%20g" % (t, a))
print("*END")
PY
}
# The droplet crosses every rank's stretch of the layer (4 ranks), so that each rank's halo is
# planned anew around it as it passes: bit for bit the single process's. The droplet over the
# layer's first column alone, 8 particles on 10 ranks, leaves two ranks without one.
droplet_deck 10 40 >"$work/droplet.k"
run_serial droplet 100
"${read_vtu[@]}" "$(ls "$work/droplet.serial"/d3plot_*.vtu | tail -n 1)" --field displacement >"$work/droplet.last" ||
  fail "the droplet's last state"
awk '$1 == "displacement" && $2 == "max" { exit !($3 > 0.43) }' "$work/droplet.last" ||
  fail "the droplet did not pass the layer's end: $(grep 'displacement max' "$work/droplet.last")"
same_on_ranks "$work/droplet.k" "$work/droplet.serial" "4 1" "3 1 rebalanced" "4 1 fixed"
# A deck of fluid alone is dealt by region (RCB), and the particles migrate to the rank of the
# region they flow into at each rebuild of the cells. The 4 regions stay put in the "fixed" run:
# the layer's 40 columns cut along x into 10, 10, 10 and 11 columns with the droplet in the first,
# which then carries it across every boundary into the last (each rank's piece holds the nodes it
# computes at each output).
piece_points "$work/droplet.serial.np4.t1.fixed" >"$work/droplet.pieces"
awk 'NR == 1 { for (r = 1; r <= NF; ++r) first[r] = max[r] = $r }
     { for (r = 1; r <= NF; ++r) if ($r > max[r]) max[r] = $r; for (r = 1; r <= NF; ++r) last[r] = $r }
     END { exit !(last[1] == first[1] - 4 && last[4] == first[4] + 4 && max[2] > first[2] && max[3] > first[3]) }' \
  "$work/droplet.pieces" || fail "the droplet did not move from rank to rank: $(cat "$work/droplet.pieces")"
# The same on a floor and stopped by a wall: a wall acts on each rank's own nodes before their
# velocities travel (the halo by reach), its force summed over the ranks, the floor's velocity
# solved from every rank's nodes on it (it holds up every rank's stretch of the layer): bit for
# bit, rwforc.csv too.
droplet_deck 10 40 walled >"$work/walled.k"
run_serial walled 100
for wall in 1 2; do
  awk -F, -v wall=$wall 'NR > 1 && $2 == wall && $3 + 0 != 0 { hit = 1 } END { exit !hit }' \
    "$work/walled.serial/rwforc.csv" || fail "wall $wall stopped nothing: $(tail -n 2 "$work/walled.serial/rwforc.csv")"
done
same_on_ranks "$work/walled.k" "$work/walled.serial" "4 1" "3 1 rebalanced"
# A wall's state of a node goes with the node to its new rank: the welded droplet of the slider
# deck crosses every rank's region. A rank that took it without its welds would let it go (the run
# without welding ends elsewhere): bit for bit, with the regions fixed. Its restart files (every
# 100 steps) of the 4-rank run, continued on 3 ranks, each rank reading its block of the nodes
# (with the walls' state of every node): the uninterrupted run.
droplet_deck 10 40 slider | sed 's/^\*END$/*DATABASE_BINARY_RUNRSF\n       100\n*END/' >"$work/slider.k"
run_serial slider 100
same_on_ranks "$work/slider.k" "$work/slider.serial" "4 1 fixed"
continue_run slider.serial.np4.t1.fixed 3 slider.serial
echo "the slider's 4-rank run continued on 3 ranks from $(grep -o 'at step [0-9]*' "$work/slider.serial.np4.t1.fixed.restart.log")"
python3 - "$work/droplet.k" >"$work/alone.k" <<'PY'
import sys
text = open(sys.argv[1]).read()
# The layer's first column (nodes 1-4) and the droplet (161-164).
lines, section = [], ""
for line in text.splitlines():
    if line.startswith("*"):
        section = line
    elif section in ("*NODE", "*ELEMENT_SPH") and 4 < int(line[:8]) <= 160:
        continue
    lines.append(line)
print("\n".join(lines))
PY
run_serial alone 100
same_on_ranks "$work/alone.k" "$work/alone.serial" "10 1" "10 1 fixed"
# With the regions fixed, ranks without a particle from the start, and ranks whose particles all
# leave (the droplet's: they hold none at the end): still bit for bit.
piece_points "$work/alone.serial.np10.t1.fixed" >"$work/alone.pieces"
awk 'NR == 1 { for (r = 1; r <= NF; ++r) { first[r] = $r; if ($r == 0) empty = 1 } }
     { for (r = 1; r <= NF; ++r) last[r] = $r }
     END { for (r in first) if (first[r] > 0 && last[r] == 0) emptied = 1; exit !(emptied && empty) }' \
  "$work/alone.pieces" || fail "no rank empty from the start, or none emptied: $(cat "$work/alone.pieces")"

# spall surface reads the 2-rank run's .pvtu (its pieces joined) as the single process's .vtu,
# also when the regions were cut anew every 5 steps (each piece then holds other nodes).
for run in d3.serial d3.serial.np2.t1 d3.serial.np2.t1.rebalanced; do
  "$cli" surface "$work/$run" --threads 1 >"$work/$run.surface.log" 2>&1 ||
    { cat "$work/$run.surface.log"; fail "surface of $run"; }
done
for f in $(cd "$work/d3.serial" && ls surface_*); do
  for run in d3.serial.np2.t1 d3.serial.np2.t1.rebalanced; do
    cmp -s "$work/d3.serial/$f" "$work/$run/$f" || fail "surface of $run: $f differs"
  done
done

# The last restart file (rank 0 writes it, every rank's own rows and particles in turn) of the
# 2-rank runs continued on one process and on 3 ranks, and of the single process on 2 ranks: each
# ends as the uninterrupted run.
[ -s "$work/d2.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run"
cp -r "$work/d2.serial.np2.t1" "$work/d2.np2.on3"
cp -r "$work/d2.serial" "$work/d2.np1.on2"
continue_run d2.serial.np2.t1 1 d2.serial
continue_run d2.np2.on3 3 d2.serial
continue_run d2.np1.on2 2 d2.serial
continue_run d3.serial.np2.t1.checkpointed 3 d3.serial

# One rank killed (SIGKILL) at a random moment of a 2-rank run, four times: mpirun ends the others,
# the folder is whole (every .pvtu the .pvd lists has its pieces: tools/check_output.py), and the
# newest restart file, continued on two ranks and on one process in turn, ends as the uninterrupted run.
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
    ranks=$((k % 2 + 1))
    continue_run killed $ranks d2.serial
    echo "a rank killed at $delay s: whole; continued on $ranks ranks from $(grep -o 'at step [0-9]*' "$work/killed.restart.log")"
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
  # A file only rank 0 writes (glstat.csv on a full disk): it ends the whole job at once with exit 4
  # and the line naming the file, rather than leave rank 1 waiting for it in the next reduction.
  mkdir -p "$work/full_csv"
  ln -s /dev/full "$work/full_csv/glstat.csv"
  code=0
  timeout 300 mpirun -np 2 "$cli" run "$work/d2.k" -o "$work/full_csv" --threads 1 >"$work/full_csv.log" 2>&1 || code=$?
  [ "$code" -eq 4 ] || { cat "$work/full_csv.log"; fail "full disk (glstat.csv, rank 0 alone): exit $code, expected 4"; }
  grep -q "cannot write .*glstat.csv: No space left on device" "$work/full_csv.log" ||
    { cat "$work/full_csv.log"; fail "full disk (glstat.csv, rank 0 alone): the message"; }
  # A restart file, into which rank 1 writes its own rows and particles at their place: its write
  # failing stops every rank with exit 4 and the line naming the file, and leaves no restart file.
  mkdir -p "$work/full_restart"
  ln -s /dev/full "$work/full_restart/runrsf.tmp"
  code=0
  timeout 300 mpirun -np 2 "$cli" run "$work/d2.k" -o "$work/full_restart" --threads 1 --checkpoint-every 100 \
    >"$work/full_restart.log" 2>&1 || code=$?
  [ "$code" -eq 4 ] || { cat "$work/full_restart.log"; fail "full disk (restart file): exit $code, expected 4"; }
  grep -q "cannot write .*runrsf.tmp: No space left on device" "$work/full_restart.log" ||
    { cat "$work/full_restart.log"; fail "full disk (restart file): the message"; }
  [ ! -e "$work/full_restart/runrsf" ] || fail "full disk (restart file): a restart file was left"
  grep -q '"status": "output_failed"' "$work/full_restart/run.json" || fail "full disk (restart file): run.json status"
fi
# Bad input in the cards each rank holds a share of (a particle card on a node the mesh box gives a
# particle too: the repeat is the generated card, in a later chunk, found at its node ID's rank;
# a particle on a node no card gives): every rank stops with exit 2 and the one process's line.
bad_particle() { sed "s/^\*END/*ELEMENT_SPH\n$(printf '%8d%8d%16s' "$1" 1 -1.0e-9)\n*END/" "$work/d3.k"; }
bad_particle 5000 >"$work/twice.k"
bad_particle 999999 >"$work/nowhere.k"
for bad in twice nowhere; do
  code=0
  "$cli" run "$work/$bad.k" -o "$work/$bad.serial" >/dev/null 2>"$work/$bad.serial.log" || code=$?
  [ "$code" -eq 2 ] || { cat "$work/$bad.serial.log"; fail "$bad: one process: exit $code, expected 2"; }
  line=$(grep '^error: ' "$work/$bad.serial.log")
  for ranks in 2 3; do
    code=0
    timeout 120 mpirun -np "$ranks" "$cli" run "$work/$bad.k" -o "$work/$bad.np$ranks" >/dev/null \
      2>"$work/$bad.np$ranks.log" || code=$?
    [ "$code" -eq 2 ] || { cat "$work/$bad.np$ranks.log"; fail "$bad on $ranks ranks: exit $code, expected 2"; }
    [ "$(grep '^error: ' "$work/$bad.np$ranks.log")" = "$line" ] ||
      { cat "$work/$bad.np$ranks.log"; fail "$bad on $ranks ranks: not the one process's line: $line"; }
  done
done
grep -q 'particle 5000 is defined twice' "$work/twice.serial.log" || fail "twice: $(cat "$work/twice.serial.log")"
grep -q 'node 999999 is not defined' "$work/nowhere.serial.log" || fail "nowhere: $(cat "$work/nowhere.serial.log")"
echo "mpi fluid: OK"
