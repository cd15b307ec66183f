#!/usr/bin/env bash
# The SPH solid and SPG on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state"), run
# as one process and under mpirun as 1-4 ranks (oversubscribed on 2 cores) with 1 or 2 threads each:
# every history (glstat.csv, rwforc.csv, nodout.csv, matsum.csv ...) is byte for byte the single
# process's, and the field output (a .pvtu per output time of each rank's .vtu piece) holds its .vtu
# files' points and fields bit for bit.
#  - the Taylor bar of examples/taylor_bar, cut short: Johnson-Cook, the corrected gradient, a fixed
#    rigid wall (each rank's own nodes, the force summed over the ranks; the velocities by reach),
#    the force pass taking each pair once (in blocks, of which each rank runs its own and the one
#    before);
#  - the brittle spall of examples/brittle_spall, cut short: the colour-field categorization (each
#    rank's own particles, with the layer flags of the others' that it reads) and prescribed motion;
#  - the compression of examples/compression_iron, cut short: a fixed and a moving rigid wall (which
#    every rank solves whole from every node's velocity);
#  - two particles of a bar on three ranks: a rank with none;
#  - a block of 8 particles driven along a resting elastic layer from before its start to past its
#    end, near enough to drag it: every rank's list rows and the particles they read change as it
#    passes (on 4 ranks, 2 x 2 threads, and 3 rebalanced);
#  - the SPG tensile bar of examples/spg_tension, coarse and pulled fast enough that bonds break
#    within the run (their broken state is every rank's), with KERNEL 0 and ITB 1 as in the example
#    and with KERNEL 1 (bonds searched anew at each update) and ITB 2; and finer across (a core of
#    interior particles, where the integration-constraint correction acts), with both;
#  - solid finite elements, each rank computing the elements with a node it owns: the SPG bar with
#    hexahedral ends (ELFORM 2, eight points an element, interface nodes shared with SPG), and a bar
#    of one-point hexahedra (ELFORM 1, hourglass control) that erode (*MAT_ADD_EROSION at 20 %
#    effective strain: about half the mass) while DT2MS adds mass.
# An SPH bar on the face of a block of hexahedra (shared nodes): each cell's nodes in the piece of the
# rank that writes it with the fields of the ranks that compute them.
# A particle whose neighbourhood collapses stops every rank with the single process's message.
# The Taylor bar, the KERNEL 1 SPG bar and the eroding bar run once more with the nodes dealt out
# anew every 5 steps (the load balancing, forced), and the Taylor bar on 2 ranks writing a restart
# file at every step: still bit for bit.
# The restart files (each SPH particle's state written by its own rank, the rest by rank 0): the
# Taylor bar's and the eroding bar's 2-rank runrsf and both SPG bars' 3-rank ones (the nodes, shape
# functions and correction beyond rank 0's reach completed for it) continued on one process, the
# Taylor bar's and the eroding bar's 3-rank ones on 2 ranks and the Taylor bar's 1-process one on 3,
# end as the uninterrupted runs.
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
# Three history nodes (nodout.csv): the velocity at t^n and the acceleration each from its owner;
# the part's energies and momentum (matsum.csv): each rank's own particles and nodes, exact sums.
sed -i 's/^\*END$/*DATABASE_HISTORY_NODE\n1,2000,4144\n*DATABASE_NODOUT\n1e-6\n*DATABASE_MATSUM\n1e-6\n*END/' \
  "$work/taylor.k"
cut_deck "$source_dir/examples/brittle_spall/brittle_spall.k" 0.01 >"$work/spall.k"
cut_deck "$source_dir/examples/compression_iron/compression_iron.k" 2e-5 >"$work/compression.k"
run_serial taylor 40
run_serial spall 40
run_serial compression 100
[ -s "$work/taylor.serial/rwforc.csv" ] || fail "the Taylor bar wrote no rwforc.csv"
[ "$(cut -d, -f2 "$work/taylor.serial/nodout.csv" | sort -u | tr '\n' ' ')" = "1 2000 4144 node " ] ||
  fail "the Taylor bar's nodout.csv: $(head -n 3 "$work/taylor.serial/nodout.csv")"
awk -F, 'NR > 1 && $2 == 2 && $3 + 0 > 0 { pushed = 1 } END { exit !pushed }' "$work/compression.serial/rwforc.csv" ||
  fail "the moving wall did not push: $(tail -n 1 "$work/compression.serial/rwforc.csv")"
