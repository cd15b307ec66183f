#!/usr/bin/env bash
# The command line as a user meets it: a run writes a ParaView series that VTK's own reader opens
# (Debian's python3-vtk9), glstat.csv, run.json and a copy of the deck; a rigid wall's forces go
# to rwforc.csv; bad input is one `file:line: *KEYWORD:` line and exit 2; an unsupported keyword
# is a warning with name and line; an unstable run exits 3 and leaves its last state; an SPG run
# writes its bond fields and an SPG option without an implementation is exit 2 naming the field;
# a rigid body's motion goes to rbdout.csv, history nodes' to nodout.csv; every public deck goes
# through `spall check` with exit 0 or 2, never a crash.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
shared_dir=$3
read_vtu=("/usr/bin/python3" "$source_dir/tools/read_vtu.py")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# DECK PATTERN WHAT: `spall check DECK` stops with exit 2 and a line matching PATTERN.
expect_input_error() {
  local code=0
  "$cli" check "$1" 2>"$1.log" || code=$?
  [ $code -eq 2 ] && grep -Eq "$2" "$1.log" || fail "$3: exit $code, $(cat "$1.log")"
}

"$cli" --version | grep -q '^spall ' || fail "--version"

# A coarse bar, a quarter period.
python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.025 --periods 0.25 >"$work/bar.k"
"$cli" run "$work/bar.k" -o "$work/out" 2>"$work/run.log" || { cat "$work/run.log"; fail "run"; }
# Its part's energies (*DATABASE_MATSUM): the steel bar (1 x 0.1 x 0.1 m, M = 78.5 kg) starts with
# v = V cos(pi x / L), V = 1 m/s, whose kinetic energy on the cell-centred lattice is M V^2 / 4 =
# 19.625 J (the mean of cos^2 over the cells is 1/2 exactly; to 1e-6, the deck's velocities have six
# digits); after a quarter period it is mostly the bar's internal energy (over 90 %), and the two
# sum to it to 1 % (the artificial viscosity dissipates 0.3 %, glstat).
sed 's/^\*END$/*DATABASE_MATSUM\n1e-5\n*END/' "$work/bar.k" >"$work/bar_matsum.k"
"$cli" run "$work/bar_matsum.k" -o "$work/bar_matsum" 2>"$work/bar_matsum.log" ||
  { cat "$work/bar_matsum.log"; fail "the bar with part energies"; }
awk -F, 'NR == 2 { start = ($4 - 19.625) ^ 2 < (1e-6 * 19.625) ^ 2 && $3 == 0 }
  END { exit !(start && $3 > 0.9 * 19.625 && ($3 + $4 - 19.625) ^ 2 < (0.01 * 19.625) ^ 2) }' \
  "$work/bar_matsum/matsum.csv" || fail "the bar's energies: $(sed -n '2p;$p' "$work/bar_matsum/matsum.csv")"
grep -q 'node-steps/s' "$work/run.log" || fail "no progress line"
last=$(ls "$work/out"/d3plot_*.vtu | tail -n 1)
"${read_vtu[@]}" "$last" --field velocity --field displacement --field pressure --field von_mises \
  --field density --field part_id --field node_id --field stress >"$work/fields" || fail "VTK could not read $last"
grep -qx 'points 640' "$work/fields" || fail "point count: $(grep points "$work/fields")"
grep -qx 'part_id min 1' "$work/fields" || fail "part_id"
grep -qx 'node_id max 640' "$work/fields" || fail "node_id"
# After a quarter period the bar is strained: a displacement and a pressure, not zeros.
awk '/^displacement magnitude_max/ { exit !($2 > 1e-6) }' "$work/fields" || fail "displacement is zero"
awk '/^pressure max/ { exit !($2 > 1e5) }' "$work/fields" || fail "pressure is zero"
grep -c '<DataSet' "$work/out/d3plot.pvd" | awk '{ exit !($1 >= 5) }' || fail "pvd series"
head -n 1 "$work/out/glstat.csv" | grep -q '^time \[time\],dt \[time\],kinetic_energy' || fail "glstat header"
grep -q '"status": "completed"' "$work/out/run.json" || fail "run.json"
cmp -s "$work/bar.k" "$work/out/deck/bar.k" || fail "deck copy"
# The SPH solid's residual-stress report (seed 000): a row per part and particle category at the end.
head -n 1 "$work/out/residual.csv" | grep -q '^time \[time\],part,category,particles' || fail "residual.csv header"
awk -F, 'NR > 1 && $2 == 1 && $4 > 0 { rows++ } END { exit !(rows >= 1) }' "$work/out/residual.csv" ||
  fail "residual.csv has no row of part 1"
# The energies do not depend on the thread count either (exact sums, parallel::exact_sum; a bar
# of more than 8192 nodes, so that each thread sums thousands of them).
python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.01 --width 0.1 --periods 0.02 >"$work/bar_threads.k"
"$cli" run "$work/bar_threads.k" -o "$work/threads1" --threads 1 2>/dev/null || fail "1-thread run"
"$cli" run "$work/bar_threads.k" -o "$work/threads2" --threads 2 2>/dev/null || fail "2-thread run"
cmp -s "$work/threads1/glstat.csv" "$work/threads2/glstat.csv" || fail "glstat.csv differs between 1 and 2 threads"

