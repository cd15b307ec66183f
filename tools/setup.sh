#!/usr/bin/env bash
# Installs the Debian packages Spall needs to build, test and post-process.
# Skips apt entirely when everything is already present, so a warm machine starts fast.
set -euo pipefail
packages=(
  build-essential cmake ninja-build
  libeigen3-dev libfmt-dev libcli11-dev
  libgtest-dev libbenchmark-dev
  libopenvdb-dev libboost-iostreams-dev
  python3-vtk9 python3-numpy python3-matplotlib
)
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