same_on_ranks "$work/taylor.k" "$work/taylor.serial" "2 1" "3 1" "4 1" "2 2" "3 1 rebalanced" "2 1 checkpointed"
same_on_ranks "$work/spall.k" "$work/spall.serial" "2 1" "3 2"
same_on_ranks "$work/compression.k" "$work/compression.serial" "2 1" "3 1 rebalanced"
# The skimmer: the layer (3 x 3 x 30 particles, 1 mm apart, soft elastic) and the 2 x 2 x 2 block
# 1.8 mm beside it (within the kernel's 2.4 mm reach), held in x and y and driven along z at 10 m/s
# (spcforc.csv and bndout.csv: the reactions, exact sums over the ranks).
python3 - >"$work/skimmer.k" <<'PY'
speed, length, dx = 10.0, 30, 1e-3
end = (length + 10) * dx / speed
print("*KEYWORD\n*CONTROL_TERMINATION\n%10.4e" % end)
print("*DATABASE_BINARY_D3PLOT\n%10.4e\n*DATABASE_GLSTAT\n%10.4e" % (end / 4, end / 100))
print("*DATABASE_SPCFORC\n%10.4e" % (end / 100))  # the reactions that hold the skimmer in x and y
print("*DATABASE_BNDOUT\n%10.4e" % (end / 100))  # and that drive it along z
print("*DATABASE_MATSUM\n%10.4e" % (end / 100))
print("*DATABASE_BINARY_RUNRSF\n%10d" % 60)
print("*PART\nlayer and skimmer\n%10d%10d%10d" % (1, 1, 1))
print("*SECTION_SPH\n%10d%10g%10g%10g" % (1, 1.2, 1.0, 1.0))
print("*MAT_ELASTIC\n%10d%10g%10g%10g" % (1, 1000.0, 1.0e6, 0.3))
layer = [(dx * i, dx * j, dx * k) for k in range(length) for j in range(3) for i in range(3)]
skimmer = [(3.8 * dx + dx * i, dx * j, -6 * dx + dx * k) for k in range(2) for j in range(2) for i in range(2)]
print("*NODE")
for n, (x, y, z) in enumerate(layer + skimmer):
    print("%8d%16.8e%16.8e%16.8e" % (n + 1, x, y, z))
print("*ELEMENT_SPH")
for n in range(len(layer + skimmer)):
    print("%8d%8d%16.8e" % (n + 1, 1, -dx ** 3))
print("*DEFINE_CURVE\n%10d\n%20g%20g\n%20g%20g" % (1, 0.0, 1.0, 1.0, 1.0))
print("*BOUNDARY_PRESCRIBED_MOTION_NODE")
for n in range(len(skimmer)):
    print("%10d%10d%10d%10d%10g" % (len(layer) + n + 1, 3, 0, 1, speed))
print("*BOUNDARY_SPC_NODE")
for n in range(len(skimmer)):
    print("%10d%10d%10d%10d%10d" % (len(layer) + n + 1, 0, 1, 1, 0))
print("*END")
PY
run_serial skimmer 100
"${read_vtu[@]}" "$(ls "$work/skimmer.serial"/d3plot_*.vtu | tail -n 1)" --field displacement >"$work/skimmer.last" ||
  fail "the skimmer's last state"
# It ends 5 mm past the layer (displacement 40 mm), and the layer was dragged along (every particle).
awk '$1 == "displacement" && $2 == "max" { exit !($5 > 0.0399) }' "$work/skimmer.last" ||
  fail "the skimmer did not pass the layer: $(grep 'displacement max' "$work/skimmer.last")"
awk '$1 == "displacement" && $2 == "min" { exit !($5 > 0.001) }' "$work/skimmer.last" ||
  fail "the layer was not dragged: $(grep 'displacement min' "$work/skimmer.last")"
