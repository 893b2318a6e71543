#!/usr/bin/env bash
# The unit and physics suites under AddressSanitizer and UndefinedBehaviorSanitizer (issue #43):
# a separate build in build-sanitize/ (-O1, frame pointers kept), every report fatal.
# Usage: bash scripts/sanitize.sh [doctest filters, e.g. -ts=unit]
# Takes about 15 minutes on a 2-core machine (build 11, tests 4); not part of CI's budget.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-sanitize"
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DMRJAM_NATIVE=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build "$build" -j"$(nproc)" --target mrjam_tests
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
# Leaks inside libgmsh (third party) are suppressed, by name, in scripts/lsan.supp.
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
if [[ $# -gt 0 ]]; then
  "$build/mrjam_tests" "$@"
else
  "$build/mrjam_tests" -ts=unit,physics
fi
