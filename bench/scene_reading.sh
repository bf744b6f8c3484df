#!/usr/bin/env bash
# Issue 42's reading figures, the previous binary beside this one in one run (interleaved):
# wall seconds and peak resident MiB (GNU time) of `wavemmlt FILE --describe` (load and check
# the scene, no render) for
#   - good files: a generated pbrt trianglemesh of 1 M vertices as text and as .pbrt.gz, and
#     when present ../shared/scenes/pbrt-v4's killeroo (a 286 kB included mesh) and Veach Ajar;
#   - bad ones: a .pbrt.gz inflating to 256 MiB of NUL bytes, one inflating to 64 MiB of
#     "0 " inside one point3 P array (no ]): both refused, exit 2.
# Medians of REPS runs each.
#   bench/scene_reading.sh --old REV [--reps N]     (e.g. --old d1a157e)
set -euo pipefail
cd "$(dirname "$0")/.."
old="" reps=3
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    *) echo "scene_reading.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$old" ] || { echo "scene_reading.sh: give --old REV (the revision to compare with)" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "scene_reading.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
source bench/old_build.sh
buildOld "$old" wavemmlt
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

python3 - "$tmp" <<'PY'
import gzip, sys, random
d = sys.argv[1]
random.seed(1)
n = 1000000
head = 'LookAt 0 0 -5  0 0 0  0 1 0\nCamera "perspective"\nWorldBegin\nLightSource "point" "point3 from" [ 0 0 -3 ]\n'
pts = ' '.join('%.6f %.6f %.6f' % (random.random(), random.random(), random.random()) for _ in range(n))
idx = ' '.join('%d %d %d' % (i, i + 1, i + 2) for i in range(0, n - 2, 3))
text = head + 'Shape "trianglemesh" "point3 P" [ ' + pts + ' ] "integer indices" [ ' + idx + ' ]\n'
open(d + '/mesh.pbrt', 'w').write(text)
open(d + '/mesh.pbrt.gz', 'wb').write(gzip.compress(text.encode(), 6))
mib = b'\0' * (1 << 20)
member = gzip.compress(mib, 9)
open(d + '/nul.pbrt.gz', 'wb').write(gzip.compress(b'') + member * 256)
zeros = gzip.compress(b'0 ' * (1 << 19), 9)
open(d + '/numbers.pbrt.gz', 'wb').write(gzip.compress(b'WorldBegin\nLightSource "point"\nShape "trianglemesh" "point3 P" [ ') + zeros * 64)
PY
cases=("$tmp/mesh.pbrt" "$tmp/mesh.pbrt.gz")
for f in ../shared/scenes/pbrt-v4/killeroos/killeroo-simple.pbrt ../shared/scenes/pbrt-v4/veach-ajar/veach-ajar.pbrt; do
  if [ -f "$f" ]; then cases+=("$f"); else echo "($f is missing: not measured)"; fi
done
cases+=("$tmp/nul.pbrt.gz" "$tmp/numbers.pbrt.gz")

printf '%-22s %6s | %9s %9s | %9s %9s | %s\n' file exit old_s new_s old_MiB new_MiB new/old_time
for f in "${cases[@]}"; do
  ot=() nt=() om=() nm=()
  for ((r = 0; r < reps; r++)); do
    for which in old new; do
      b=build/wavemmlt; [ $which = old ] && b=$oldBuild/wavemmlt
      set +e
      /usr/bin/time -f "%e %M" -o "$tmp/t" "$b" "$f" --describe >/dev/null 2>"$tmp/err"
      rc=$?
      set -e
      read -r s kb < <(tail -1 "$tmp/t")
      if [ $which = old ]; then ot+=("$s"); om+=($((kb / 1024))); else nt+=("$s"); nm+=($((kb / 1024))); nrc=$rc; fi
    done
  done
  o=$(median "${ot[@]}") n=$(median "${nt[@]}")
  printf '%-22s %6s | %9s %9s | %9s %9s | %s\n' "$(basename "$f")" "$nrc" "$o" "$n" "$(median "${om[@]}")" "$(median "${nm[@]}")" \
    "$(awk -v a="$o" -v b="$n" 'BEGIN {printf (a > 0 ? "%.2f" : "-"), b / a}')"
done
