#!/usr/bin/env bash
# One command for the test suite: install dependencies, build (warnings as errors), run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
./scripts/build.sh
ctest --test-dir build --output-on-failure --timeout 900 -j "$(nproc)"
