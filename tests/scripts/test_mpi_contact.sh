#!/usr/bin/env bash
# Contact and rigid bodies on several MPI ranks (issue 35; docs/SCALING.md, "Replicated state" and
# "Solid elements, rigid bodies and contact by reach"): each rank answers the touches of its own
# slave nodes and every rank gathers every touch; every rank computes every rigid body, its nodes'
# forces brought in from their ranks; with every contact's segments a body's, only the velocities
# the formulations read travel. Run as one process and under mpirun
# as 2-3 ranks (oversubscribed on 2 cores) with 1 or 2 threads each, every history (glstat.csv,
# rcforc.csv, rbdout.csv, the drill's spcforc.csv) is byte for byte the single process's and the
# .pvtu pieces hold its fields bit for bit:
#  - the rotating punch of tools/make_punch_deck.py: a rigid cylinder (*MAT_RIGID, prescribed
#    plunge and spin) pressed into a block of hexahedra through *CONTACT_AUTOMATIC_NODES_TO_SURFACE
#    with Coulomb friction (thrust and friction torque in rcforc.csv, the body's force in rbdout.csv);
#  - the same punch left free to turn (only the plunge prescribed): its spin is the friction
#    torque's, summed over the forces of every rank's nodes;
#  - a rigid cap on an SPG column, sharing nodes with it: the body's motion is the sum of forces
#    that several ranks computed;
#  - the punch made elastic and thrown at the block: the segments deform, and every velocity
#    travels each step;
#  - an elastic block thrown onto a plate whose top layer erodes (*MAT_ADD_EROSION FAILTM), through
#    *CONTACT_ERODING_SURFACE_TO_SURFACE (EROSOP 1): the faces of the eroded elements leave the
#    contact and the layer below's top faces enter it, as every rank learns which elements eroded;
#  - the coarse friction-drilling deck of test_drilling, cut after the tool has entered the sheet:
#    SPG and hexahedra sharing nodes, bonds breaking, the rigid drill in frictional contact; on 2
#    ranks also with the nodes dealt out anew every 5 steps (the load balancing, forced).
# The 2-rank punch's runrsf, continued on 3 ranks and on one process, the 3-rank punch's in fixed
# blocks, continued on one process, the 2-rank eroding plate's (which faces are in the contact),
# continued on 3 ranks, and the 2-rank drill's (SPG's DT2MS masses raised by each rank
# for its own particles), continued on 3 ranks, end as the uninterrupted run.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

source "$source_dir/tests/scripts/mpi_common.sh"

python3 "$source_dir/tools/make_punch_deck.py" --end-time 2e-5 --outputs 4 >"$work/punch.k"
sed -i 's/^\*END$/*DATABASE_BINARY_RUNRSF\n       200\n*END/' "$work/punch.k"
run_serial punch 400
# Pressed in: the thrust on the block (side 1, fz) and the friction torque about the axis (mz).
awk -F, '$3 == 1 { last = $0; fz = $6; mz = $9 } END { print last; exit !(fz < -1000 && mz > 0.1) }' \
  "$work/punch.serial/rcforc.csv" >"$work/punch.last" || fail "the punch does not press and turn: $(cat "$work/punch.last")"
# The punch's segments are a rigid body's: each rank brings in only the velocities its formulations
# read (the halo by reach), the body's nodes' forces from their ranks. On 3 ranks in fixed blocks a
# rank holds top-surface nodes that it neither owns nor reads, and must add no touch's force to them:
# it would go uncleared and reach the restart file, or a later deal's new owner (a continued run
# below; the rebalanced one deals anew every 5 steps).
same_on_ranks "$work/punch.k" "$work/punch.serial" "2 1" "3 1" "2 2" "3 1 fixed" "3 1 rebalanced"

# The spin prescribed until 1e-5 s (DEATH on its *BOUNDARY_PRESCRIBED_MOTION_RIGID DOF 7 card): then
# the moment of the contact forces on the punch's nodes alone turns it (the punch, stuck to the block
# by friction, rings against the block's torsional stiffness).
python3 - "$work/punch.k" >"$work/free.k" <<'PY'
import re, sys
deck = open(sys.argv[1]).read()
spin = re.compile(r"(\*BOUNDARY_PRESCRIBED_MOTION_RIGID\n(?:\$.*\n)*\s*\d+\s+7\s.*)\n")
assert len(spin.findall(deck)) == 1, "one prescribed spin"
sys.stdout.write(spin.sub(lambda m: m.group(1) + "         0    1.0e-5\n", deck))
PY
run_serial free 400
awk -F, '$1 > 1.1e-5 { w = $11 > 0 ? $11 : -$11; if (w > most) most = w } END { exit !(most > 100) }' \
  "$work/free.serial/rbdout.csv" || fail "the released punch does not turn"
same_on_ranks "$work/free.k" "$work/free.serial" "2 1" "3 2"