# Without *DATABASE_BINARY_D3PLOT a run still leaves its first and last state for d3plot.pvd; so
# does a run that ENDENG stops early (here at once: a 1e-12 % change of the energy ratio).
sed '/^\*DATABASE_BINARY_D3PLOT$/,+2d' "$work/bar.k" >"$work/no_d3plot.k"
"$cli" run "$work/no_d3plot.k" -o "$work/no_d3plot_out" 2>"$work/no_d3plot.log" || { cat "$work/no_d3plot.log"; fail "run without d3plot"; }
[ "$(ls "$work/no_d3plot_out"/d3plot_*.vtu | wc -l)" -eq 2 ] || fail "without *DATABASE_BINARY_D3PLOT: $(ls "$work/no_d3plot_out")"
[ "$(grep -c '<DataSet' "$work/no_d3plot_out/d3plot.pvd")" -eq 2 ] || fail "pvd without *DATABASE_BINARY_D3PLOT"
grep -q 'timestep="0"' "$work/no_d3plot_out/d3plot.pvd" || fail "no first state in d3plot.pvd"
sed 's/^9\.9058e-05         0       0\.0       0\.0       0\.0$/9.9058e-05         0       0.0     1e-12       0.0/' \
  "$work/no_d3plot.k" >"$work/endeng.k"
grep -q '1e-12' "$work/endeng.k" || fail "ENDENG deck"
"$cli" run "$work/endeng.k" -o "$work/endeng_out" 2>"$work/endeng.log" || { cat "$work/endeng.log"; fail "run with ENDENG"; }
[ "$(ls "$work/endeng_out"/d3plot_*.vtu | wc -l)" -eq 2 ] || fail "ENDENG: $(ls "$work/endeng_out")"
awk -F, 'END { exit !($1 < 9e-5) }' "$work/endeng_out/glstat.csv" || fail "ENDENG did not stop the run early"

# A bar at rest has no energy ratio (0/0): "n/a" in the summary, nan in glstat.csv, null in run.json.
python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.025 --periods 0.02 --amplitude 0 >"$work/rest.k"
"$cli" run "$work/rest.k" -o "$work/rest_out" 2>"$work/rest.log" || { cat "$work/rest.log"; fail "run at rest"; }
grep -q 'energy ratio n/a' "$work/rest.log" || { cat "$work/rest.log"; fail "summary of a model at rest"; }
tail -n 1 "$work/rest_out/glstat.csv" | awk -F, '{ exit !($NF == "nan") }' || fail "glstat ratio at rest: $(tail -n 1 "$work/rest_out/glstat.csv")"
grep -q '"energy_ratio": null' "$work/rest_out/run.json" || fail "run.json energy_ratio at rest"
grep -Eq '"energy_ratio": 0\.9|"energy_ratio": 1' "$work/out/run.json" || fail "run.json energy_ratio of the bar"

# Node histories (*DATABASE_HISTORY_NODE and _SET, *DATABASE_NODOUT): the bar at rest falling
# under *LOAD_BODY_Z (g = 9.81, every node feels -m g) moves as one body, and central differences
# integrate a constant acceleration exactly: u_z = -g t^2 / 2, v_z = -g t, a_z = -g at every
# output time (Newton), for node 1 and the set {2, 3, 1}, each node once, in the deck's order.
# u_z = x - X of nodes at z = 0.0125 m, whose positions are spaced 2^-59 m = 1.7e-18 m apart: u_z to
# 1e-9 and two of those spacings (4e-8 of the first step's u_z, 4e-11 m; the last digits of dt and
# so of x follow the host's libm).
awk '/^\*END/ { print "*DEFINE_CURVE\n77\n0.0,1.0\n1.0,1.0\n*LOAD_BODY_Z\n77,9.81\n*SET_NODE_LIST\n5\n2,3,1\n" \
  "*DATABASE_HISTORY_NODE\n1\n*DATABASE_HISTORY_NODE_SET\n5\n*DATABASE_NODOUT\n2e-6" } { print }' "$work/rest.k" >"$work/fall.k"
"$cli" run "$work/fall.k" -o "$work/fall_out" 2>"$work/fall.log" || { cat "$work/fall.log"; fail "run with history nodes"; }
head -n 1 "$work/fall_out/nodout.csv" | grep -q '^time \[time\],node,ux \[length\],uy \[length\],uz \[length\],vx \[velocity\]' ||
  fail "nodout header: $(head -n 1 "$work/fall_out/nodout.csv")"
awk -F, 'NR > 1 { rows++; if ((NR - 2) % 3 + 1 != $2) order = 1
  g = 9.81; t = $1; if ($11 + g > 1e-9 * g || $11 + g < -1e-9 * g) bad = 1
  u = g * t * t / 2; if (t > 0 && ($5 + u) ^ 2 > (1e-9 * u + 3.5e-18) ^ 2) bad = 1
  if (t > 0 && (($8 + g * t) / (g * t) > 1e-9 || ($8 + g * t) / (g * t) < -1e-9)) bad = 1 }
  END { exit !(rows >= 9 && rows % 3 == 0 && !order && !bad) }' "$work/fall_out/nodout.csv" ||
  fail "nodout.csv is not free fall of nodes 1, 2, 3: $(cat "$work/fall_out/nodout.csv")"
