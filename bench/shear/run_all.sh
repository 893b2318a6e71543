#!/bin/bash
# Reproduces the measured tables of docs/shear.md: the tiers of the bundled example (seeds 1 and 2)
# and the sensitivity variants, one run at a time on one thread (about 45 minutes on a 2-core VM).
# Reports go to out/bench_shear/<name>/report.json; `mrjam` is taken from build/.
set -u
cd "$(dirname "$0")/../.."
mrjam=build/mrjam
run() {  # name scene tier
    mkdir -p out/bench_shear/$1
    /usr/bin/time -f "%e s wall" $mrjam shear "$2" --report out/bench_shear/$1/report.json --fidelity "$3" --threads 1 --quiet \
        2> out/bench_shear/$1.log || echo "$1 failed (see out/bench_shear/$1.log)"
}
for tier in quick standard paper; do run ${tier}_seed1 examples/shear_trendler_00-100.json $tier; done
run quick_seed2 bench/shear/seed2.json quick
run standard_seed2 bench/shear/seed2.json standard
for v in saturation no_rolling monodisperse volume_reading density10 field_sweep; do run quick_$v bench/shear/$v.json quick; done
# Lees-Edwards boundaries and monolayer cells (docs/shear.md, about 12 minutes).
for v in lees_edwards lees_edwards_seed2 monolayer monolayer_lees_edwards; do run quick_$v bench/shear/$v.json quick; done
