#!/usr/bin/env bash
# The examples as their READMEs describe them: each committed deck is what its generator writes
# with the options the README names, `spall check` accepts it, and the post-processing tools
# (taylor_bar_shape.py, compression_force.py, render_particles.py) work on the output of real,
# coarse runs of the same scenes. Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
py=/usr/bin/python3  # Debian's interpreter: python3-vtk9, numpy, matplotlib
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# The coarse runs are a few hundred particles: one thread, and no spinning waits on shared cores.
export OMP_WAIT_POLICY=passive
examples=$source_dir/examples
tools=$source_dir/tools

# Generators reproduce the committed decks.
python3 "$tools/make_taylor_bar_deck.py" --across 12 | cmp -s - "$examples/taylor_bar/taylor_bar.k" ||
  fail "examples/taylor_bar/taylor_bar.k is not what make_taylor_bar_deck.py --across 12 writes"
for scene in ductile iron; do
  python3 "$tools/make_compression_deck.py" --scene $scene | cmp -s - "$examples/compression_$scene/compression_$scene.k" ||
    fail "examples/compression_$scene/compression_$scene.k is not what make_compression_deck.py --scene $scene writes"
done

python3 "$tools/make_spg_tension_deck.py" --fem-ends 0.3 | cmp -s - "$examples/fem_spg_bar/bar.k" ||
  fail "examples/fem_spg_bar/bar.k is not what make_spg_tension_deck.py --fem-ends 0.3 writes"

python3 "$tools/make_punch_deck.py" | cmp -s - "$examples/punch_rotation/punch.k" ||
  fail "examples/punch_rotation/punch.k is not what make_punch_deck.py writes"

python3 "$tools/make_brittle_deck.py" | cmp -s - "$examples/brittle_spall/brittle_spall.k" ||
  fail "examples/brittle_spall/brittle_spall.k is not what make_brittle_deck.py writes"

python3 "$tools/make_drilling_deck.py" | cmp -s - "$examples/friction_drilling/drilling.k" ||
  fail "examples/friction_drilling/drilling.k is not what make_drilling_deck.py writes"