sed 's/^\*DATABASE_HISTORY_NODE$/&\n99999/' "$work/fall.k" >"$work/fall_bad.k"
expect_input_error "$work/fall_bad.k" 'fall_bad\.k:[0-9]+: \*DATABASE_HISTORY_NODE: node 99999 does not exist' \
  "a history node that does not exist"

# SPC reactions (*DATABASE_SPCFORC): a steel column 0.1 x 0.1 x 1 m (rho 7850) of 2 x 2 x 10
# fully integrated hexahedra standing on its base (every base node held by *BOUNDARY_SPC_SET) under
# gravity, damped critically in its first mode (2 omega = pi c / L = 15 860 /s) for 3 ms: at rest
# the base carries the column's weight, Newton's third law, R_z = M g = 7850 x 0.01 x 9.81 N =
# 770.085 N (to 1e-6; the elements' forces sum to zero), and nothing across (|R_x|, |R_y| < 1e-6 M g).
python3 - >"$work/column.k" <<'PY'
end, n, m = 3e-3, 2, 10
a, h = 0.1 / n, 1.0 / m
print("*KEYWORD\n*CONTROL_TERMINATION\n%10.4e\n*DATABASE_SPCFORC\n%10.4e" % (end, end / 50))
print("*PART\ncolumn\n1,1,1\n*SECTION_SOLID\n1,2\n*MAT_ELASTIC\n1,7850.0,2.0e11,0.3\n*NODE")
node = lambda i, j, k: 1 + i + (n + 1) * (j + (n + 1) * k)
for k in range(m + 1):
    for j in range(n + 1):
        for i in range(n + 1):
            print("%8d%16.8e%16.8e%16.8e" % (node(i, j, k), a * i, a * j, h * k))
print("*ELEMENT_SOLID")
for k in range(m):
    for j in range(n):
        for i in range(n):
            c = [node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k)]
            c += [q + (n + 1) ** 2 for q in c]
            print("%8d%8d" % (1 + i + n * (j + n * k), 1) + "".join("%8d" % q for q in c))
print("*SET_NODE_LIST_GENERATE\n1\n1,%d\n*BOUNDARY_SPC_SET\n1,0,1,1,1" % (n + 1) ** 2)
print("*DEFINE_CURVE\n77\n0.0,1.0\n1.0,1.0\n*LOAD_BODY_Z\n77,9.81\n*DAMPING_GLOBAL\n0,15860.0\n*END")
PY
"$cli" run "$work/column.k" -o "$work/column_out" 2>"$work/column.log" || { cat "$work/column.log"; fail "the column"; }
head -n 1 "$work/column_out/spcforc.csv" | grep -qx 'time \[time\],fx \[force\],fy \[force\],fz \[force\]' ||
  fail "spcforc header: $(head -n 1 "$work/column_out/spcforc.csv")"
awk -F, 'END { w = 7850 * 0.01 * 9.81; exit !(NR == 52 && $1 == 0.003 && ($4 - w) ^ 2 < (1e-6 * w) ^ 2 &&
  $2 ^ 2 < (1e-6 * w) ^ 2 && $3 ^ 2 < (1e-6 * w) ^ 2) }' "$work/column_out/spcforc.csv" ||
  fail "the column's base does not carry its weight, 770.085 N: $(tail -n 2 "$work/column_out/spcforc.csv")"
# Element histories (*DATABASE_HISTORY_SOLID, *DATABASE_ELOUT): in the column at rest each layer
# carries the weight above it, sigma_zz(z) = -rho g (L - z) (statics); the element mean of a linear
# field is its value at the centroid: element 21 (z = 0.55 m) -34 653.825 Pa and 37 (z = 0.95 m)
# -3 850.425 Pa, to 1e-5. Named 21, 37, 21: each once, in the card's order.
sed 's/^\*END$/*DATABASE_HISTORY_SOLID\n21,37,21\n*DATABASE_ELOUT\n3e-4\n*END/' "$work/column.k" >"$work/column_elout.k"
"$cli" run "$work/column_elout.k" -o "$work/column_elout" 2>"$work/column_elout.log" ||
  { cat "$work/column_elout.log"; fail "the column with element histories"; }
head -n 1 "$work/column_elout/elout.csv" | grep -q '^time \[time\],element,sxx \[stress\],syy \[stress\],szz' ||
  fail "elout header: $(head -n 1 "$work/column_elout/elout.csv")"
awk -F, 'NR > 1 { rows++; if ($2 != (rows % 2 ? 21 : 37)) order = 1 }
  $1 == 0.003 { exact = -7850 * 9.81 * ($2 == 21 ? 0.45 : 0.05); if (($5 - exact) ^ 2 < (1e-5 * exact) ^ 2) good++ }
  END { exit !(rows == 22 && !order && good == 2) }' "$work/column_elout/elout.csv" ||
  fail "elout.csv is not the column's weight: $(tail -n 2 "$work/column_elout/elout.csv")"
# The same elements by a *SET_SOLID (37, 21) and *DATABASE_HISTORY_SOLID_SET: in the set's order,
# the same values.
sed 's/^\*DATABASE_HISTORY_SOLID$/*SET_SOLID\n5\n37,21\n*DATABASE_HISTORY_SOLID_SET/; s/^21,37,21$/5/' \
  "$work/column_elout.k" >"$work/column_elout_set.k"
