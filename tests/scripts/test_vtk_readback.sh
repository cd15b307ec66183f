#!/usr/bin/env bash
# VTK's own reader (Debian's python3-vtk9, as ParaView would) reads back a VTU that write_vtu wrote
# and must see exactly the point count, the vector field, the Int64 field and the tensor's component
# names that tests/unit/test_output.cpp (VtuSample) put in it; the .pvd beside it must parse as XML
# and list it. Also checks that tools/read_vtu.py fails on a missing field: other tests rely on it.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR. The unit test binaries sit beside the CLI.
set -euo pipefail
cli=$1
source_dir=$2
test_output="$(dirname "$cli")/test_output"
read_vtu=("/usr/bin/python3" "$source_dir/tools/read_vtu.py")

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

SPALL_VTU_SAMPLE_DIR=$work "$test_output" --gtest_filter='VtuSample.*' >"$work/gtest.log" ||
  { cat "$work/gtest.log"; exit 1; }

"${read_vtu[@]}" "$work/sample.vtu" --field velocity --field category --values >"$work/summary"
"${read_vtu[@]}" "$work/sample.vtu" --field stress | grep component_names >>"$work/summary"

cat >"$work/expected" <<'END'
points 4
cells 4
velocity components 3 type Float64
velocity min -3.25 -2.0 0.0
velocity max 7.0 8.0 9.0
velocity magnitude_min 0.0
velocity magnitude_max 13.92838827718412
velocity value 0 1.5 -2.0 0.1
velocity value 1 0.0 0.0 0.0
velocity value 2 -3.25 4.0 0.001
velocity value 3 7.0 8.0 9.0
category components 1 type Int64
category min -1
category max 9007199254740993
category value 0 0
category value 1 2
category value 2 -1
category value 3 9007199254740993
stress component_names xx yy zz xy yz zx
END
diff -u "$work/expected" "$work/summary"

# The series is XML that a standard parser accepts, and it points at the sample.
/usr/bin/python3 - "$work/sample.pvd" <<'END'
import sys
import xml.etree.ElementTree as ElementTree
root = ElementTree.parse(sys.argv[1]).getroot()
datasets = [(d.get("timestep"), d.get("file")) for d in root.iter("DataSet")]
assert root.get("type") == "Collection" and datasets == [("0.10000000000000001", "sample.vtu")], datasets
END

# Cells: 8 vertex cells and one hexahedron of volume 1 (VTK computes it from our node order); the
# cell fields are NaN / -1 on the vertex cells and the block's values on the hexahedron.
/usr/bin/python3 - "$work/hexahedron.vtu" <<'END'
import math, sys
import vtk
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(sys.argv[1])
reader.Update()
grid = reader.GetOutput()
assert grid.GetNumberOfPoints() == 8 and grid.GetNumberOfCells() == 9, (grid.GetNumberOfPoints(), grid.GetNumberOfCells())
assert [grid.GetCellType(i) for i in range(9)] == [vtk.VTK_VERTEX] * 8 + [vtk.VTK_HEXAHEDRON]
quality = vtk.vtkMeshQuality()
quality.SetInputData(grid)
quality.SetHexQualityMeasureToVolume()
quality.Update()
volume = quality.GetOutput().GetCellData().GetArray("Quality").GetValue(8)
assert abs(volume - 1.0) < 1e-12, volume
ids = grid.GetCellData().GetArray("element_id")
strain = grid.GetCellData().GetArray("plastic_strain")
assert [ids.GetValue(i) for i in range(9)] == [-1] * 8 + [42]
assert all(math.isnan(strain.GetValue(i)) for i in range(8)) and strain.GetValue(8) == 0.25
END

if "${read_vtu[@]}" "$work/sample.vtu" --field no_such_field >/dev/null 2>&1; then
  echo "read_vtu.py accepted a missing field" >&2
  exit 1
fi
echo "VTK read the sample back exactly"