for deck in "$examples"/*/*.k; do
  "$cli" check "$deck" >"$work/check.log" 2>&1 || { cat "$work/check.log"; fail "spall check $deck"; }
done

# A coarse Taylor bar, 20 us after impact: shorter and with a wider foot than at t = 0.
python3 "$tools/make_taylor_bar_deck.py" --across 4 --end-time 20e-6 --outputs 2 >"$work/taylor.k"
"$cli" run "$work/taylor.k" -o "$work/taylor" --threads 1 >/dev/null 2>&1 || fail "run of the coarse Taylor bar"
"$py" "$tools/taylor_bar_shape.py" "$work/taylor" >"$work/shape" || fail "taylor_bar_shape.py"
awk '/^L\/L0/ { l = $2 } /^R\/R0/ { r = $2 } END { exit !(l > 0.5 && l < 1 && r > 1) }' "$work/shape" ||
  fail "shape after impact: $(cat "$work/shape")"

# Pictures: a planar cut of two files on one colour scale, and the colour-field surface.
"$py" "$tools/render_particles.py" "$work/taylor/d3plot_00000.vtu" "$work/taylor/d3plot_00002.vtu" \
  --field effective_plastic_strain --view xz --cut -o "$work/cut.png" >/dev/null || fail "render --cut"
"$py" "$tools/render_particles.py" "$work/taylor/d3plot_00002.vtu" --field pressure --view iso --surface \
  -o "$work/surface.png" >/dev/null || fail "render --surface"
for png in cut surface; do
  head -c 8 "$work/$png.png" | od -An -tx1 | tr -d ' \n' | grep -qx '89504e470d0a1a0a' || fail "$png.png is not a PNG"
done
"$py" "$tools/render_particles.py" "$work/taylor/d3plot_00000.vtu" --field no_such_field -o "$work/x.png" \
  2>"$work/err" && fail "a missing field was accepted"
grep -q "no point field 'no_such_field'" "$work/err" || fail "missing-field message: $(cat "$work/err")"

# A coarse bar with finite-element ends on an SPG core: one series with the hexahedra as cells, and
# the picture draws the elements' nodes (NaN for the particle field) in grey beside the particles.
python3 "$tools/make_spg_tension_deck.py" --fem-ends 0.3 --elements 10 --end-time 10e-6 >"$work/fem_spg.k"
"$cli" run "$work/fem_spg.k" -o "$work/fem_spg" --threads 1 >/dev/null 2>&1 || fail "run of the coarse FEM/SPG bar"
"$py" - "$work/fem_spg/d3plot_00001.vtu" <<'PY' || fail "the FEM/SPG bar's output"
import sys, vtk
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update(); g = r.GetOutput()
hexahedra = sum(g.GetCellType(c) == vtk.VTK_HEXAHEDRON for c in range(g.GetNumberOfCells()))
assert hexahedra == 2 * 3 * 2 * 2, hexahedra  # 3 of 10 elements along at each end, 2 x 2 across
assert g.GetCellData().GetArray("von_mises") is not None and g.GetPointData().GetArray("bond_count") is not None
PY
"$py" "$tools/render_particles.py" "$work/fem_spg/d3plot_00001.vtu" --field effective_plastic_strain --view xz \
  -o "$work/fem_spg.png" >/dev/null || fail "render of the FEM/SPG bar"

# A coarse frictionless compression to 10 %: both walls report forces; the table has ten rows.
python3 "$tools/make_compression_deck.py" --scene ductile --across 5 --strain 0.1 --outputs 2 >"$work/squeeze.k"
"$cli" run "$work/squeeze.k" -o "$work/squeeze" --threads 1 >/dev/null 2>&1 || fail "run of the coarse compression"
"$py" "$tools/compression_force.py" "$work/squeeze" --flow 0.1 0 1 >"$work/force" || fail "compression_force.py"
[ "$(awk '$2 ~ /^0\.[0-9]+$/ && NF == 7' "$work/force" | wc -l)" -eq 10 ] || fail "force table: $(cat "$work/force")"
# A coarse brittle bar (4 x 4 x 40 particles; the physics is tests/verification/
# test_sph_brittle_spall.cpp): count_fragments.py finds the scabs and their crack faces, and the
# categories draw in seed 000 Figure 4's colours.
python3 "$tools/make_brittle_deck.py" --across 4 --end-time 0.15 --outputs 2 >"$work/brittle.k"
"$cli" run "$work/brittle.k" -o "$work/brittle" --threads 1 >/dev/null 2>&1 || fail "run of the coarse brittle bar"
"$py" "$tools/count_fragments.py" "$work/brittle/d3plot_00002.vtu" >"$work/fragments" || fail "count_fragments.py"
awk '/^fragments / { n = $2 } /^crack_face_particles / { faces = $2; surface = $4 }
     END { exit !(n >= 2 && faces > 0 && surface > 0) }' "$work/fragments" ||
  fail "fragments of the coarse brittle bar: $(cat "$work/fragments")"
"$py" "$tools/render_particles.py" "$work/brittle/d3plot_00002.vtu" --field category --categories \
  --view xz --cut -o "$work/categories.png" >/dev/null || fail "render --categories"
head -c 8 "$work/categories.png" | od -An -tx1 | tr -d ' \n' | grep -qx '89504e470d0a1a0a' ||
  fail "categories.png is not a PNG"

# A coarse turning punch: the contact's forces on the punch come out in rcforc.csv, and the plot
# tool reads them (the block pushes the punch up; friction turns it back).
python3 "$tools/make_punch_deck.py" --spacing 1e-3 --end-time 2e-5 --outputs 2 >"$work/punch.k"
"$cli" run "$work/punch.k" -o "$work/punch" --threads 1 >/dev/null 2>&1 || fail "run of the coarse punch"
"$py" "$tools/plot_contact_forces.py" "$work/punch" -o "$work/torque.png" >"$work/forces" || fail "plot_contact_forces.py"
awk '/^last quarter/ { f = $4; m = $7 } END { exit !(f > 0 && m < 0) }' "$work/forces" ||
  fail "punch forces: $(cat "$work/forces")"
head -c 8 "$work/torque.png" | od -An -tx1 | tr -d ' \n' | grep -qx '89504e470d0a1a0a' || fail "torque.png is not a PNG"
# *DATABASE_RCFORC_MOMENT: side 2's moments about the middle of the punch's face (on the axis,
# plunged along -z), side 1's about the origin.
awk -F, 'NR > 1 && $3 == 2 && $1 > 0 { if ($10 * $10 + $11 * $11 > 1e-20 || !($12 < 0)) bad = 1; seen = 1 }
         NR > 1 && $3 == 1 && ($10 != 0 || $11 != 0 || $12 != 0) { bad = 1 }
         END { exit !(seen && !bad) }' "$work/punch/rcforc.csv" ||
  fail "rcforc.csv moment points: $(tail -2 "$work/punch/rcforc.csv")"
echo "examples: OK"
