#!/usr/bin/env bash
# Speed against an earlier revision, both measured in this run (issue 10). Builds REV's
# wavemmlt and wavemmlt_bench in build-bench-old/ (as bench/mmlt_chains.sh does), then:
#   1. MMLT mutations per CPU-second (the process's user + system time, GNU time) on the seed
#      room (SPP mutations per pixel) and Bitterli's Cornell box (4 SPP: its renders are short),
#      65536 chains, the two binaries interleaved REPS times; prints each run, the medians and
#      new / old;
#   2. wavemmlt_bench of both (PT, BPT and MMLT as fractions of Embree's incoherent-ray
#      ceiling, thread scaling, bytes per chain), one after the other, the ratio lines only.
# Reads the scenes from ../shared/scenes/ beside the checkout and says so when they are missing.
#
#   bench/speed.sh --old REV [--reps N] [--spp N] [--skip-ceiling] [--skip-mmlt]
set -euo pipefail
cd "$(dirname "$0")/.."
old="" reps=5 spp=32 ceiling=1 mmlt=1
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --reps) reps=$2; shift 2 ;; --spp) spp=$2; shift 2 ;;
    --skip-ceiling) ceiling=0; shift ;; --skip-mmlt) mmlt=0; shift ;;
    *) echo "speed.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$old" ] || { echo "speed.sh: --old REV is required (the revision to compare with)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "speed.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
shared=../shared/scenes
scenes=()
for s in seed-room/seed-room.xml bitterli-cornell/bitterli-cornell-256.xml; do
  if [ -f "$shared/$s" ]; then scenes+=("$shared/$s"); else echo "speed.sh: $shared/$s is missing: left out" >&2; fi
done
[ ${#scenes[@]} -gt 0 ] || { echo "speed.sh: no scene found: nothing to measure" >&2; exit 0; }
cmake --build build -j"$(nproc)" --target wavemmlt wavemmlt_bench >/dev/null
. bench/old_build.sh
buildOld "$old" wavemmlt wavemmlt_bench
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# Mutations per CPU-second of one MMLT render: wavemmlt ARGS...
rate() {
  local b=$1 scene=$2 seed=$3 n=$spp
  case $scene in *cornell*) n=$((4 * spp)) ;; esac
  /usr/bin/time -f '%U %S' -o "$out/cpu" "$b" "$scene" --tracer mmlt --chains 65536 --spp "$n" --seed "$seed" \
    --quiet --stats "$out/s.json" -o "$out/o.pfm" >/dev/null
  local m
  m=$(grep -o '"mmlt_mutations": [0-9]*' "$out/s.json" | grep -o '[0-9]*$')
  awk -v m="$m" '{ printf "%.0f\n", m / ($1 + $2) }' "$out/cpu"
}
median() { sort -n | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }

[ "$mmlt" = 1 ] && echo "MMLT mutations per CPU-second, 65536 chains, $spp (Cornell box: $((4 * spp))) mutations per pixel; old = $old, new = $(git rev-parse --short HEAD)" &&
  printf '%-28s %12s %12s %8s\n' scene "old" "new" "new/old"
for scene in "${scenes[@]}"; do
  [ "$mmlt" = 1 ] || break
  : > "$out/old" && : > "$out/new"
  for r in $(seq 1 "$reps"); do
    rate "$oldBuild/wavemmlt" "$scene" "$r" >> "$out/old"
    rate build/wavemmlt "$scene" "$r" >> "$out/new"
  done
  echo "  runs old: $(tr '\n' ' ' < "$out/old")" >&2
  echo "  runs new: $(tr '\n' ' ' < "$out/new")" >&2
  o=$(median < "$out/old") n=$(median < "$out/new")
  awk -v s="$(basename "$scene")" -v o="$o" -v n="$n" 'BEGIN { printf "%-28s %12.0f %12.0f %8.2f\n", s, o, n, n / o }'
done

if [ "$ceiling" = 1 ]; then
  # The scenes by absolute path: each binary would look for them beside its own source.
  benchScenes=()
  for s in bunny/bunny.xml dragon/dragon-full.xml bitterli-cornell/bitterli-cornell-256.xml; do
    [ -f "$shared/$s" ] && benchScenes+=("$(realpath "$shared/$s")") || echo "speed.sh: $shared/$s is missing: left out" >&2
  done
  for b in "$oldBuild/wavemmlt_bench" build/wavemmlt_bench; do
    echo
    echo "$b:"
    "$b" "${benchScenes[@]}" 2>&1 | grep -E '^/|^2 |scaling|^bpt|^mmlt' || true
  done
fi
