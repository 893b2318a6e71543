#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, run the main job (a quick valve design).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
# The main job, end to end (a few minutes): for the 20x and 40x constrictions, the curved
# bracket's applied field (gmsh + GetDP), its field map, the jam predictor in that field with
# 105 kPa applied to the closed valve, and the open valve's flow rate; then which constriction is
# the widest that still jams.
./build/mrjam design examples/design_quick.json --fidelity quick --report out/design_quick/report.json
# The engine on its own: grains settling in a box, with ParaView snapshots.
./build/mrjam run examples/settle_column.json --report out/settle_column/report.json --quiet
echo "design report: out/design_quick/report.json (per constriction: field, jam outcome, open flow);"
echo "  table.csv and plots of jam probability and open flow against the constriction in out/design_quick/;"
echo "  the field map, the jam report and a picture of the throat under out/design_quick/<constriction>/"
echo "DEM report: out/settle_column/report.json; snapshots (ParaView): out/settle_column/snapshot_*.vtk"
