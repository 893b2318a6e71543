#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, install mrjam (under PREFIX, default
# ~/.local: bin/mrjam, bin/mrjam-bench, share/doc/mrjam, share/mrjam/examples) and run the main
# job, a quick valve design, with the installed program.
set -euo pipefail
cd "$(dirname "$0")/.."
PREFIX=${PREFIX:-$HOME/.local}
./scripts/install-deps.sh
./scripts/build.sh
cmake --install build --prefix "$PREFIX" >/dev/null
mrjam="$PREFIX/bin/mrjam"
echo "installed: $mrjam (add $PREFIX/bin to PATH to type mrjam)"
# The main job, end to end (a few minutes): for the 20x and 40x constrictions, the curved
# bracket's applied field (gmsh + GetDP), its field map, the jam predictor in that field with
# 105 kPa applied to the closed valve, and the open valve's flow rate; then which constriction is
# the widest that still jams.
"$mrjam" design examples/design_quick.json --fidelity quick --report out/design_quick/report.json
# The engine on its own: grains settling in a box, with ParaView snapshots.
"$mrjam" run examples/settle_column.json --report out/settle_column/report.json --quiet
echo "design report: out/design_quick/report.json (per constriction: field, jam outcome, open flow);"
echo "  the summary figure out/design_quick/summary.png (jam probability, open flow, the field), table.csv;"
echo "  the field map, the jam report and a picture of the throat under out/design_quick/<constriction>/"
echo "DEM report: out/settle_column/report.json; snapshots (ParaView): out/settle_column/snapshot_*.vtk"
