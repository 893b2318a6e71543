#!/usr/bin/env bash
# mrjam-bench's "contact" scene against LIGGGHTS 3.8 on the identical initial state.
#
#   bench/contact_vs_liggghts.sh [MRJAM_BENCH_BINARY] [STEPS]
#
#   MRJAM_BENCH_BINARY  default build/mrjam-bench (a relative path is taken from the current directory)
#   STEPS         default 2000
#
# Environment:
#   LIGGGHTS         LIGGGHTS executable (default: liggghts on PATH; Debian's package installs
#                    /usr/bin/liggghts)
#   REPEAT           run each code this many times, alternating, and keep each one's fastest
#                    (default 3; a shared VM's timings vary by tens of per cent between runs)
#
# mrjam runs the scene, writes its initial state as a LAMMPS data file and a JSON summary;
# LIGGGHTS (bench/liggghts/contact.in, 1 process) then runs the same number of steps from that
# file. Both costs are given in core-microseconds per particle-step; for LIGGGHTS that is
# T*P*1e6/(N*M) from its "Loop time of T on P procs for N steps with M atoms" line. Results go
# to bench/out/ (contact.data, mrjam_contact.json, liggghts_contact.out,
# contact_vs_liggghts.json). Needs bash, awk, sed, grep; uses jq when present.
set -euo pipefail

usage() { sed -n '2,20s/^# \{0,1\}//p' "$0"; }
die() { echo "contact_vs_liggghts: $*" >&2; exit 1; }

case "${1:-}" in -h|--help) usage; exit 0 ;; esac
[ $# -le 2 ] || { usage >&2; exit 2; }

mrjam=${1:-build/mrjam-bench}
steps=${2:-2000}
if [ $# -ge 1 ] && [ "${mrjam#/}" = "$mrjam" ]; then mrjam="$PWD/$mrjam"; fi

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
if [ "${mrjam#/}" = "$mrjam" ]; then mrjam="$root/$mrjam"; fi

case "$steps" in ''|*[!0-9]*) die "STEPS must be a positive integer, got '$steps'" ;; esac
[ "$steps" -gt 0 ] || die "STEPS must be a positive integer, got '$steps'"
[ -x "$mrjam" ] || die "no mrjam-bench executable at $mrjam (build it: cmake -B build && cmake --build build)"

liggghts=${LIGGGHTS:-liggghts}
command -v "$liggghts" >/dev/null 2>&1 ||
    die "LIGGGHTS not found ('$liggghts'); install Debian's liggghts package or set LIGGGHTS"
repeat=${REPEAT:-${LIGGGHTS_REPEAT:-3}}
case "$repeat" in ''|*[!0-9]*|0) die "REPEAT must be a positive integer" ;; esac

out=bench/out
mkdir -p "$out"
data=$out/contact.data
mrjam_json=$out/mrjam_contact.json
lig_out=$out/liggghts_contact.out
result_json=$out/contact_vs_liggghts.json
rm -f "$data" "$mrjam_json" "$result_json"

# First number stored under "key" anywhere in a JSON file.
json_number() {
    local file=$1 key=$2 value=
    if command -v jq >/dev/null 2>&1; then
        value=$(jq -r --arg k "$key" 'first(.. | objects | select(has($k)) | .[$k]) // empty' "$file")
    else
        value=$(tr -d '\n\r' <"$file" |
            grep -o "\"$key\"[[:space:]]*:[[:space:]]*[-+0-9.eE]*" | head -n 1 |
            sed 's/.*:[[:space:]]*//')
    fi
    printf '%s' "$value"
}

is_number() { printf '%s' "$1" | grep -Eq '^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$'; }

# ---- mrjam and LIGGGHTS, alternating ---------------------------------------------------------
run_mrjam() {
    echo "== mrjam run $1/$repeat: $mrjam contact --steps $steps"
    "$mrjam" contact --steps "$steps" --write-data "$data" --json "$mrjam_json.run" ||
        die "mrjam-bench contact failed"
    [ -s "$data" ] || die "mrjam wrote no data file at $data"
    local us
    us=$(json_number "$mrjam_json.run" core_us_per_particle_step)
    is_number "$us" || die "no numeric core_us_per_particle_step in $mrjam_json.run"
    if [ -z "${mrjam_us:-}" ] || awk -v a="$us" -v b="$mrjam_us" 'BEGIN { exit !(a < b) }'; then
        mrjam_us=$us
        cp "$mrjam_json.run" "$mrjam_json"
    fi
    rm -f "$mrjam_json.run"
}
mrjam_us=
# ---- LIGGGHTS ------------------------------------------------------------------------------
best_t=
for ((run = 1; run <= repeat; run++)); do
    run_mrjam "$run"
    echo "== LIGGGHTS run $run/$repeat: $liggghts -in bench/liggghts/contact.in ($steps steps)"
    this_out=$out/liggghts_contact.run$run.out
    if ! "$liggghts" -in bench/liggghts/contact.in -var datafile "$data" -var steps "$steps" \
        -log none -nocite >"$this_out" 2>&1; then
        tail -n 20 "$this_out" >&2
        die "LIGGGHTS failed (full output in $this_out)"
    fi
    loop=$(grep -m 1 '^Loop time of ' "$this_out") ||
        { tail -n 20 "$this_out" >&2; die "no 'Loop time' line in $this_out"; }
    t=$(printf '%s\n' "$loop" | awk '{ print $4 }')
    echo "   $loop"
    if [ -z "$best_t" ] || awk -v a="$t" -v b="$best_t" 'BEGIN { exit !(a < b) }'; then
        best_t=$t
        cp "$this_out" "$lig_out"
    fi
    rm -f "$this_out"