"$cli" run "$work/column_elout_set.k" -o "$work/column_elout_set" 2>"$work/column_elout_set.log" ||
  { cat "$work/column_elout_set.log"; fail "the column with a solid set's histories"; }
diff <(awk -F, 'NR > 1 && $2 == 21' "$work/column_elout/elout.csv") \
  <(awk -F, 'NR > 1 && $2 == 21' "$work/column_elout_set/elout.csv") >/dev/null &&
  awk -F, 'NR > 1 { rows++; if ($2 != (rows % 2 ? 37 : 21)) order = 1 } END { exit !(rows == 22 && !order) }' \
    "$work/column_elout_set/elout.csv" || fail "the solid set's elout.csv: $(sed -n '2,3p' "$work/column_elout_set/elout.csv")"
sed 's/^21,37,21$/21,99/' "$work/column_elout.k" >"$work/elout_bad.k"
expect_input_error "$work/elout_bad.k" \
  'elout_bad\.k:[0-9]+: \*DATABASE_HISTORY_SOLID: solid element 99 does not exist' \
  "a history element that does not exist"
# An SPG part's elements are particles at their nodes: no element history.
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 4 --speed 100 --end-time 4e-6 |
  sed 's/^\*END$/*DATABASE_HISTORY_SOLID\n1\n*END/' >"$work/elout_spg.k"
expect_input_error "$work/elout_spg.k" \
  'elout_spg\.k:[0-9]+: \*DATABASE_HISTORY_SOLID: solid element 1 is not a finite' \
  "a history element of an SPG part"
# Prescribed-motion reactions (*DATABASE_BNDOUT): the column's base held by zero velocity in x, y
# and z (*BOUNDARY_PRESCRIBED_MOTION_SET VAD 0) instead of the SPC carries its weight once at rest,
# R_z = M g = 770.085 N to 1e-6, and does no work (its nodes do not move). Without gravity and
# damping, the base driven up at 10 m/s^2 (VAD 1): the motion's work is the only work done on the
# column, glstat's external work, to 1e-9.
python3 - "$work/column.k" "$work/held.k" "$work/lifted.k" <<'PY'
import sys
deck = open(sys.argv[1]).read()
spc = "*BOUNDARY_SPC_SET\n1,0,1,1,1\n"
assert spc in deck
held = "".join("1,%d,0,78\n" % d for d in (1, 2, 3))
open(sys.argv[2], "w").write(deck.replace(spc, "*BOUNDARY_PRESCRIBED_MOTION_SET\n" + held +
                                          "*DEFINE_CURVE\n78\n0.0,0.0\n1.0,0.0\n*DATABASE_BNDOUT\n6e-5\n"))
lifted = deck.replace(spc, "*BOUNDARY_PRESCRIBED_MOTION_SET\n1,3,1,79,10.0\n*DEFINE_CURVE\n79\n0.0,1.0\n1.0,1.0\n"
                      "*DATABASE_BNDOUT\n6e-5\n")
open(sys.argv[3], "w").write(lifted.replace("*LOAD_BODY_Z\n77,9.81\n", "").replace("*DAMPING_GLOBAL\n0,15860.0\n", ""))
PY
for deck in held lifted; do
  "$cli" run "$work/$deck.k" -o "$work/${deck}_out" 2>"$work/$deck.log" ||
    { cat "$work/$deck.log"; fail "the $deck column"; }
done
head -n 1 "$work/held_out/bndout.csv" | grep -qx 'time \[time\],fx \[force\],fy \[force\],fz \[force\],work \[energy\]' \
  ||
  fail "bndout header: $(head -n 1 "$work/held_out/bndout.csv")"
awk -F, 'END { w = 7850 * 0.01 * 9.81; exit !($1 == 0.003 && ($4 - w) ^ 2 < (1e-6 * w) ^ 2 && $5 == 0) }' \
  "$work/held_out/bndout.csv" ||
  fail "the held base does not carry the weight: $(tail -n 1 "$work/held_out/bndout.csv")"
lift_work=$(tail -n 1 "$work/lifted_out/bndout.csv" | cut -d, -f5)
head -n 1 "$work/lifted_out/glstat.csv" | cut -d, -f6 | grep -q '^external_work' || fail "glstat's 6th column"
awk -F, -v w="$lift_work" 'END { exit !(w > 0.03 && (w - $6) ^ 2 < (1e-9 * w) ^ 2) }' "$work/lifted_out/glstat.csv" ||
  fail "the lifting motion's work $lift_work is not glstat's external work: $(tail -n 1 "$work/lifted_out/glstat.csv")"
# Part energies (*DATABASE_MATSUM). The column of nu = 0 at rest under its weight (uniaxial
# strain, sigma_zz = E eps_zz) holds the strain energy of its finite elements: linear elements with
# lumped (here consistent) loads give the bar's exact nodal displacements, so each layer's strain is
# the mean of the exact rho g (L - z) / E, and U = (rho g)^2 A L^3 / (6 E) (1 - 1 / (4 m^2)) =
# 4.929316e-5 J for m = 10 layers (0.25 % below the continuum's), to 1e-4 (the damped transient
# has decayed by e^-24); no kinetic or hourglass energy (ELFORM 2).
sed -e 's/^1,7850.0,2.0e11,0.3$/1,7850.0,2.0e11,0.0/' -e 's/^\*END$/*DATABASE_MATSUM\n1.5e-3\n*END/' \
  "$work/column.k" >"$work/column_matsum.k"
