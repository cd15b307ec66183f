#!/usr/bin/env bash
# Builds LAMMPS with its MACHDYN package (Smooth Mach Dynamics) from Debian's source package and
# times the Taylor bar of lammps_smd_taylor_bar.in, so that issue 3's peer is measured on the
# machine that measures Spall (Debian's binary lammps package leaves MACHDYN out).
#   [RANKS=2] bash bench/peers/lammps_smd.sh [across] [hfac] [warm] [steps]   (defaults: 35 2.37 200 500)
# RANKS: MPI ranks (default 1), the way SMD uses more than one core (it has no OpenMP styles).
# Prints particles, neighbours inside the support and particle-steps per second of the timed run.
# Adds a deb-src entry for bookworm to apt's sources where none is, and builds under
# build/peers/lammps (5 to 15 minutes on 2 cores, once).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
across=${1:-35} hfac=${2:-2.37} warm=${3:-200} steps=${4:-500} ranks=${RANKS:-1}
work=$root/build/peers/lammps
lmp=$work/build/lmp_smd
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
if [ ! -x "$lmp" ]; then
  if ! grep -rqs '^Types: deb-src\|^deb-src' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
      $SUDO tee /etc/apt/sources.list.d/spall-deb-src.sources >/dev/null
  fi
  $SUDO apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends xz-utils cmake g++ libeigen3-dev libopenmpi-dev
  mkdir -p "$work" && cd "$work"
  apt-get source --download-only lammps
  tar xf lammps_*.orig.tar.xz
  source_dir=$(ls -d "$work"/lammps-*/ | head -1)
  cmake -S "$source_dir/cmake" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-O3 -march=native" \
    -DPKG_MACHDYN=on -DDOWNLOAD_EIGEN3=no -DBUILD_MPI=yes -DBUILD_OMP=yes \
    -DLAMMPS_MACHINE=smd >"$work/build.log" 2>&1 || { tail -20 "$work/build.log"; exit 1; }
  echo "lammps_smd: building LAMMPS with MACHDYN (log: $work/build.log)"
  cmake --build "$work/build" -j "$(nproc)" >>"$work/build.log" 2>&1 || { tail -20 "$work/build.log"; exit 1; }
fi
log=$work/taylor_bar_${across}_${hfac}_${ranks}.log
cd "$work"
# One rank is not bound to a core, so that `taskset -c 1 bash bench/peers/lammps_smd.sh` runs it
# beside a Spall run pinned to core 0 (mpirun would bind it to core 0 as well: half the speed).
bind=""
[ "$ranks" -eq 1 ] && bind="--bind-to none"
OMP_NUM_THREADS=1 mpirun --allow-run-as-root $bind -np "$ranks" "$lmp" -in "$root/bench/peers/lammps_smd_taylor_bar.in" -log none \
  -var across "$across" -var hfac "$hfac" -var warm "$warm" -var steps "$steps" >"$log" 2>&1 || { tail -5 "$log"; exit 1; }
# The last "Loop time of T on P procs for N steps with M atoms" is the timed run; the neighbours are
# the thermo column c_neighbours at its last line.
awk -v log_file="$log" '
  /^Loop time of/ { seconds = $4; ranks = $6; steps = $9; atoms = $12 }
  /^ *[0-9]+ +[0-9.e+-]+ +[0-9.e+-]+ +[0-9]+ +[0-9.e+-]+ +[0-9.e+-]+ *$/ { neighbours = $5 }
  END {
    if (seconds == "") { print "lammps_smd: no timed run in " log_file > "/dev/stderr"; exit 1 }
    printf "LAMMPS SMD Taylor bar: %d particles, %.1f neighbours in support, %d steps in %.2f s on %d ranks: %.3g particle-steps/s, %.3g per core\n",
           atoms, neighbours, steps, seconds, ranks, atoms * steps / seconds, atoms * steps / seconds / ranks
  }' "$log"
