#!/usr/bin/env bash
# MMLT's memory against PT's (issue 14): peak resident memory (GNU time's %M) of one render of
# Bitterli's Cornell box at 1920 x 1080 and 3840 x 2160 with MaxPathLength 10 and 64, one
# mutation (PT: one sample) per pixel, 65536 chains; with --old REV also that revision's MMLT
# (built in build-bench-old/, as bench/mmlt_chains.sh does). Prints one row per size and
# length: PT's peak, MMLT's peak, MMLT's chain state (its --stats), and the ratio
# (MMLT - chain state) / PT, which the design keeps below 2.
#
#   bench/mmlt_memory.sh [--old REV] [--threads N]
set -euo pipefail
cd "$(dirname "$0")/.."
old="" threads=2
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --threads) threads=$2; shift 2 ;;
    *) echo "mmlt_memory.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
scene=../shared/scenes/bitterli-cornell/bitterli-cornell.xml
[ -f "$scene" ] || { echo "mmlt_memory.sh: $scene is missing (the shared scenes folder beside the checkout): nothing to measure" >&2; exit 0; }
[ -x /usr/bin/time ] || { echo "mmlt_memory.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
bin=build/wavemmlt
[ -x "$bin" ] || scripts/setup.sh
oldBin=""
if [ -n "$old" ]; then
  . bench/old_build.sh
  buildOld "$old" wavemmlt
  oldBin=$oldBuild/wavemmlt
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
peak() {  # peak resident KiB of: wavemmlt ARGS...
  local b=$1; shift
  /usr/bin/time -f %M -o "$out/rss" "$b" "$scene" --quiet --threads "$threads" --spp 1 -o "$out/o.exr" "$@" >/dev/null
  cat "$out/rss"
}
printf '%-11s %4s %10s %10s %12s %18s %12s\n' size L "PT MB" "MMLT MB" "chains MB" "(MMLT-chains)/PT" "old MMLT MB"
for size in 1920x1080 3840x2160; do
  for L in 10 64; do
    w=${size%x*} h=${size#*x}
    pt=$(peak "$bin" --tracer pt --width "$w" --height "$h" --max-length "$L")
    mm=$(peak "$bin" --tracer mmlt --chains 65536 --width "$w" --height "$h" --max-length "$L" --stats "$out/s.json")
    chain=$(grep -o '"mmlt_chain_state_bytes": [0-9]*' "$out/s.json" | grep -o '[0-9]*$')
    oldmm=-
    [ -n "$oldBin" ] && oldmm=$(( $(peak "$oldBin" --tracer mmlt --chains 65536 --width "$w" --height "$h" --max-length "$L") / 1024 ))
    awk -v s="$size" -v L="$L" -v pt="$pt" -v mm="$mm" -v ch="$chain" -v o="$oldmm" \
      'BEGIN { printf "%-11s %4d %10.0f %10.0f %12.1f %18.2f %12s\n", s, L, pt / 1024, mm / 1024, ch / 1048576, (mm - ch / 1024) / pt, o }'
  done
done
