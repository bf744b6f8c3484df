#!/usr/bin/env bash
# The thesis' chapter 6 as measured curves on the seed room (issue 4), each against the cached
# BPT reference of wavemmlt_bench_error:
#   6.1  time per mutation for MaxPathLength 3..15          -> OUT/time-per-mutation.csv (+ .png)
#   6.2  error vs time for ProbLarge 0.2, 0.4, 0.6, 0.8     -> OUT/p-large.csv (+ plots)
#   6.3  error vs time, BPT against MMLT (equal time)       -> OUT/bpt-mmlt.csv (+ plots)
#   and  error vs time for 1k, 16k and 65k chains           -> OUT/chains.csv (+ plots)
#
#   bench/mmlt_curves.sh [OUT] [BUDGETS]      (defaults: bench-mmlt, 2,4,8,16)
#
# Runs from the project root after scripts/setup.sh; reads ../shared/scenes/seed-room (says so
# and exits 0 when it is missing). The first run renders and caches the reference (about 10
# minutes on 2 cores); the curves take about 6 minutes more.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench-mmlt}
budgets=${2:-2,4,8,16}
scene=../shared/scenes/seed-room/seed-room.xml
if [ ! -r "$scene" ]; then
    echo "$0: $scene is missing (the curves read it from ../shared/scenes/); skipped"
    exit 0
fi
mkdir -p "$out"
size=256

# 6.1: seconds per mutation from --stats (65536 chains, 4 mutations per pixel).
echo "max_length,us_per_mutation,mrays_per_second,mutations" > "$out/time-per-mutation.csv"
for L in $(seq 3 15); do
    build/wavemmlt "$scene" --tracer mmlt --max-length "$L" --width $size --height $size --spp 4 \
        --quiet -o "$out/tmp.pfm" --stats "$out/tmp.json"
    awk -v L="$L" -F': ' '
        /"mmlt_mutations_per_second"/ { gsub(/,/, "", $2); mps = $2 }
        /"mrays_per_second"/ { gsub(/,/, "", $2); mr = $2 }
        /"mmlt_mutations"/ { gsub(/,/, "", $2); m = $2 }
        END { printf "%d,%.4f,%.3f,%d\n", L, 1e6 / mps, mr, m }' "$out/tmp.json" >> "$out/time-per-mutation.csv"
done
rm -f "$out/tmp.pfm" "$out/tmp.json"
cat "$out/time-per-mutation.csv"

bench=build/wavemmlt_bench_error
$bench "$scene" --tracers mmlt --sweep p-large=0.2,0.4,0.6,0.8 --budgets "$budgets" --csv "$out/p-large.csv"
$bench "$scene" --tracers bpt,mmlt --budgets "$budgets" --csv "$out/bpt-mmlt.csv"
$bench "$scene" --tracers mmlt --sweep chains=1024,16384,65536 --budgets "$budgets" --csv "$out/chains.csv"
for c in p-large bpt-mmlt chains; do bench/plot_error.sh "$out/$c.csv" "$out/$c"; done

command -v gnuplot >/dev/null && gnuplot <<GP
set terminal pngcairo size 800,500
set output "$out/time-per-mutation.png"
set datafile separator ","
set key top left
set xlabel "MaxPathLength"
set ylabel "microseconds per mutation"
set y2label "Mrays/s"
set y2tics
plot "$out/time-per-mutation.csv" every ::1 using 1:2 with linespoints title "time per mutation", \
     "" every ::1 using 1:3 axes x1y2 with linespoints title "Mrays/s"
GP
echo "curves in $out/"
