#!/usr/bin/env bash
# Issue 26's pbrt-v4 importer figures, measured in this run with build/wavemmlt:
#   1. parse + build of each pbrt file that loads: wall seconds and peak RSS (GNU time) of
#      a 16 x 16, 1 spp render (the render itself is negligible), and --stats'
#      mesh and Embree bytes. The scenes are tests/data/scenes/pbrt-v4's (the killeroo, its
#      loopsubdiv at 3 levels, is the largest that loads) and, when present,
#      ../shared/scenes/pbrt-v4's others (refused ones are listed with their message);
#   2. MMLT mutations per second on the pbrt Cornell box next to the same box written in the
#      thesis format (tests/data/scenes/pbrt-v4/cornell-box/cornell-box-thesis.xml), 128 x 128,
#      both with a box filter (the pbrt file asks for a Gaussian), medians of REPS interleaved runs.
#
#   bench/pbrt.sh [--reps N]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=5
while [ $# -gt 0 ]; do
  case $1 in
    --reps) reps=$2; shift 2 ;;
    *) echo "pbrt.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "pbrt.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
bin=build/wavemmlt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
json() { grep -o "\"$2\": [0-9.e+-]*" "$1" | head -1 | awk '{print $2}'; }

echo "== parse + build (16 x 16, 1 spp, 2 threads)"
printf '%-44s %8s %9s %12s %12s\n' scene wall_s peak_MiB meshes_MiB embree_MiB
scenes=(tests/data/scenes/pbrt-v4/cornell-box/*.pbrt tests/data/scenes/pbrt-v4/killeroos/*.pbrt)
if [ -d ../shared/scenes/pbrt-v4 ]; then
  for f in ../shared/scenes/pbrt-v4/*/*.pbrt; do
    case $f in */geometry/*) ;; *) scenes+=("$f") ;; esac
  done
else
  echo "(../shared/scenes/pbrt-v4 is missing: only the test copies are measured)"
fi
for f in "${scenes[@]}"; do
  if /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin" "$f" --width 16 --height 16 --spp 1 --threads 2 \
       --stats "$tmp/s.json" -o "$tmp/o.exr" >/dev/null 2>"$tmp/err"; then
    read -r wall kb < "$tmp/time"
    meshes=$(grep -o '"meshes": [0-9]*' "$tmp/s.json" | awk '{printf "%.1f", $2 / 1048576}')
    embree=$(grep -o '"embree": [0-9]*' "$tmp/s.json" | awk '{printf "%.1f", $2 / 1048576}')
    printf '%-44s %8s %9.1f %12s %12s\n' "$(basename "$f")" "$wall" "$(echo "$kb / 1024" | bc -l)" "$meshes" "$embree"
  else
    printf '%-44s refused: %s\n' "$(basename "$f")" "$(grep -v '^warning' "$tmp/err" | head -1 | sed 's/^error: [^ ]*: //' | cut -c1-90)"
  fi
done

echo
echo "== MMLT mutations per second, the pbrt Cornell box and the same box in the thesis format (128 x 128, 16 mutations per pixel, $reps runs each, interleaved)"
pb=() th=()
for r in $(seq "$reps"); do
  "$bin" tests/data/scenes/pbrt-v4/cornell-box/cornell-box.pbrt --tracer mmlt --width 128 --height 128 --spp 16 --threads 2 --filter box \
      --stats "$tmp/p.json" -o "$tmp/p.exr" >/dev/null 2>&1
  pb+=("$(json "$tmp/p.json" mmlt_mutations_per_second)")
  "$bin" tests/data/scenes/pbrt-v4/cornell-box/cornell-box-thesis.xml --tracer mmlt --width 128 --height 128 --spp 16 --threads 2 --filter box \
      --stats "$tmp/t.json" -o "$tmp/t.exr" >/dev/null 2>&1
  th+=("$(json "$tmp/t.json" mmlt_mutations_per_second)")
done
mp=$(median "${pb[@]}") mt=$(median "${th[@]}")
printf 'pbrt file:   %.3g mutations/s (runs: %s)\n' "$mp" "${pb[*]}"
printf 'thesis file: %.3g mutations/s (runs: %s)\n' "$mt" "${th[*]}"
printf 'ratio pbrt / thesis: %.3f\n' "$(echo "$mp / $mt" | bc -l)"
