#!/usr/bin/env bash
# The jam predictor's table of each case at a tier (docs/notes/jam_measurements.md, "Where it stands"): the bundled
# Mix 2 valves at 20x, 30x and 40x in a uniform 230 mT, each with a 1 ms hold, N seeds each, JOBS
# runs at a time (default 2, one thread each), then the table (bench/jam_table.py). A report that
# finished before is kept and one interrupted (Ctrl-C) is resumed from its checkpoint, so a stopped
# table picks up where it left off.
#
#   bash bench/jam_tiers.sh [quick|standard|paper] [seeds] [build/mrjam] [out/jam_tiers]
#
# YOUNGS='0.5 GPa' sets the grains' Young's modulus (the examples': 1 GPa) and names the runs
# after it: the cost in accuracy of softer, faster grains (docs/notes/jam_measurements.md, "Softer grains").
# HOLD=K evaluates the magnetic forces every K steps and holds them in between
# (model/magnetic_update_interval), naming the runs after it (docs/notes/jam_measurements.md, "Held magnetic forces").
# LOOKUP=K looks the carrier flow up at the grains every K steps (model/flow_lookup_interval),
# naming the runs after it.
# SLAB=K sets the slab's thickness to K largest-grain diameters (model/slab_thickness_diameters),
# naming the runs after it (docs/notes/jam_measurements.md, "A 2-diameter slab").
#
# Quick tier: 2-6 minutes of a core per seed and case. Standard: 75-105 minutes. The 10 um mix
# (examples/valve_10um_30x.json) takes hours even at the quick tier; FINE=1 adds it. FINE=quick adds
# examples/valve_10um_30x_quick.json instead, its speed settings stacked and ended by a steady flow
# (about 40 minutes of a core per seed; docs/notes/jam_measurements.md, "The 10 um mix in minutes").
set -euo pipefail
TIER=${1:-quick}
SEEDS=${2:-1}
MRJAM=$(realpath "${3:-build/mrjam}")
OUT=${4:-out/jam_tiers}
HERE=$(cd "$(dirname "$0")/.." && pwd)
case $TIER in quick | standard | paper) ;; *) echo "tier must be quick, standard or paper, not '$TIER'" >&2; exit 2 ;; esac
[[ $SEEDS =~ ^[1-9][0-9]*$ ]] || { echo "seeds must be a whole number of at least 1, not '$SEEDS'" >&2; exit 2; }
[[ -x $MRJAM ]] || { echo "no mrjam at $MRJAM: build it first (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$OUT"
OUT=$(realpath "$OUT")

cases=(valve_mix2_20x valve_mix2_30x valve_mix2_40x)
case ${FINE:-0} in
  0) ;;
  1) cases+=(valve_10um_30x) ;;
  quick) cases+=(valve_10um_30x_quick) ;;
  *) echo "FINE must be 0, 1 or quick, not '$FINE'" >&2; exit 2 ;;
esac

# One job per case and seed: a copy of the example with its seed and its own output directory.
jobs=()
for c in "${cases[@]}"; do
  for ((s = 1; s <= SEEDS; s++)); do
    name="${c}_${TIER}_s$s"
    [[ -n ${YOUNGS:-} ]] && name="${c}_${TIER}_E${YOUNGS// /}_s$s"
    [[ -n ${HOLD:-} ]] && name="${name%_s$s}_hold${HOLD}_s$s"
    [[ -n ${LOOKUP:-} ]] && name="${name%_s$s}_lookup${LOOKUP}_s$s"
    [[ -n ${SLAB:-} ]] && name="${name%_s$s}_slab${SLAB}_s$s"
    python3 - "$HERE/examples/$c.json" "$OUT/$name.json" "$s" "$OUT/$name" "${YOUNGS:-}" "${HOLD:-}" "${LOOKUP:-}" "${SLAB:-}" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["seed"] = int(sys.argv[3])
scene.setdefault("output", {})["directory"] = sys.argv[4]
if sys.argv[5]:
    scene.setdefault("material", {})["youngs_modulus"] = sys.argv[5]
if sys.argv[6]:
    scene.setdefault("model", {})["magnetic_update_interval"] = int(sys.argv[6])
if sys.argv[7]:
    scene.setdefault("model", {})["flow_lookup_interval"] = int(sys.argv[7])
if sys.argv[8]:
    scene.setdefault("model", {})["slab_thickness_diameters"] = float(sys.argv[8])
json.dump(scene, open(sys.argv[2], "w"), indent=1)
PY
    jobs+=("$name")
  done
done

run_one() {
  local name=$1 report=$OUT/$1.report.json status="" checkpoint=""
  if [[ -f $report ]]; then
    read -r status checkpoint < <(python3 -c "import json, sys; r = json.load(open(sys.argv[1])); print(r.get('status', ''), r.get('checkpoint', ''))" "$report")
  fi
  if [[ $status == complete ]]; then
    echo "[jam_tiers] $name: done before, kept" >&2
    return 0
  fi
  local args=("$OUT/$name.json" --fidelity "$TIER")
  if [[ $status == interrupted && -f $checkpoint ]]; then  # Ctrl-C kept a checkpoint: go on from it
    echo "[jam_tiers] $name: resuming from $checkpoint" >&2
    args=(--resume "$checkpoint")
  else
    echo "[jam_tiers] $name: running" >&2
  fi
  "$MRJAM" jam "${args[@]}" --report "$report" --threads 1 --quiet ||
    echo "[jam_tiers] $name: stopped with exit code $? (its partial report is kept)" >&2
}
export -f run_one
export MRJAM OUT TIER
printf '%s\n' "${jobs[@]}" | xargs -P "${JOBS:-2}" -I{} bash -c 'run_one {}'

reports=()
for name in "${jobs[@]}"; do reports+=("$OUT/$name.report.json"); done
python3 "$HERE/bench/jam_table.py" "${reports[@]}"
