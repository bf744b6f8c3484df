#!/usr/bin/env bash
# The comparison the MMLT paper makes, on any scenes: equal-time error curves of PT, BPT,
# PSSMLT and MMLT (issue 29). For each scene, wavemmlt_bench_error renders every tracer at
# every budget with REPS seeds, against its cached BPT reference, and prints RMSE (with the
# runs' spread), relative RMSE and MSE, samples or mutations per second, MMLT's and
# PSSMLT's acceptance rates of small and large steps, and the equal-time ratios
# RMSE(mmlt) / RMSE(pssmlt) and RMSE(pt) / RMSE(bpt) per budget.
#
#   bench/tracer_curves.sh [OUT] [BUDGETS] [REPS] [SCENE ...]
#       defaults: bench-tracers, 2,4,8,16, 3, and the seed room, Bitterli's Cornell box and
#       Bitterli's veach-bidir (its Mitsuba 3 file) from ../shared/scenes/
#
# Writes OUT/curves.csv (bench_error.cpp's columns), OUT/<scene>.png (bench/plot_error.sh:
# RMSE and relative MSE against time, bars from the least to the greatest run) and
# OUT/summary.txt (the printed tables). Scenes that are missing are named and skipped. The
# first run renders and caches each reference (BPT, 256 x 256: about 5 to 10 minutes per
# scene on 2 cores); the curves take about 4 x REPS x (sum of BUDGETS) seconds per scene.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench-tracers}
budgets=${2:-2,4,8,16}
reps=${3:-3}
shift $(( $# < 3 ? $# : 3 ))
scenes=("$@")
shared=../shared/scenes
if [ ${#scenes[@]} -eq 0 ]; then
    scenes=("$shared/seed-room/seed-room.xml" "$shared/bitterli-cornell/bitterli-cornell-256.xml"
            "$shared/mitsuba/veach-bidir/scene.xml")
fi
present=()
for s in "${scenes[@]}"; do
    if [ -r "$s" ]; then present+=("$s"); else echo "$0: $s is missing (read from ../shared/scenes/); skipped"; fi
done
[ ${#present[@]} -gt 0 ] || exit 0
[ -x build/wavemmlt_bench_error ] || { echo "$0: build/wavemmlt_bench_error is missing: run scripts/setup.sh" >&2; exit 2; }
mkdir -p "$out"
build/wavemmlt_bench_error "${present[@]}" --tracers pt,bpt,pssmlt,mmlt --budgets "$budgets" --reps "$reps" \
    --csv "$out/curves.csv" | tee "$out/summary.txt"
bench/plot_error.sh "$out/curves.csv" "$out"
