#!/usr/bin/env bash
# The cost of pixel filters (docs/filters.md), measured in this run:
#   1. the box (every scene that names no other filter in the thesis format) against an
#      earlier revision's binary: CPU seconds (user + system, GNU time) of PT, LT, BPT and
#      MMLT (65536 chains) on Bitterli's Cornell box, the two binaries interleaved REPS
#      times; each run, the medians and new / old;
#   2. each filter against the box with the new binary (--filter), the same renders:
#      medians and filter / box.
# Reads the Cornell box from ../shared/scenes/ (tests/data's copy when that is missing).
#
#   bench/filters.sh --old REV [--reps N] [--spp N]
set -euo pipefail
cd "$(dirname "$0")/.."
old="" reps=3 spp=16
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --reps) reps=$2; shift 2 ;; --spp) spp=$2; shift 2 ;;
    *) echo "filters.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$old" ] || { echo "filters.sh: --old REV is required" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "filters.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
command -v bc >/dev/null || { echo "filters.sh: needs bc (apt-get install bc)" >&2; exit 1; }
scene=../shared/scenes/bitterli-cornell/bitterli-cornell-256.xml
if [ ! -f "$scene" ]; then
  echo "filters.sh: $scene is missing: using tests/data's copy" >&2
  scene=tests/data/scenes/bitterli-cornell/bitterli-cornell-256.xml
fi
source bench/old_build.sh
buildOld "$old" wavemmlt
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cpu() {  # cpu BINARY ARGS...: CPU seconds of one render
  local bin=$1; shift
  /usr/bin/time -f "%U %S" -o "$tmp/t" "$bin" "$scene" --quiet --spp "$spp" --seed 1 -o "$tmp/o.pfm" "$@"
  awk '{printf "%.2f", $1 + $2}' "$tmp/t"
}
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
tracers=("pt" "lt" "bpt" "mmlt --chains 65536")
echo "== box: $old against this checkout (CPU s, $spp spp, $reps interleaved runs)"
for t in "${tracers[@]}"; do
  o=() n=()
  for ((r = 0; r < reps; ++r)); do
    o+=("$(cpu "$oldBuild/wavemmlt" --tracer $t)")
    n+=("$(cpu build/wavemmlt --tracer $t)")
  done
  mo=$(median "${o[@]}") mn=$(median "${n[@]}")
  printf '%-22s old %s  new %s  medians %s / %s  new/old %.3f\n' "$t" "${o[*]}" "${n[*]}" "$mo" "$mn" "$(echo "$mn / $mo" | bc -l)"
done
echo "== each filter against the box, this checkout (CPU s medians of $reps)"
for t in "${tracers[@]}"; do
  declare -A m=()
  for f in box tent gaussian mitchell lanczos; do
    v=()
    for ((r = 0; r < reps; ++r)); do v+=("$(cpu build/wavemmlt --tracer $t --filter $f)"); done
    m[$f]=$(median "${v[@]}")
  done
  line=$(printf '%-22s box %s' "$t" "${m[box]}")
  for f in tent gaussian mitchell lanczos; do line+=$(printf '  %s %s (%.2f)' "$f" "${m[$f]}" "$(echo "${m[$f]} / ${m[box]}" | bc -l)"); done
  echo "$line"
  unset m
done
