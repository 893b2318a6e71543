#!/usr/bin/env bash
# The magnetics mode's speed/accuracy table (docs/magnetics.md): every bracket variant and state
# at the standard tier, and the rectangular ON valve by every model and mesh level, with wall
# times on this machine. Usage: bash bench/magnetics_table.sh [build/mrjam] [out/magnetics_table]
# Needs python3 for the table. The finest mesh needs ~4 GB of memory and a few minutes.
set -euo pipefail
MRJAM=${1:-build/mrjam}
OUT=${2:-out/magnetics_table}
mkdir -p "$OUT"
run() {  # name, fidelity, scene JSON
  local name=$1 tier=$2 scene=$3
  echo "$scene" > "$OUT/$name.json"
  "$MRJAM" magnetics "$OUT/$name.json" --report "$OUT/$name.report.json" --fidelity "$tier" --quiet
  echo "done $name" >&2
}
valve='"valve": {"constriction": "30x"}'
for v in unguided rectangular curved unchamfered insert; do
  run "${v}_on_3d" standard "{\"variant\": \"$v\", \"state\": \"on\", $valve, \"output\": {\"directory\": \"$OUT/work\"}}"
  run "${v}_on_2d" quick "{\"variant\": \"$v\", \"state\": \"on\", $valve, \"output\": {\"directory\": \"$OUT/work\"}}"
  run "${v}_on_circuit" standard "{\"variant\": \"$v\", \"state\": \"on\", \"model\": \"circuit\", $valve}"
done
run rectangular_off_3d standard "{\"variant\": \"rectangular\", \"state\": \"off\", $valve, \"output\": {\"directory\": \"$OUT/work\"}}"
run rectangular_partial_3d standard "{\"variant\": \"rectangular\", \"state\": \"partial\", $valve, \"output\": {\"directory\": \"$OUT/work\"}}"
run rectangular_on_alnico_mu3.5 standard "{\"variant\": \"rectangular\", $valve, \"magnets\": {\"alnico\": {\"recoil_permeability\": 3.5}}, \"output\": {\"directory\": \"$OUT/work\"}}"
run insert_on_saturating standard "{\"variant\": \"insert\", $valve, \"materials\": {\"iron\": {\"model\": \"saturating\"}}, \"output\": {\"directory\": \"$OUT/work\"}}"
run rectangular_on_saturating standard "{\"variant\": \"rectangular\", $valve, \"materials\": {\"iron\": {\"model\": \"saturating\"}}, \"output\": {\"directory\": \"$OUT/work\"}}"
for level in "coarse 0.4 1.0" "paper 0.1 0.25" "finest 0.075 0.19"; do
  set -- $level
  run "rectangular_on_mesh_$1" standard "{\"variant\": \"rectangular\", $valve, \"mesh\": {\"fluid_size\": \"$2 mm\", \"device_size\": \"$3 mm\"}, \"output\": {\"directory\": \"$OUT/work\"}}"
done
python3 - "$OUT" <<'PY'
import json, sys, glob, os
out = sys.argv[1]
rows = {}
for f in sorted(glob.glob(os.path.join(out, '*.report.json'))):
    r = json.load(open(f)); name = os.path.basename(f)[:-len('.report.json')]
    rows[name] = r
ref = rows.get('rectangular_on_mesh_finest')
print('| case | model | mesh (fluid/device mm) | unknowns | mean B active mT | max B active mT | mean B inactive mT | wall s |')
print('|---|---|---|---|---|---|---|---|')
for name, r in rows.items():
    res = r['results']; fid = r['fidelity']; mesh = fid.get('mesh', {})
    m = f"{mesh.get('fluid_size', 0)*1e3:.3g}/{mesh.get('device_size', 0)*1e3:.3g}" if fid['model'] != 'circuit' else '-'
    print(f"| {name} | {fid['model']} | {m} | {r['mesh']['unknowns']} | {res['mean_B_active_T']*1e3:.2f} | "
          f"{res['max_B_active_T']*1e3:.1f} | {res['mean_B_inactive_T']*1e3:.4g} | {r['timing']['wall_s']:.1f} |")
if ref:
    b = ref['results']['mean_B_active_T']
    print(f"\nrelative to the finest mesh ({b*1e3:.2f} mT):")
    for name in ['rectangular_on_circuit', 'rectangular_on_2d', 'rectangular_on_mesh_coarse', 'rectangular_on_3d', 'rectangular_on_mesh_paper']:
        if name in rows:
            v = rows[name]['results']['mean_B_active_T']
            print(f"  {name}: {(v-b)/b*100:+.2f} %  ({rows[name]['timing']['wall_s']:.1f} s)")
PY
