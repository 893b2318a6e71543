#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, run the bundled example scene.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
./build/mrjam run examples/settle_column.json --report out/settle_column/report.json
echo "report: out/settle_column/report.json; snapshots (ParaView): out/settle_column/snapshot_*.vtk"
