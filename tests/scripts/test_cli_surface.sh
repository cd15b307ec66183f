#!/usr/bin/env bash
# `spall surface` on a real run's output, as a user meets it: a steel bar (1 x 0.1 x 0.1 m, 8
# particles across, tools/make_bar_deck.py) run for a quarter period, then its surface. VTK's own
# readers (Debian's python3-vtk9) must open the .vtp and the .ply with the same triangles (> 0),
# the .vtp must carry the particles' fields, and its enclosed volume must be the bar's 0.01 m^3
# within 5 % (the surface c = 1/2 sits where the material ends; the edges, rounded over about 1.4
# spacings as in the cube of tests/verification/test_surface_reconstruction.cpp, take about 3 %;
# the strain of a quarter period is 2e-4).
# Bad input is one error line and exit 2.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
cli=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

python3 "$source_dir/tools/make_bar_deck.py" --spacing 0.0125 --periods 0.25 >"$work/bar.k"
"$cli" run "$work/bar.k" -o "$work/out" 2>"$work/run.log" || { cat "$work/run.log"; fail "run"; }
last=$(basename "$(ls "$work/out"/d3plot_*.vtu | tail -n 1)" .vtu)
last=${last#d3plot_}

"$cli" surface "$work/out" --threads 2 2>"$work/surface.log" || { cat "$work/surface.log"; fail "surface"; }
cat "$work/surface.log"
[ -s "$work/out/surface_$last.vtp" ] || fail "no surface_$last.vtp beside d3plot_$last.vtu"
[ -s "$work/out/surface_$last.ply" ] || fail "no surface_$last.ply"
grep -q "closed (Euler characteristic 2)" "$work/surface.log" || fail "surface not reported closed"

# VTK reads both files; prints triangles, the fields' presence, and the enclosed volume.
/usr/bin/python3 - "$work/out/surface_$last.vtp" "$work/out/surface_$last.ply" >"$work/vtk.txt" <<'PY' || fail "VTK could not read the surface"
import sys
import vtk

def read(reader, path):
    errors = []
    reader.AddObserver("ErrorEvent", lambda caller, event: errors.append(event))
    reader.SetFileName(path)
    reader.Update()
    if errors:
        sys.exit(f"VTK cannot read {path}")
    return reader.GetOutput()

vtp = read(vtk.vtkXMLPolyDataReader(), sys.argv[1])
ply = read(vtk.vtkPLYReader(), sys.argv[2])
triangles = sum(vtp.GetCell(i).GetNumberOfPoints() == 3 for i in range(vtp.GetNumberOfCells()))
print("vtp_triangles", triangles, "of", vtp.GetNumberOfCells())
print("ply_triangles", ply.GetNumberOfPolys())
for name in ("pressure", "velocity", "part_id"):
    array = vtp.GetPointData().GetArray(name)
    print(name, "missing" if array is None else array.GetNumberOfTuples() == vtp.GetNumberOfPoints())
mass = vtk.vtkMassProperties()
mass.SetInputData(vtp)
mass.Update()
print("volume", mass.GetVolume())
PY
cat "$work/vtk.txt"
awk '/^vtp_triangles/ { exit !($2 > 0 && $2 == $4) }' "$work/vtk.txt" || fail "no triangles in the .vtp"
vtp_triangles=$(awk '/^vtp_triangles/ { print $2 }' "$work/vtk.txt")
grep -qx "ply_triangles $vtp_triangles" "$work/vtk.txt" || fail ".ply and .vtp differ in triangles"
for name in pressure velocity part_id; do grep -qx "$name True" "$work/vtk.txt" || fail "field $name on the surface"; done
awk '/^volume/ { exit !($2 > 0.0095 && $2 < 0.0105) }' "$work/vtk.txt" || fail "enclosed volume is not the bar's 0.01 m^3"

# The same files on one thread as on two (fields included).
cp "$work/out/surface_$last.vtp" "$work/many_threads.vtp"
"$cli" surface "$work/out" --threads 1 2>/dev/null || fail "surface --threads 1"
cmp -s "$work/out/surface_$last.vtp" "$work/many_threads.vtp" || fail "the .vtp depends on the thread count"

# --time picks the snapshot at or last before it; --field limits the fields carried; --part keeps
# the particles of the parts named.
"$cli" surface --field pressure "$work/out" --time 0 --field part_id --part 1 2>/dev/null || fail "surface --time 0"
[ -s "$work/out/surface_00000.vtp" ] || fail "no surface_00000.vtp for --time 0"
grep -q 'Name="pressure"' "$work/out/surface_00000.vtp" || fail "--field pressure not carried"
grep -q 'Name="part_id"' "$work/out/surface_00000.vtp" || fail "--field part_id not carried"
! grep -q 'Name="velocity"' "$work/out/surface_00000.vtp" || fail "--field carried more than asked"

# Bad input: one error line naming what is wrong, exit 2.
expect_bad() {
  local pattern=$1
  shift
  set +e
  "$cli" surface "$@" 2>"$work/bad.log"
  local code=$?
  set -e
  [ "$code" -eq 2 ] || { cat "$work/bad.log"; fail "surface $*: exit $code, expected 2"; }
  grep -Eq -- "$pattern" "$work/bad.log" || { cat "$work/bad.log"; fail "surface $*: message"; }
}
expect_bad "d3plot\.pvd: no such file" "$work"
expect_bad "no snapshot at or before time -1" "$work/out" --time -1
expect_bad "--field nothing: .* has no such point field" "$work/out" --field nothing
expect_bad "iso" "$work/out" --iso -0.5
expect_bad "no SPH particle .*in part 2" "$work/out" --part 2
echo "surface CLI tests passed"
