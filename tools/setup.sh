#!/usr/bin/env bash
# Installs the Debian packages Spall needs to build, test and post-process.
# `tools/setup.sh fuzz`: those the keyword reader's fuzz target needs instead (make fuzz): clang,
# libFuzzer (libfuzzer-14-dev; clang's -fsanitize=fuzzer links the copy in libclang-rt-14-dev) and
# LLVM's OpenMP.
# Skips apt entirely when everything is already present, so a warm machine starts fast.
set -euo pipefail
if [ "${1:-}" = fuzz ]; then
  packages=(cmake ninja-build clang libfuzzer-14-dev libclang-rt-14-dev libomp-dev libeigen3-dev libfmt-dev)
else
  packages=(
    build-essential cmake ninja-build
    libeigen3-dev libfmt-dev libcli11-dev
    libgtest-dev libbenchmark-dev
    libopenvdb-dev libboost-iostreams-dev
    libopenmpi-dev openmpi-bin
    python3-vtk9 python3-numpy python3-matplotlib
  )
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
