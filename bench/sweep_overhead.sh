#!/usr/bin/env bash
# The sweep engine's cost per point against running the mode directly, and points per hour on 1
# and 2 MPI ranks: examples/sweeps/table32.json (36 jam points on the continuum tier, each a
# fraction of a second, so the figures are the engine's and the processes' own cost).
# Usage: bash bench/sweep_overhead.sh [BUILD_DIR]   (prints a table; nothing is asserted)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
mrjam="${1:-$root/build}/mrjam"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sweep="$root/examples/sweeps/table32.json"
seconds() { local t0 t1; t0=$(date +%s.%N); "$@" > /dev/null 2>&1; t1=$(date +%s.%N); echo "$t1 - $t0" | bc -l; }

# The same 36 scenes run one by one, as a user would without the sweep.
"$mrjam" sweep "$sweep" --out "$work/scenes" --quiet
direct=$(seconds bash -c "for s in $work/scenes/points/p*/scene.json; do
  '$mrjam' jam \"\$s\" --fidelity continuum --report $work/direct.json --quiet; done")
serial=$(seconds "$mrjam" sweep "$sweep" --out "$work/serial" --quiet)
printf '| how | wall for 36 points (s) | per point (ms) | points per hour |\n|---|---|---|---|\n'
row() { printf '| %s | %.2f | %.0f | %.0f |\n' "$1" "$2" "$(echo "1000 * $2 / 36" | bc -l)" "$(echo "3600 * 36 / $2" | bc -l)"; }
row "each scene run directly" "$direct"
row "mrjam sweep, one process" "$serial"
if command -v mpirun > /dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  for np in 1 2; do
    row "mpirun -np $np mrjam sweep" "$(seconds mpirun --oversubscribe -np $np "$mrjam" sweep "$sweep" --out "$work/np$np" --quiet)"
  done
fi