# A rigid cap of hexahedra (*MAT_RIGID) on an elastic SPG column (*SECTION_SOLID_SPG), sharing its
# top nodes, thrown down at 20 m/s onto the column held at its foot: the cap slows and rebounds by
# the SPG forces on the shared nodes, which each rank computes for its own nodes only (the halo
# brings the other ranks' in before the body sums them).
python3 - >"$work/cap.k" <<'PY'
n, h = 2, 2.5e-3  # elements across, element size
layers = 16     # the column's; the cap is one more
print("*KEYWORD\n*CONTROL_TERMINATION\n    3.0e-5\n*DATABASE_BINARY_D3PLOT\n    1.0e-5\n*DATABASE_GLSTAT\n    1.0e-6")
print("*DATABASE_RBDOUT\n    1.0e-6")
print("*PART\ncolumn\n         1         1         1\n*PART\ncap\n         2         2         2")
print("*SECTION_SOLID_SPG\n         1        47\n       1.6       1.6       1.6         0         0       0.0        15")
print("         1       0.6       1.2         1\n*SECTION_SOLID\n         2         1")
print("*MAT_ELASTIC\n         1    7850.0   2.0e+11       0.3")
print("*MAT_RIGID\n         2   78500.0   2.0e+11       0.3\n       0.0         0         0\n       0.0")
node = lambda i, j, k: 1 + i + (n + 1) * (j + (n + 1) * k)
print("*NODE")
for k in range(layers + 2):
    for j in range(n + 1):
        for i in range(n + 1):
            print(f"{node(i, j, k):8d}{i * h:16.8e}{j * h:16.8e}{k * h:16.8e}")
print("*ELEMENT_SOLID")
e = 0
for k in range(layers + 1):
    for j in range(n):
        for i in range(n):
            e += 1
            corners = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)]
            corners += [c + (n + 1) ** 2 for c in corners]
            print(f"{e:8d}{2 if k == layers else 1:8d}" + "".join(f"{c:8d}" for c in corners))
print("*SET_NODE_LIST\n         1\n" + "".join(f"{node(i, j, 0):10d}" for j in range(n + 1) for i in range(n + 1)))
print("*BOUNDARY_SPC_SET\n         1         0         1         1         1         0         0         0")
print("*INITIAL_VELOCITY_GENERATION\n         2         2       0.0       0.0       0.0     -20.0\n       0.0       0.0       0.0")
print("*END")
PY
run_serial cap 60
awk -F, 'NR > 1 { vz = $8 } END { exit !(vz > -15) }' "$work/cap.serial/rbdout.csv" ||
  fail "the cap does not slow down: $(tail -n 1 "$work/cap.serial/rbdout.csv")"
same_on_ranks "$work/cap.k" "$work/cap.serial" "2 1" "3 1"

# The punch made elastic and thrown at the block (20 m/s; it bounces off by 4 us): the contact's
# segments are deformable, any rank's nodes, so every velocity travels each step ("every node").
python3 - "$work/punch.k" >"$work/soft.k" <<'PY'
import re, sys
deck = open(sys.argv[1]).read()
deck, n = re.subn(r"\*MAT_RIGID\n(?:\$.*\n)?.*\n(?:\$.*\n)?.*\n", "*MAT_ELASTIC\n         2    7850.0    2.0e11       0.3\n", deck)
assert n == 1, "one *MAT_RIGID"
deck, n = re.subn(r"\*BOUNDARY_PRESCRIBED_MOTION_RIGID\n(?:\$.*\n)?.*\n", "", deck)
assert n == 2, "two prescribed motions"
deck = deck.replace("*CONTACT_AUTOMATIC", "*INITIAL_VELOCITY_GENERATION\n         2         2       0.0       0.0       0.0     -20.0\n"
                    "       0.0       0.0       0.0\n*CONTACT_AUTOMATIC", 1)
deck = re.sub(r"(\*CONTROL_TERMINATION\n(?:\$.*\n)*)\s*\S+", lambda m: m.group(1) + "    4.0e-6", deck)
sys.stdout.write(deck)
PY
run_serial soft 100
awk -F, '$3 == 1 { f = $6 < 0 ? -$6 : $6; if (f > most) most = f } END { exit !(most > 1000) }' "$work/soft.serial/rcforc.csv" ||
  fail "the elastic punch does not press on the block"
same_on_ranks "$work/soft.k" "$work/soft.serial" "2 1" "3 1 rebalanced"
grep -q '"halo": "every node"' "$work/soft.serial.np2.t1/run.json" || fail "soft: the deformable segments' velocities by reach"

