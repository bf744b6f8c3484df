#!/usr/bin/env bash
# The light-sample flat loops over several lights (issue 25), against an earlier revision,
# both measured in this run: CPU seconds (user + system, GNU time) of PT, LT, BPT and MMLT
# (65536 chains) on Bitterli's Cornell box with its light cut in two rectangles (written
# here from tests/data's copy) and on the box as it is (one light), the two binaries
# interleaved REPS times; each run, the medians, new / old, and whether the images are the
# same bits (they must be: the loops change no arithmetic).
#
#   bench/lights.sh --old REV [--reps N] [--spp N]
set -euo pipefail
cd "$(dirname "$0")/.."
old="" reps=5 spp=32
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --reps) reps=$2; shift 2 ;; --spp) spp=$2; shift 2 ;;
    *) echo "lights.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$old" ] || { echo "lights.sh: --old REV is required" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "lights.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
command -v bc >/dev/null || { echo "lights.sh: needs bc (apt-get install bc)" >&2; exit 1; }
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
source bench/old_build.sh
buildOld "$old" wavemmlt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
src=tests/data/scenes/bitterli-cornell
cp -r "$src/meshes" "$tmp/"
cp "$src/bitterli-cornell-256.xml" "$tmp/one.xml"
python3 - "$tmp" <<'PY'
import sys
tmp = sys.argv[1]
s = open(f"{tmp}/one.xml").read()
i = s.index('  <Light Type="Area" ID="0">')
j = s.index('</Light>', i) + len('</Light>')
light = s[i:j]
half = lambda x, ident: (light.replace('ID="0"', f'ID="{ident}"')
                         .replace('<Position x="-0.005"', f'<Position x="{x}"')
                         .replace('<Width value="0.47"/>', '<Width value="0.235"/>'))
assert '<Width value="0.47"/>' in light and '<Position x="-0.005"' in light
open(f"{tmp}/two.xml", "w").write(s[:i] + half(-0.1225, 0) + "\n" + half(0.1125, 1) + s[j:])
PY
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
cpu() {  # binary scene tracer seed out
  local extra=()
  [ "$3" = mmlt ] && extra=(--chains 65536)
  /usr/bin/time -f '%U %S' -o "$tmp/t" "$1" "$2" --tracer "$3" --spp "$spp" --seed "$4" --quiet -o "$5" "${extra[@]}" >/dev/null
  awk '{printf "%.2f", $1 + $2}' "$tmp/t"
}
echo "== CPU s, $spp spp, $reps interleaved runs; old = $old, new = $(git rev-parse --short HEAD)"
for scene in two one; do
  for t in pt lt bpt mmlt; do
    o=() n=()
    for ((r = 1; r <= reps; ++r)); do
      o+=("$(cpu "$oldBuild/wavemmlt" "$tmp/$scene.xml" $t $r "$tmp/o.pfm")")
      n+=("$(cpu build/wavemmlt "$tmp/$scene.xml" $t $r "$tmp/n.pfm")")
    done
    same=$(cmp -s "$tmp/o.pfm" "$tmp/n.pfm" && echo "same image" || echo "IMAGES DIFFER")
    mo=$(median "${o[@]}") mn=$(median "${n[@]}")
    printf '%-4s %-5s old %s  new %s  medians %s / %s  new/old %.3f  (%s)\n' "$scene" $t "${o[*]}" "${n[*]}" \
      "$mo" "$mn" "$(echo "$mn / $mo" | bc -l)" "$same"
  done
done