grep -q '^1,7850.0,2.0e11,0.0$' "$work/column_matsum.k" || fail "the column's material line"
"$cli" run "$work/column_matsum.k" -o "$work/column_matsum" 2>"$work/column_matsum.log" ||
  { cat "$work/column_matsum.log"; fail "the column with part energies"; }
head -n 1 "$work/column_matsum/matsum.csv" | grep -qx 'time \[time\],part,internal_energy \[energy\],kinetic_energy \[energy\],hourglass_energy \[energy\],x_momentum \[mass\*length/time\],y_momentum \[mass\*length/time\],z_momentum \[mass\*length/time\],eroded_internal_energy \[energy\],eroded_kinetic_energy \[energy\],added_mass \[mass\]' ||
  fail "matsum header: $(head -n 1 "$work/column_matsum/matsum.csv")"
awk -F, 'END { u = (7850 * 9.81) ^ 2 * 0.01 / (6 * 2e11) * (1 - 1 / 400.0)
  exit !(NR == 4 && $1 == 0.003 && $2 == 1 && ($3 - u) ^ 2 < (1e-4 * u) ^ 2 && $4 < 1e-8 * u && $5 == 0) }' \
  "$work/column_matsum/matsum.csv" ||
  fail "the column at rest does not hold its strain energy 4.929316e-5 J: $(tail -n 1 "$work/column_matsum/matsum.csv")"
sed 's/^1\.5e-3$/-1.5e-3/' "$work/column_matsum.k" >"$work/matsum_bad.k"
expect_input_error "$work/matsum_bad.k" 'matsum_bad\.k:[0-9]+: \*DATABASE_MATSUM: field DT.*negative' "a negative MATSUM DT"
# Two elastic blocks (ELFORM 1) and a rigid one, 0.1 m cubes of steel (M = 7.85 kg) apart and in
# flight at VX = 2, VY = -3 and VZ = 5 m/s: each part carries 1/2 M V^2 (15.7, 35.325, 98.125 J) and
# M V (15.7, -23.55, 39.25 kg m/s) to round-off, no internal or hourglass energy (a translation
# strains nothing); the parts' kinetic energies sum to glstat's. A fourth block at VX = -4 m/s is
# deleted at 5e-5 s (*MAT_ADD_EROSION FAILTM): at the end it has no kinetic energy nor momentum, and
# its eroded kinetic energy is the 1/2 M V^2 = 62.8 J it took with it (glstat's eroded_kinetic_energy),
# its eroded internal energy 0. No part has added mass.
python3 - >"$work/flight.k" <<'PY'
print("*KEYWORD\n*CONTROL_TERMINATION\n1.0e-4\n*DATABASE_MATSUM\n5.0e-5\n*DATABASE_GLSTAT\n5.0e-5")
print("*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850.0,2.0e11,0.3\n*MAT_RIGID\n2,7850.0,2.0e11,0.3\n0.0,0.0,0.0")
print("*MAT_ELASTIC\n3,7850.0,2.0e11,0.3\n*MAT_ADD_EROSION\n3\n0.0,0.0,0.0,0.0,0.0,0.0,0.0,5.0e-5")
print("*PART\nmoving x\n1,1,1\n*PART\nmoving y\n2,1,1\n*PART\nrigid z\n3,1,2\n*PART\neroding\n4,1,3\n*NODE")
n, a = 2, 0.05
for p in range(4):
    for k in range(n + 1):
        for j in range(n + 1):
            for i in range(n + 1):
                print("%8d%16.8e%16.8e%16.8e" % (1 + 100 * p + i + 3 * (j + 3 * k), p + a * i, a * j, a * k))
print("*ELEMENT_SOLID")
for p in range(4):
    for k in range(n):
        for j in range(n):
            for i in range(n):
                c = [1 + 100 * p + q + 3 * (j + 3 * k) for q in (i, i + 1)]
                c = [c[0], c[1], c[1] + 3, c[0] + 3]
                c += [q + 9 for q in c]
                print("%8d%8d" % (1 + 10 * p + i + n * (j + n * k), p + 1) + "".join("%8d" % q for q in c))
print("*INITIAL_VELOCITY_GENERATION\n1,2,0.0,2.0,0.0,0.0\n0.0,0.0,0.0,0.0,0.0,0.0")
print("*INITIAL_VELOCITY_GENERATION\n2,2,0.0,0.0,-3.0,0.0\n0.0,0.0,0.0,0.0,0.0,0.0")
print("*INITIAL_VELOCITY_GENERATION\n3,2,0.0,0.0,0.0,5.0\n0.0,0.0,0.0,0.0,0.0,0.0")
print("*INITIAL_VELOCITY_GENERATION\n4,2,0.0,-4.0,0.0,0.0\n0.0,0.0,0.0,0.0,0.0,0.0\n*END")
PY
"$cli" run "$work/flight.k" -o "$work/flight_out" 2>"$work/flight.log" ||
  { cat "$work/flight.log"; fail "the blocks in flight"; }
