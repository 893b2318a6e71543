#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, run the bundled example scene.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
# The valve's field (gmsh + GetDP, ~15 s), then the field map drives grains in the engine.
./build/mrjam magnetics examples/epm_rectangular_on.json --report out/epm_rectangular_on/report.json \
    --field-map out/epm_rectangular_on/field.map
./build/mrjam run examples/settle_column.json --report out/settle_column/report.json
echo "magnetics report: out/epm_rectangular_on/report.json (picture: out/epm_rectangular_on/report_B_midplane.png)"
echo "DEM report: out/settle_column/report.json; snapshots (ParaView): out/settle_column/snapshot_*.vtk"
