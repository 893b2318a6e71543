#!/usr/bin/env bash
# Where a jam step's time goes, as samples per sample of the kick pass (a streaming pass over the
# grains that changes with neither the contact law nor its memory access), so builds can be
# compared on a VM whose speed moves between runs (docs/notes/benchmark_log.md, "The contact
# pass's one stall"). Resumes CHECKPOINT (a copy of it) on one thread for SECONDS under `perf record`.
#
#   bash bench/step_shares.sh build/mrjam out/x/checkpoint.mrjam [seconds=30]
set -euo pipefail
if [[ $# -lt 2 || ! -x $1 || ! -f $2 ]]; then
  echo "usage: bash bench/step_shares.sh MRJAM CHECKPOINT [seconds]: MRJAM a built mrjam, CHECKPOINT a jam run's checkpoint.mrjam (Ctrl-C a run to get one)" >&2
  exit 2
fi
MRJAM=$(realpath "$1")
CHECKPOINT=$(realpath "$2")
SECONDS_RUN=${3:-30}
[[ $SECONDS_RUN =~ ^[1-9][0-9]*$ ]] || { echo "seconds must be a whole number of at least 1, not '$SECONDS_RUN'" >&2; exit 2; }
command -v perf > /dev/null || { echo "needs perf (apt-get install linux-perf)" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cp "$CHECKPOINT" "$WORK/checkpoint.mrjam"
cd "$WORK"
timeout -s INT "$SECONDS_RUN" perf record -q -o perf.data "$MRJAM" jam --resume checkpoint.mrjam --threads 1 --quiet > log 2>&1 || true
perf report -i perf.data --no-children --sort symbol -n 2> /dev/null | python3 -c '
import re, sys
parts = {"grain contacts": 0, "wall contacts": 0, "magnetic pairs": 0, "list builds": 0, "kick": 0, "all": 0}
for line in sys.stdin:
    m = re.match(r"\s*[\d.]+%\s+(\d+)\s+\[\.\]\s+(.*)", line)
    if not m:
        continue
    n, name = int(m.group(1)), m.group(2)
    parts["all"] += n
    if "grain_contacts" in name:
        parts["grain contacts"] += n
    elif "wall_contacts" in name or "hertz_mindlin" in name or "Wall::touch" in name:
        parts["wall contacts"] += n
    elif "pair_pass<" in name:
        parts["magnetic pairs"] += n
    elif "NeighborList::" in name or "fill_chunks" in name:
        parts["list builds"] += n
    elif "kick_pass<true, true" in name:
        parts["kick"] += n
if parts["kick"] == 0:
    sys.exit("no kick samples: the run ended before it stepped")
if parts["grain contacts"] == 0:
    sys.exit("no samples named grain_contacts: the build inlined the contact pass (lib/engine/forces.cpp keeps it out of line)")
print(", ".join("%s %.2f" % (k, v / parts["kick"]) for k, v in parts.items() if k != "kick"), "samples per kick sample")
'