glstat_kinetic=$(tail -n 1 "$work/flight_out/glstat.csv" | cut -d, -f3)
column() { head -n 1 "$1" | tr ',' '\n' | grep -n "^$2 " | cut -d: -f1; }
glstat_eroded=$(tail -n 1 "$work/flight_out/glstat.csv" | cut -d, -f"$(column "$work/flight_out/glstat.csv" eroded_kinetic_energy)")
awk -F, -v glstat="$glstat_kinetic" -v eroded="$glstat_eroded" '
  function off(x, exact) { return (x - exact) ^ 2 > (1e-12 * 100) ^ 2 }
  $1 == 1e-4 { rows++; k = $2
    if (off($4, k == 1 ? 15.7 : k == 2 ? 35.325 : k == 3 ? 98.125 : 0) || off($6, k == 1 ? 15.7 : 0) ||
        off($7, k == 2 ? -23.55 : 0) || off($8, k == 3 ? 39.25 : 0) || off($3, 0) || off($5, 0) ||
        off($9, 0) || off($10, k == 4 ? 62.8 : 0) || $11 != 0) bad = 1
    kinetic += $4; eroded_sum += $10 }
  END { exit !(rows == 4 && !bad && !off(kinetic, glstat) && !off(eroded_sum, eroded)) }' "$work/flight_out/matsum.csv" ||
  fail "the parts in flight (glstat's kinetic energy $glstat_kinetic, eroded $glstat_eroded): $(tail -n 4 "$work/flight_out/matsum.csv")"

# The SPH fluid computes no force on its wall particles: their reactions are refused, not zeros.
sed 's/^\*END$/*DATABASE_SPCFORC\n0.001\n*END/' "$source_dir/examples/dam_break/dam_break_2d.k" >"$work/spc_fluid.k"
expect_input_error "$work/spc_fluid.k" \
  'spc_fluid\.k:[0-9]+: \*DATABASE_SPCFORC: the SPH fluid computes no force on the particles an SPC holds' \
  "SPCFORC with an SPH fluid"

# A rigid wall through the particle layer at x = 0.5125, facing +x: the half in front of it moves
# onto it (v = V cos(pi x / L) < 0 there), so rwforc.csv has rows with a positive normal force.
sed 's/^\*END$/*RIGIDWALL_PLANAR\n\n    0.5125       0.0       0.0       1.5       0.0       0.0\n*DATABASE_RWFORC\n   1.0e-05\n*END/' \
  "$work/bar.k" >"$work/wall.k"
"$cli" run "$work/wall.k" -o "$work/wall_out" 2>"$work/wall.log" || { cat "$work/wall.log"; fail "run with a wall"; }
head -n 1 "$work/wall_out/rwforc.csv" | grep -qx 'time \[time\],wall,normal_force \[force\],fx \[force\],fy \[force\],fz \[force\]' ||
  fail "rwforc header: $(head -n 1 "$work/wall_out/rwforc.csv")"
awk -F, 'NR > 1 && $2 == 1 && $3 > 0 && $4 < 0 { found = 1 } END { exit !found }' "$work/wall_out/rwforc.csv" ||
  fail "no row of wall 1 with a positive normal force"

# A bad number: one line with file, line, keyword and field; exit 2; no output folder.
sed '0,/^\*NODE/{/^\*NODE/{n;s/^\(.\{8\}\).\{16\}/\1     1.2.3e-02 /}}' "$work/bar.k" >"$work/bad.k"
set +e
"$cli" run "$work/bad.k" -o "$work/bad_out" 2>"$work/bad.log"
code=$?
set -e
[ "$code" -eq 2 ] || fail "bad number: exit $code"
grep -Eq "bad\.k:[0-9]+: \*NODE: field X: .*1\.2\.3e-02" "$work/bad.log" || { cat "$work/bad.log"; fail "bad number message"; }
[ ! -e "$work/bad_out" ] || fail "output written for a bad deck"

# An unsupported physics keyword stops the check at its line (exit 2), unless skipped by name,
# and then the warning says the physics is incomplete.
sed 's/^\*END$/*CONTACT_TIED_SURFACE_TO_SURFACE\n         1         0         2\n       0.2\n\n*END/' "$work/bar.k" >"$work/contact.k"
set +e
"$cli" check "$work/contact.k" >/dev/null 2>"$work/contact.log"
code=$?
set -e
[ "$code" -eq 2 ] || fail "a deck with a contact checked with exit $code"
grep -Eq 'contact\.k:[0-9]+: \*CONTACT_TIED_SURFACE_TO_SURFACE: not supported by Spall, and it defines physics' "$work/contact.log" ||
  { cat "$work/contact.log"; fail "contact refusal"; }
"$cli" check "$work/contact.k" --skip CONTACT >/dev/null 2>"$work/contact.log" || fail "check --skip CONTACT"
grep -q 'on request (--skip): the physics of this run is incomplete' "$work/contact.log" || fail "--skip warning"
# Thermal materials in a structural deck: one warning that they are not used; a thermal solution
# (*CONTROL_SOLUTION SOLN 1) is refused by name with exit 2.
sed 's/^\*END$/*MAT_THERMAL_ISOTROPIC\n         1    7850.0\n     460.0      45.0\n*MAT_THERMAL_ISOTROPIC\n         2    7850.0\n     460.0      45.0\n*CONTROL_SOLUTION\n         0\n*END/' \
  "$work/bar.k" >"$work/thermal.k"
