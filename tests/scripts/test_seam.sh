#!/usr/bin/env bash
# The seam (docs/ARCHITECTURE.md): only src/spall/core names OpenMP or x86 intrinsics. Physics
# loops go through core/parallel.hpp and SIMD through core/simd.hpp, so that a GPU backend is a new
# body for those, not a second copy of the physics.
# Arguments, as CTest passes them: CLI SOURCE_DIR SHARED_DIR.
set -euo pipefail
source_dir=$2
cd "$source_dir"
status=0
openmp=$(grep -rlE '#pragma omp|#include <omp.h>|\bomp_[a-z_]+\(' src apps --include='*.cpp' --include='*.hpp' |
  grep -v '^src/spall/core/' || true)
if [ -n "$openmp" ]; then
  echo "OpenMP named outside src/spall/core:" >&2
  echo "$openmp" >&2
  status=1
fi
intrinsics=$(grep -rlE '\b_mm(256|512)?_[a-z0-9_]+\(|\b__m(128|256|512)[di]?\b|<immintrin.h>' src apps \
  --include='*.cpp' --include='*.hpp' | grep -v '^src/spall/core/' || true)
if [ -n "$intrinsics" ]; then
  echo "x86 intrinsics outside src/spall/core/simd.hpp:" >&2
  echo "$intrinsics" >&2
  status=1
fi
[ $status -eq 0 ] && echo "the seam holds: OpenMP and intrinsics only in src/spall/core"
exit $status
