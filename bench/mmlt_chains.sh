#!/usr/bin/env bash
# MMLT at full width (issue 9): equal-time error for 1k, 4k, 16k and 65k chains on the seed
# room and the Cornell box, this build against an earlier revision built side by side, runs
# interleaved (old, new, old, new ...) so that both see the same machine load; then the
# tasks per round and the longest/mean task ratio of this build at each chain count.
#
#   bench/mmlt_chains.sh [--old REV] [--budgets 4,16,32] [--chains 1024,4096,16384,65536]
#                        [--reps N] [--size WxH] [--out DIR]
#
# REV defaults to 5b79c02 (MMLT before the pass/pool design). The old revision is built in
# build-bench-old/ (a git worktree in build-bench-old/src). Scenes and the cached BPT
# references: see bench/bench_error.cpp (both binaries share its cache, build/bench-cache).
# Prints one table per scene: RMSE (against the reference) per budget and chain count, old
# and new, and the ratio RMSE(65536) / RMSE(1024) of each. CSVs in OUT (build/bench-chains).
set -euo pipefail
cd "$(dirname "$0")/.."
old=5b79c02 budgets=4,16,32 chains=1024,4096,16384,65536 reps=1 size=256x256 out=build/bench-chains
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --budgets) budgets=$2; shift 2 ;; --chains) chains=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;; --size) size=$2; shift 2 ;; --out) out=$2; shift 2 ;;
    *) echo "mmlt_chains.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
scenes=(../shared/scenes/seed-room/seed-room.xml ../shared/scenes/bitterli-cornell/bitterli-cornell-256.xml)
for s in "${scenes[@]}"; do
  [ -f "$s" ] || { echo "mmlt_chains.sh: $s is missing (the shared scenes folder beside the checkout): nothing to measure" >&2; exit 0; }
done
cache=build/bench-cache  # shared with wavemmlt_bench_error's default
mkdir -p "$out" "$cache"
new=build/wavemmlt_bench_error
[ -x "$new" ] || scripts/setup.sh
. bench/old_build.sh
buildOld "$old" wavemmlt_bench_error
oldBin=$oldBuild/wavemmlt_bench_error
IFS=, read -r -a budgetList <<< "$budgets"
IFS=, read -r -a chainList <<< "$chains"
for s in "${scenes[@]}"; do
  name=$(basename "$s" .xml)
  : > "$out/$name-old.csv"; : > "$out/$name-new.csv"
  for b in "${budgetList[@]}"; do
    for c in "${chainList[@]}"; do
      for which in old new; do
        bin=$new; [ $which = old ] && bin=$oldBin
        "$bin" "$s" --tracers mmlt --budgets "$b" --chains "$c" --reps "$reps" --size "$size" \
               --cache "$cache" --csv "$out/tmp.csv" >/dev/null
        tail -n +2 "$out/tmp.csv" | sed "s/^/$c,/" >> "$out/$name-$which.csv"
      done
    done
  done
  echo "== $name: RMSE against the reference at equal time (MMLT, $size, $reps rep(s)); old = $old"
  printf '%8s' "chains"; for b in "${budgetList[@]}"; do printf '%18s' "${b}s old / new"; done; echo
  for c in "${chainList[@]}"; do
    printf '%8s' "$c"
    for b in "${budgetList[@]}"; do
      o=$(awk -F, -v c="$c" -v b="$b" '$1 == c && $5 + 0 == b + 0 { print $8 }' "$out/$name-old.csv")
      n=$(awk -F, -v c="$c" -v b="$b" '$1 == c && $5 + 0 == b + 0 { print $8 }' "$out/$name-new.csv")
      printf '%18s' "$(printf '%.4f / %.4f' "$o" "$n")"
    done
    echo
  done
  echo "RMSE(${chainList[${#chainList[@]}-1]} chains) / RMSE(${chainList[0]} chains):"
  for which in old new; do
    printf '%8s' "$which"
    for b in "${budgetList[@]}"; do
      r=$(awk -F, -v b="$b" -v lo="${chainList[0]}" -v hi="${chainList[${#chainList[@]}-1]}" \
          '$5 + 0 == b + 0 && $1 == lo { l = $8 } $5 + 0 == b + 0 && $1 == hi { h = $8 } END { if (l > 0) printf "%.2f", h / l }' \
          "$out/$name-$which.csv")
      printf '%18s' "ratio $r"
    done
    echo
  done
  echo "tasks per round and longest/mean task (this build, 4 s each):"
  for c in "${chainList[@]}"; do
    build/wavemmlt "$s" --tracer mmlt --chains "$c" --time 4 --quiet --width "${size%x*}" --height "${size#*x}" \
      -o "$out/t.pfm" --stats "$out/t.json"
    printf '  %6s chains: %s tasks per round, longest/mean %s, %s passes of %s iterations\n' "$c" \
      "$(grep -o '"mmlt_tasks_per_round": [0-9]*' "$out/t.json" | grep -o '[0-9]*$')" \
      "$(grep -o '"mmlt_longest_task_ratio": [0-9.]*' "$out/t.json" | grep -o '[0-9.]*$')" \
      "$(grep -o '"mmlt_passes": [0-9]*' "$out/t.json" | grep -o '[0-9]*$')" \
      "$(grep -o '"mmlt_pass_length": [0-9]*' "$out/t.json" | grep -o '[0-9]*$')"
  done
done