"$cli" check "$work/thermal.k" >/dev/null 2>"$work/thermal.log" || { cat "$work/thermal.log"; fail "check thermal.k"; }
[ "$(grep -c 'not used: no thermal solution is requested' "$work/thermal.log")" -eq 1 ] ||
  { cat "$work/thermal.log"; fail "thermal materials: not one warning"; }
sed 's/^         0$/         1/' "$work/thermal.k" >"$work/thermal_soln.k"
set +e
"$cli" check "$work/thermal_soln.k" >/dev/null 2>"$work/thermal_soln.log"
code=$?
set -e
[ "$code" -eq 2 ] || fail "a thermal solution checked with exit $code"
grep -Eq 'thermal_soln\.k:[0-9]+: \*CONTROL_SOLUTION: field SOLN: 1 \(thermal only\)' "$work/thermal_soln.log" ||
  { cat "$work/thermal_soln.log"; fail "thermal solution refusal"; }
# A deck with nothing Spall can run: exit 2.
printf '*KEYWORD\n*CONTROL_TERMINATION\n       1.0\n*END\n' >"$work/empty.k"
set +e
"$cli" check "$work/empty.k" >/dev/null 2>"$work/empty.log"
code=$?
set -e
[ "$code" -eq 2 ] && grep -q 'nothing to simulate' "$work/empty.log" || fail "an empty deck: exit $code, $(cat "$work/empty.log")"

# An unsupported keyword: a warning with its name and line; the run goes on.
sed 's/^\*END$/*CONTROL_ENERGY\n         2\n*END/' "$work/bar.k" >"$work/unsupported.k"
"$cli" check "$work/unsupported.k" 2>"$work/unsupported.log" >/dev/null || fail "check with unsupported keyword"
grep -Eq "warning: .*unsupported\.k:[0-9]+: \*CONTROL_ENERGY: not supported" "$work/unsupported.log" ||
  { cat "$work/unsupported.log"; fail "unsupported warning"; }

# A step far above the stable one: exit 3, which node and step, and the last state on disk.
sed 's/^       0.0       0.9$/       0.0       4.0/' "$work/bar.k" >"$work/unstable.k"
set +e
"$cli" run "$work/unstable.k" -o "$work/unstable_out" 2>"$work/unstable.log"
code=$?
set -e
[ "$code" -eq 3 ] || { cat "$work/unstable.log"; fail "unstable run: exit $code"; }
grep -Eq "numerical instability at step [0-9]+, time .*: (SPH solid: )?node [0-9]+" "$work/unstable.log" || fail "instability message"
grep -q '"status": "unstable"' "$work/unstable_out/run.json" || fail "unstable run.json"
"${read_vtu[@]}" "$(ls "$work/unstable_out"/d3plot_*.vtu | tail -n 1)" --field velocity >/dev/null || fail "last state"
# A collapse that empties a particle's neighbourhood before any particle runs away (the treated
# ductile block at 1.7 x the stable factor): exit 3 naming the particle, not an abort.
python3 "$source_dir/tools/make_compression_deck.py" --scene ductile --across 8 --treat 1 |
  sed 's/^       0.0       0.9$/       0.0       1.7/' >"$work/collapse.k"
set +e
"$cli" run "$work/collapse.k" -o "$work/collapse_out" --threads 1 2>"$work/collapse.log"
code=$?
set -e
[ "$code" -eq 3 ] || { cat "$work/collapse.log"; fail "collapsing run: exit $code"; }
grep -Eq "numerical instability at step [0-9]+, time .*: SPH solid: node [0-9]+ has density" "$work/collapse.log" || { cat "$work/collapse.log"; fail "collapse message"; }

# An SPG deck (examples/spg_tension, coarse and short): the SPG fields come out; an SPG option
# that is not implemented is exit 2 naming the field at its card's line.
python3 "$source_dir/tools/make_spg_tension_deck.py" --elements 10 --end-time 4e-6 >"$work/spg.k"
"$cli" run "$work/spg.k" -o "$work/spg_out" 2>"$work/spg.log" || { cat "$work/spg.log"; fail "SPG run"; }
"${read_vtu[@]}" "$(ls "$work/spg_out"/d3plot_*.vtu | tail -n 1)" --field effective_plastic_strain \
  --field broken_bonds --field bond_damage --field bond_count >"$work/spg_fields" || fail "SPG fields"
grep -qx 'points 99' "$work/spg_fields" || fail "SPG point count: $(grep points "$work/spg_fields")"
sed 's/^         1       0.6       1.2         1$/         5       0.6       1.2         1/' "$work/spg.k" >"$work/spg_idam.k"
set +e
"$cli" check "$work/spg_idam.k" 2>"$work/spg_idam.log"
code=$?
set -e
[ "$code" -eq 2 ] || { cat "$work/spg_idam.log"; fail "SPG IDAM 5: exit $code"; }
grep -Eq "spg_idam\.k:[0-9]+: \*SECTION_SOLID_SPG: IDAM 5: " "$work/spg_idam.log" || { cat "$work/spg_idam.log"; fail "SPG IDAM message"; }