done

atoms=$(awk '$2 == "atoms" && NF == 2 { print $1; exit }' "$data")

# "Loop time of T on P procs for N steps with M atoms[, finish time ...]"
read -r lig_t lig_p lig_n lig_m < <(grep -m 1 '^Loop time of ' "$lig_out" | awk '{ print $4, $6, $9, $12 }')
for v in "$lig_t" "$lig_p" "$lig_n" "$lig_m"; do
    is_number "$v" || die "cannot parse the Loop time line of $lig_out"
done
[ "$lig_n" = "$steps" ] || echo "warning: LIGGGHTS ran $lig_n steps, asked for $steps" >&2
[ -z "$atoms" ] || [ "$lig_m" = "$atoms" ] ||
    echo "warning: LIGGGHTS has $lig_m atoms, the data file $atoms (atoms lost?)" >&2

lig_version=$(sed -n '1s/.*Version \([^,]*\),.*/\1/p' "$lig_out")  # e.g. LIGGGHTS-PUBLIC 3.8.0
neighbors=$(sed -n 's/^Total # of neighbors = *\([0-9]*\).*/\1/p' "$lig_out" | head -n 1)
builds=$(sed -n 's/^Neighbor list builds = *\([0-9]*\).*/\1/p' "$lig_out" | head -n 1)
dangerous=$(sed -n 's/^Dangerous builds = *\([0-9]*\).*/\1/p' "$lig_out" | head -n 1)
# Last thermo row: step atoms ke rotational-ke sum-of-contact-counts.
read -r th_step th_ke th_rke th_cn < <(awk '
    /^ *Step / { inside = 1; next }
    /^Loop time of / { inside = 0 }
    inside && $1 ~ /^[0-9]+$/ && NF >= 5 { last = $1 " " $3 " " $4 " " $5 }
    END { print last }' "$lig_out") || true
contacts=$(awk -v c="${th_cn:-}" 'BEGIN { if (c != "") printf "%d", c / 2 }')
[ "${dangerous:-0}" = 0 ] || echo "warning: LIGGGHTS reports $dangerous dangerous neighbour builds" >&2

lig_us=$(awk -v t="$lig_t" -v p="$lig_p" -v n="$lig_n" -v m="$lig_m" \
    'BEGIN { printf "%.6g", t * p * 1e6 / (n * m) }')
ratio=$(awk -v a="$lig_us" -v b="$mrjam_us" 'BEGIN { if (b > 0) printf "%.4g", a / b; else print "null" }')

# ---- report --------------------------------------------------------------------------------
echo
echo "contact scene: $lig_m particles, $steps steps, 1 core each"
printf '  %-24s %s\n' "" "core-us per particle-step"
printf '  %-24s %s\n' "mrjam" "$mrjam_us"
printf '  %-24s %s   (loop %s s on %s proc)\n' "LIGGGHTS ${lig_version##* }" "$lig_us" "$lig_t" "$lig_p"
printf '  %-24s %s\n' "ratio LIGGGHTS / mrjam" "$ratio"
[ -z "${neighbors:-}" ] || echo "  LIGGGHTS: $neighbors neighbour pairs at the end, $builds list builds${contacts:+, $contacts contacts at step $th_step}"

json_or_null() { if is_number "${1:-}"; then printf '%s' "$1"; else printf 'null'; fi; }
{
    printf '{\n'
    printf '  "scene": "contact",\n'
    printf '  "steps": %s,\n' "$steps"
    printf '  "particles": %s,\n' "$lig_m"
    printf '  "mrjam": {\n'
    printf '    "binary": "%s",\n' "$(printf '%s' "$mrjam" | sed 's/[\\"]/\\&/g')"
    printf '    "summary": "%s",\n' "$mrjam_json"
    printf '    "core_us_per_particle_step": %s\n' "$mrjam_us"
    printf '  },\n'
    printf '  "liggghts": {\n'
    printf '    "version": "%s",\n' "$(printf '%s' "${lig_version:-unknown}" | sed 's/[\\"]/\\&/g')"
    printf '    "runs": %s,\n' "$repeat"
    printf '    "loop_time_s": %s,\n' "$lig_t"
    printf '    "procs": %s,\n' "$lig_p"
    printf '    "loop_steps": %s,\n' "$lig_n"
    printf '    "atoms": %s,\n' "$lig_m"
    printf '    "core_us_per_particle_step": %s,\n' "$lig_us"
    printf '    "neighbor_pairs": %s,\n' "$(json_or_null "${neighbors:-}")"
    printf '    "neighbor_builds": %s,\n' "$(json_or_null "${builds:-}")"
    printf '    "dangerous_builds": %s,\n' "$(json_or_null "${dangerous:-}")"
    printf '    "contacts_final": %s,\n' "$(json_or_null "${contacts:-}")"
    printf '    "kinetic_energy_final_J": %s,\n' "$(json_or_null "${th_ke:-}")"
    printf '    "rotational_energy_final_J": %s\n' "$(json_or_null "${th_rke:-}")"
    printf '  },\n'
    printf '  "ratio_liggghts_over_mrjam": %s\n' "$ratio"
    printf '}\n'
} >"$result_json"
echo "  written: $result_json"