same_on_ranks "$work/skimmer.k" "$work/skimmer.serial" "4 1" "2 2" "3 1 rebalanced"
# Two particles on three ranks: rank 0, which writes every file, owns neither.
python3 "$source_dir/tools/make_bar_deck.py" --length 0.05 --width 0.025 --spacing 0.025 --periods 2 >"$work/two.k"
run_serial two
same_on_ranks "$work/two.k" "$work/two.serial" "3 1"
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 16 --speed 100 --end-time 4e-5 >"$work/spg.k"
sed -E 's/^( +1\.6){3} +0 +0 +0\.0 +15 +0\.0$/       1.6       1.6       1.6         0         1       0.0        15       0.0/;
        s/^( +1 +0\.6 +1\.2) +1$/\1         2/' "$work/spg.k" >"$work/spg_k1.k"
[ "$(diff "$work/spg.k" "$work/spg_k1.k" | grep -c '^>')" -eq 2 ] || fail "the KERNEL 1, ITB 2 deck"
sed -i 's/^\*END$/*DATABASE_BINARY_RUNRSF\n       300\n*END/' "$work/spg.k"
for deck in spg spg_k1; do
  run_serial $deck 400
  "${read_vtu[@]}" "$(ls "$work/$deck.serial"/d3plot_*.vtu | tail -n 1)" --field broken_bonds >"$work/$deck.bonds"
  grep -Eq '^broken_bonds max [1-9]' "$work/$deck.bonds" || fail "$deck: no bond broke ($(cat "$work/$deck.bonds"))"
done
same_on_ranks "$work/spg.k" "$work/spg.serial" "2 1" "3 2" "3 1 checkpointed"
same_on_ranks "$work/spg_k1.k" "$work/spg_k1.serial" "3 1 fixed" "2 1 rebalanced"
# The KERNEL 1 bar as two SPG parts (its halves along the bar, sharing the nodes between them): each
# part plans what it reads at its own points, and a rank's window of the nodes holds both parts'
# (SpgFormulation::hold_nodes).
python3 - "$work/spg_k1.k" >"$work/spg_parts.k" <<'PY'
import sys
lines, out, elements = open(sys.argv[1]).read().split("\n"), [], False
for line in lines:
    if line.startswith("*"):
        elements = line.startswith("*ELEMENT_SOLID")
    elif elements and line.strip() and not line.startswith("$"):
        eid = int(line.split()[0])
        line = "%8d%8d" % (eid, 1 if (eid - 1) % 16 < 8 else 2) + line[16:]  # 16 elements along x first
    out.append(line)
deck = "\n".join(out)
print(deck.replace("*SECTION_SOLID_SPG", "*PART\nsecond half\n         2         1         1\n*SECTION_SOLID_SPG", 1), end="")
PY
[ "$(grep -c '^\*PART' "$work/spg_parts.k")" -eq 2 ] || fail "the two-part SPG deck"
sed -i 's/^\*END$/*DATABASE_MATSUM\n2e-6\n*END/' "$work/spg_parts.k"  # each part's energies
run_serial spg_parts 400
same_on_ranks "$work/spg_parts.k" "$work/spg_parts.serial" "3 1 rebalanced" "4 1 fixed"
# The SPG bar with 6 elements across: particles two rings of bonds inside the surface, where the
# integration-constraint correction acts (each rank solves for its own particles, the partners'
# multipliers, defect terms and correction rows brought in), 5 kernel updates, with KERNEL 0 and
# ITB 1, and with KERNEL 1 and ITB 2.
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 32 --speed 100 --end-time 2e-6 |
  sed 's/^\*END$/*DATABASE_BINARY_RUNRSF\n        40\n*END/' >"$work/spg_core.k"
sed -E 's/^( +1\.6){3} +0 +0 +0\.0 +15 +0\.0$/       1.6       1.6       1.6         0         1       0.0        15       0.0/;
        s/^( +1 +0\.6 +1\.2) +1$/\1         2/' "$work/spg_core.k" >"$work/spg_core_k1.k"
[ "$(diff "$work/spg_core.k" "$work/spg_core_k1.k" | grep -c '^>')" -eq 2 ] || fail "the KERNEL 1, ITB 2 core deck"
run_serial spg_core 75
run_serial spg_core_k1 75
same_on_ranks "$work/spg_core.k" "$work/spg_core.serial" "3 1 fixed" "2 2" "3 1 rebalanced"
same_on_ranks "$work/spg_core_k1.k" "$work/spg_core_k1.serial" "3 1" "2 1 rebalanced"

python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 16 --speed 100 --end-time 4e-5 --fem-ends 0.25 \
  >"$work/fem_ends.k"
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 16 --speed 100 --end-time 6e-5 --fem-ends 0.5 |
  python3 -c '