# Started by an MPI launcher as one rank, a run is the plain run (several ranks: test_mpi_*.sh). With
# Open MPI's mpirun where it is installed (allowed to run as root, as in CI), else with what mpirun
# tells each process.
if command -v mpirun >/dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
  # Under the sanitizers: Open MPI's unloaded plugins leave allocations LeakSanitizer cannot name.
  launch() { ASAN_OPTIONS=detect_leaks=0 mpirun -np 1 "$@"; }
else
  launch() { OMPI_COMM_WORLD_SIZE=1 "$@"; }
fi
python3 "$source_dir/tools/make_punch_deck.py" --end-time 2e-6 >"$work/punch.k"
launch "$cli" run "$work/punch.k" -o "$work/mpi1_out" >/dev/null 2>&1 || fail "one MPI rank"

# Not a keyword file: a folder or a binary file is one line and exit 2, not a page of warnings.
set +e
"$cli" check "$work" >/dev/null 2>"$work/folder.err"; folder_code=$?
"$cli" check "$cli" >/dev/null 2>"$work/binary.err"; binary_code=$?
set -e
[ "$folder_code" -eq 2 ] && grep -q 'is a directory, not a keyword file' "$work/folder.err" &&
  [ "$(wc -l <"$work/folder.err")" -eq 1 ] || { cat "$work/folder.err"; fail "a folder as the deck"; }
[ "$binary_code" -eq 2 ] && grep -q 'not a keyword file (binary data' "$work/binary.err" &&
  [ "$(wc -l <"$work/binary.err")" -eq 1 ] || { cat "$work/binary.err"; fail "a binary file as the deck"; }

# A bad option value: one line naming the option and what it must be, exit 2.
set +e
"$cli" run "$work/punch.k" -o "$work/bad_option" --balance-threshold -1 >/dev/null 2>"$work/option.err"; option_code=$?
set -e
[ "$option_code" -eq 2 ] && grep -q '^--balance-threshold: must be zero or more, got -1$' "$work/option.err" ||
  { cat "$work/option.err"; fail "a negative --balance-threshold"; }

# A rigid tool turning at 3000 rpm (*MAT_RIGID, *BOUNDARY_PRESCRIBED_MOTION_RIGID DOF 7, LCTM
# holding the step): rbdout.csv has the body's angular velocity, 314.16 rad/s about z.
{
  echo "*KEYWORD"
  echo "*CONTROL_TERMINATION"; echo "   1.0e-03"
  echo "*CONTROL_TIMESTEP"; echo "       0.0       0.9       0.0       0.0       0.0        99"
  echo "*DATABASE_GLSTAT"; echo "   1.0e-04"
  echo "*PART"; echo "tool"; echo "         1         1         1"
  echo "*SECTION_SOLID"; echo "         1         1"
  echo "*MAT_RIGID"; echo "         1    7850.0   2.0e+11       0.3"; echo "       1.0         7         4"
  echo "*DEFINE_CURVE"; echo "        99"; echo "                 0.0              1.0e-5"; echo "                 1.0              1.0e-5"
  echo "*DEFINE_CURVE"; echo "         1"; echo "                 0.0                 1.0"; echo "                 1.0                 1.0"
  echo "*BOUNDARY_PRESCRIBED_MOTION_RIGID"; echo "         1         7         0         1    314.16"
  echo "*NODE"
  n=1
  for z in 0.0 0.01; do for y in -0.005 0.005; do for x in -0.005 0.005; do
    printf '%8d%16s%16s%16s\n' $n $x $y $z; n=$((n + 1))
  done; done; done
  echo "*ELEMENT_SOLID"; printf '%8d%8d%8d%8d%8d%8d%8d%8d%8d%8d\n' 1 1 1 2 4 3 5 6 8 7
  echo "*END"
} >"$work/tool.k"
"$cli" run "$work/tool.k" -o "$work/tool" 2>"$work/tool.log" || { cat "$work/tool.log"; fail "rigid tool run"; }
head -n 1 "$work/tool/rbdout.csv" | grep -q '^time \[time\],part,x \[length\]' || fail "rbdout header: $(head -n 1 "$work/tool/rbdout.csv")"
tail -n 1 "$work/tool/rbdout.csv" | awk -F, '{ exit !($2 == 1 && $11 > 314.159 && $11 < 314.161 && $9 == 0 && $10 == 0) }' ||
  fail "rbdout last row: $(tail -n 1 "$work/tool/rbdout.csv")"

# Every public deck: `spall check` answers 0 or 2 with a clear line, never a crash (the decks live
# in shared/ beside the checkout, which a user's clone does not have).
if [ -d "$shared_dir/decks/public" ]; then
  while IFS= read -r deck; do
    set +e
    "$cli" check "$deck" >"$work/check.out" 2>"$work/check.err"
    code=$?
    set -e
    case $code in
      0) ;;
      2) grep -Eq '^error: ' "$work/check.err" || fail "$deck: exit 2 without an error line" ;;
      *) cat "$work/check.err"; fail "$deck: exit $code" ;;
    esac
    echo "check $(basename "$deck"): exit $code: $(grep '^error' "$work/check.err" | head -n 1)"
  done < <(find "$shared_dir/decks/public" -name '*.k' | sort)
else
  echo "$shared_dir/decks/public is absent (a clone without ../shared): public decks skipped"
fi
echo "CLI tests passed"
