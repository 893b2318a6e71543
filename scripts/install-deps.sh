#!/usr/bin/env bash
# Installs everything mrjam needs from Debian's packages (run as root on a fresh machine).
set -euo pipefail
# libgmsh-dev (meshing, C++ API) and getdp (solver, run as a program) serve `mrjam magnetics`;
# librsvg2-dev renders the plots' PNG twins (with DejaVu for their text); libvalijson-dev checks
# the reports the tests make against their JSON Schemas (schemas/); python3 runs the doc checks;
# libnlopt-cxx-dev is the shear calibration's derivative-free search;
# Open MPI serves `mpirun -np N mrjam sweep` (a build without it still sweeps in one process).
# `--bench` adds the peers the benchmarks run side by side with mrjam (LIGGGHTS 3.8, callgrind).
packages=(build-essential cmake libeigen3-dev libpng-dev libcli11-dev nlohmann-json3-dev doctest-dev libgmsh-dev getdp
          libopenmpi-dev openmpi-bin librsvg2-dev fonts-dejavu-core libvalijson-dev python3
          libnlopt-cxx-dev)
if [ "${1:-}" = "--bench" ]; then packages+=(liggghts valgrind jq); fi
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