import re, sys
deck = sys.stdin.read()
deck = re.sub(r"\*PART\ntensile bar\n.*\n.*\n", "", deck, count=1)  # every element is part 2
deck = re.sub(r"\*SECTION_SOLID_SPG\n(?:.*\n){6}", "", deck, count=1)
deck = deck.replace("         2         2\n", "         2         1\n", 1)  # ELFORM 1
deck = deck.replace("       0.0       0.9\n", "       0.0       0.9         0       0.0   -1.2e-7\n", 1)  # DT2MS
deck = deck.replace("*NODE", "*MAT_ADD_EROSION\n         1       0.0       0.0       0.0       0.2\n*NODE", 1)
sys.stdout.write(deck)' >"$work/eroding.k"
sed -i 's/^\*END$/*DATABASE_BINARY_RUNRSF\n       100\n*END/' "$work/eroding.k"
# Element histories (elout.csv) of elements that erode (1, 72, 144) and one that does not (3).
# And matsum.csv: the elements each rank books, those that eroded left out, the hourglass energy.
sed -i 's/^\*END$/*DATABASE_HISTORY_SOLID\n1,3,72,144\n*DATABASE_ELOUT\n1e-5\n*DATABASE_MATSUM\n1e-5\n*END/' \
  "$work/eroding.k"
sed -i 's/^\*END$/*DATABASE_MATSUM\n4e-6\n*END/' "$work/fem_ends.k"  # SPG and FEM parts' energies
run_serial fem_ends 300
run_serial eroding 300
grep -q 'one-point hexahedra' "$work/eroding.log" || fail "the eroding bar is not ELFORM 1"
tail -n 1 "$work/eroding.serial/glstat.csv" | awk -F, '{ exit !($10 > 1e-4 && $10 < 2e-4 && $11 > 0) }' ||
  fail "the eroding bar: eroded and added mass $(tail -n 1 "$work/eroding.serial/glstat.csv")"
same_on_ranks "$work/fem_ends.k" "$work/fem_ends.serial" "2 1" "3 2"
same_on_ranks "$work/eroding.k" "$work/eroding.serial" "2 1" "3 1 fixed" "2 2" "3 1 rebalanced"
# The solid elements bring in the velocities of their elements' nodes alone (docs/SCALING.md, "Solid
# elements, rigid bodies and contact by reach"); the eroding bar's masses, which DT2MS raises every
# step, stay at their nodes' ranks until a new deal or a checkpoint.
for run in fem_ends.serial.np2.t1 eroding.serial.np3.t1.rebalanced; do
  grep -q '"halo": "by reach"' "$work/$run/run.json" || fail "$run: the velocities do not go by reach"
done
# Alone in a deck, the solid elements hold a window of the node order on each rank, not every node
# (docs/SCALING.md, "The solid elements' window of the nodes").
# So does SPG (docs/SCALING.md, "SPG's window of the nodes"). Of runs whose deal stays the first
# (fixed): one dealt anew by the work measured could give a rank most of the nodes on a loaded machine.
for run in eroding.serial.np3.t1.fixed spg_core.serial.np3.t1.fixed spg_k1.serial.np3.t1.fixed \
  spg_parts.serial.np4.t1.fixed; do
  rows=$(grep -o '"node_rows": {"mean": [0-9.]*, "max": [0-9]*' "$work/$run/run.json" | grep -o '[0-9]*$')
  nodes=$(grep -o '"nodes": [0-9]*' "$work/$run/run.json" | grep -o '[0-9]*$')
  [ "$rows" -lt "$nodes" ] || fail "$run: a rank holds $rows rows of $nodes nodes"
done

# An SPH bar whose first layer of particles sits on the last face of a block of hexahedra (shared
# nodes), pulled apart there: a rank writes a cell of its own with a particle another rank computes,
# whose fields come from that rank (a stale copy fails same_fields: a node written twice).
python3 - >"$work/on_cells.k" <<'PY'
dx, n, w = 0.025, 40, 4
print("*KEYWORD\n*CONTROL_TERMINATION\n2.0e-5\n*DATABASE_BINARY_D3PLOT\n5.0e-6\n*DATABASE_GLSTAT\n1.0e-6")
print("*PART\nbar\n1,1,1\n*SECTION_SPH\n1,1.2\n*MAT_ELASTIC\n1,7850.0,2.0e11,0.3\n*PART\nblock\n2,2,1\n*SECTION_SOLID\n2,1")
nid = {(i, j, k): 1 + (i + 4) * w * w + j * w + k for i in range(-4, n) for j in range(w) for k in range(w)}
print("*NODE")
for (i, j, k), node in nid.items():
    print(f"{node},{(i + 0.5) * dx},{(j + 0.5) * dx},{(k + 0.5) * dx}")
