#!/usr/bin/env bash
# Fuzzes the scene readers (jam, shear, asteroid) and the unit parser with libFuzzer under
# AddressSanitizer and UndefinedBehaviorSanitizer (issue #43). A separate clang build in
# build-fuzz/; the seed corpus is tests/fuzz/corpus/ (the bundled examples and unit strings),
# new inputs that reach new code go to build-fuzz/corpus/. A finding (a crash, an exception other
# than a refusal, a sanitizer report, an input slower than 10 s) stops the run and is saved as
# build-fuzz/crash-* (or timeout-*): rerun it with `build-fuzz/mrjam-fuzz-scene FILE`.
# Usage: bash scripts/fuzz.sh [seconds, default 300]. Not part of CI's budget.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-300}"
bash "$root/scripts/install-deps.sh"
dpkg -s clang >/dev/null 2>&1 && dpkg -s libomp-dev >/dev/null 2>&1 || {
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends clang libomp-dev
}
build="$root/build-fuzz"
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined"
CXX=clang++ CC=clang cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DMRJAM_NATIVE=OFF -DMRJAM_FUZZ=ON \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build "$build" -j"$(nproc)" --target mrjam-fuzz-scene
mkdir -p "$build/corpus"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
./mrjam-fuzz-scene -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len=65536 \
  corpus "$root/tests/fuzz/corpus"