# The eroding plate: 8 x 8 x 3 hexahedra of 1 mm (the bottom two layers part 2, the top one part 3,
# deleted at 2 us), the 4 x 4 x 2 block (part 1) on its middle at 200 m/s down: it presses on part 3,
# flies through the 1 mm it leaves and meets part 2's top faces from 7 us on.
python3 - >"$work/plate.k" <<'PY'
h, n, layers = 1e-3, 8, 3
print("*KEYWORD\n*CONTROL_TERMINATION\n   1.2e-05\n*DATABASE_BINARY_D3PLOT\n    4.0e-6\n*DATABASE_GLSTAT\n    2.0e-7")
print("*DATABASE_RCFORC\n    2.0e-7\n*DATABASE_MATSUM\n    2.0e-7\n*DATABASE_BINARY_RUNRSF\n        10")
for pid in (1, 2, 3):
    print(f"*PART\npart {pid}\n{pid:10d}{pid:10d}{pid:10d}\n*SECTION_SOLID\n{pid:10d}         1")
    print(f"*MAT_ELASTIC\n{pid:10d}    7850.0   2.0e+10       0.3")
print("*MAT_ADD_EROSION\n         3\n" + " " * 70 + "    2.0e-6")
def lattice(first, origin, counts, part_of):
    nx, ny, nz = counts
    node = lambda i, j, k: first + i + (nx + 1) * (j + (ny + 1) * k)
    print("*NODE")
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                print(f"{node(i, j, k):8d}{origin[0] + i * h:16.8e}{origin[1] + j * h:16.8e}{origin[2] + k * h:16.8e}")
    print("*ELEMENT_SOLID")
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                c = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)]
                c += [x + (nx + 1) * (ny + 1) for x in c]
                print(f"{node(i, j, k):8d}{part_of(k):8d}" + "".join(f"{x:8d}" for x in c))
    return [node(i, j, 0) for j in range(ny + 1) for i in range(nx + 1)]
bottom = lattice(1, (0, 0, 0), (n, n, layers), lambda k: 3 if k == layers - 1 else 2)
lattice(10001, (2 * h, 2 * h, layers * h), (4, 4, 2), lambda k: 1)
print("*SET_NODE_LIST\n         1\n" + "".join(f"{x:10d}" + ("\n" if i % 8 == 7 else "") for i, x in enumerate(bottom)))
print("*BOUNDARY_SPC_SET\n         1         0         1         1         1         0         0         0")
print("*SET_PART_LIST\n         1\n         2         3")
print("*CONTACT_ERODING_SURFACE_TO_SURFACE_ID\n         1\n         1         1         3         2")
print("       0.2       0.2       0.0       0.0      20.0\n\n         0         1         0")
print("*INITIAL_VELOCITY_GENERATION\n         1         2       0.0       0.0       0.0    -200.0\n       0.0       0.0       0.0")
print("*END")
PY
run_serial plate 20
# The block presses on the plate before 2 us and again once it reaches part 2 (rcforc.csv, side 1's fz).
awk -F, '$3 == 1 && $1 < 2e-6 && $6 > 1 { before = 1 } $3 == 1 && $1 > 7e-6 && $6 > 1 { after = 1 }
  END { exit !(before && after) }' "$work/plate.serial/rcforc.csv" ||
  fail "the block does not meet the faces erosion exposed: $(grep -c . "$work/plate.serial/rcforc.csv") rows"
same_on_ranks "$work/plate.k" "$work/plate.serial" "2 1" "3 2" "3 1 rebalanced"
[ -s "$work/plate.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank plate"
continue_run plate.serial.np2.t1 3 plate.serial

python3 "$source_dir/tools/make_drilling_deck.py" --spacing 0.4e-3 --layers 4 --ring-layers 3 --segments 24 \
  --time-scale 2000 --dt2ms=-2e-7 --smstep 15 --outputs 2 --histories 200 >"$work/drill_full.k"
cut_deck "$work/drill_full.k" 3e-4 700 >"$work/drill.k"
run_serial drill 1000
awk -F, '$3 == 2 { last = $0; fz = $6 } END { print last; exit !(fz > 500) }' "$work/drill.serial/rcforc.csv" \
  >"$work/drill.last" || fail "the drill does not press on the sheet: $(cat "$work/drill.last")"
same_on_ranks "$work/drill.k" "$work/drill.serial" "2 1" "3 2" "2 1 rebalanced"
# The punch's and the drill's segments are a rigid body's: their runs go by reach (run.json).
for run in punch.serial.np3.t1.fixed drill.serial.np2.t1; do
  grep -q '"halo": "by reach"' "$work/$run/run.json" || fail "$run: the velocities do not go by reach"
done
[ -s "$work/drill.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank drill"
continue_run drill.serial.np2.t1 3 drill.serial

# The 2-rank punch's runrsf (the friction forces of the touches in it) continued on 3 ranks and on one
# process.
[ -s "$work/punch.serial.np2.t1/runrsf" ] || fail "no runrsf from the 2-rank punch"
cp -r "$work/punch.serial.np2.t1" "$work/punch.on3"
continue_run punch.on3 3 punch.serial
continue_run punch.serial.np2.t1 1 punch.serial
continue_run punch.serial.np3.t1.fixed 1 punch.serial
echo "mpi contact: OK"