print("*ELEMENT_SPH")
for (i, j, k), node in nid.items():
    if i >= 0:
        print(f"{node},1,{7850 * dx ** 3}")
print("*ELEMENT_SOLID")
cells = [(i, j, k) for i in range(-4, 0) for j in range(w - 1) for k in range(w - 1)]
for e, (i, j, k) in enumerate(cells, 1):
    corners = [(i, j, k), (i + 1, j, k), (i + 1, j + 1, k), (i, j + 1, k)]
    corners += [(a, b, c + 1) for a, b, c in corners]
    print(f"{e},2," + ",".join(str(nid[c]) for c in corners))
layer = [str(nid[(0, j, k)]) for j in range(w) for k in range(w)]
print("*SET_NODE_LIST\n1\n" + "\n".join(",".join(layer[m:m + 8]) for m in range(0, len(layer), 8)))
print("*INITIAL_VELOCITY\n1\n-10.0,0.0,0.0\n*END")
PY
run_serial on_cells 5
same_on_ranks "$work/on_cells.k" "$work/on_cells.serial" "2 1 fixed" "3 1 fixed"

# A particle whose neighbourhood collapses (test_cli.sh's treated ductile block at 1.7 x the stable
# factor): every rank stops with exit 3 and the single process's line, the particle's density and h
# from the rank that computes it.
python3 "$source_dir/tools/make_compression_deck.py" --scene ductile --across 8 --treat 1 |
  sed 's/^       0.0       0.9$/       0.0       1.7/' >"$work/collapse.k"
collapse_line() { grep -E "numerical instability at step [0-9]+, time .*: SPH solid: node [0-9]+ has density" "$1"; }
set +e
"$cli" run "$work/collapse.k" -o "$work/collapse.serial" --threads 1 >"$work/collapse.log" 2>&1
code=$?
set -e
[ "$code" -eq 3 ] && collapse_line "$work/collapse.log" >/dev/null || { cat "$work/collapse.log"; fail "collapse: exit $code"; }
for ranks in 2 3; do
  set +e
  timeout 300 mpirun -np $ranks "$cli" run "$work/collapse.k" -o "$work/collapse.np$ranks" --threads 1 \
    >"$work/collapse.np$ranks.log" 2>&1
  code=$?
  set -e
  [ "$code" -eq 3 ] || { tail -20 "$work/collapse.np$ranks.log"; fail "collapse on $ranks ranks: exit $code"; }
  [ "$(collapse_line "$work/collapse.np$ranks.log" | sort -u)" = "$(collapse_line "$work/collapse.log")" ] ||
    fail "collapse on $ranks ranks: $(collapse_line "$work/collapse.np$ranks.log") against $(collapse_line "$work/collapse.log")"
done

# The 2-rank runs' last restart files continued on one process (the SPH particles' state written by
# the rank that computes each, the rest by rank 0), the Taylor bar's 3-rank file on 2 ranks, and
# its 2-rank folder, which the single process continued, once more on 3 ranks.
for deck in taylor eroding; do
  [ -s "$work/$deck.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank run ($deck)"
  continue_run $deck.serial.np2.t1 1 $deck.serial
done
continue_run taylor.serial.np3.t1 2 taylor.serial
continue_run eroding.serial.np3.t1.fixed 2 eroding.serial
continue_run spg.serial.np3.t2 1 spg.serial
continue_run spg_core.serial.np3.t1.fixed 1 spg_core.serial
continue_run spg_core.serial.np2.t2 3 spg_core.serial
continue_run taylor.serial.np2.t1 3 taylor.serial
# The skimmer's 2-rank run continued on one process: bndout.csv's work goes on from the file's.
continue_run skimmer.serial.np2.t2 1 skimmer.serial
echo "mpi solid: OK"
