#!/usr/bin/env bash
# The cost of spectral mode (issue 45, docs/spectral.md): each tracer's render time on the same
# scene in RGB (--rgb) and with sampled wavelengths (--spectral), both measured in this run,
# interleaved REPS times; with --old REV also REV's binary in RGB beside this one's (spectral
# mode must leave RGB renders as fast as they were). The time is the render's own (--stats
# "seconds": after loading and building the scene), 2 threads.
#
# Scenes (from the checkout: tests/data): pbrt-v4's Cornell box, and the same box with its
# fog kept everywhere (cornell-box-volume.pbrt with Integrator "volpath" and the camera in the
# fog, written to a temporary folder: a medium's coefficients at the wavelengths per segment).
# Tracers PT, BPT and MMLT at 128 x 128, with the spp below (MMLT: mutations per pixel).
# Prints per scene and tracer the medians, spectral / RGB, and (--old) new / old in RGB; each
# run's times go to stderr.
#
#   bench/spectral.sh [--old REV] [--reps N]
set -euo pipefail
cd "$(dirname "$0")/.."
old="" reps=3
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --reps) reps=$2; shift 2 ;;
    *) echo "spectral.sh: unknown option $1 (see the comment at the top of bench/spectral.sh)" >&2; exit 2 ;;
  esac
done
[[ $reps =~ ^[1-9][0-9]*$ ]] || { echo "spectral.sh: --reps wants a positive count" >&2; exit 2; }
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
oldBin=""
if [ -n "$old" ]; then
  . bench/old_build.sh
  buildOld "$old" wavemmlt
  oldBin=$oldBuild/wavemmlt
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

box=tests/data/scenes/pbrt-v4/cornell-box
# The fog box: the volume box's fog on both sides of every shape (the file names no other file)
# under volpath.
fog=$out/fog.pbrt
sed -e 's/^Integrator .*/Integrator "volpath"/' -e 's/^WorldBegin/WorldBegin\nMediumInterface "fog" "fog"/' \
  "$box/cornell-box-volume.pbrt" > "$fog"
grep -q '^Integrator "volpath"' "$fog" || { echo "spectral.sh: $box/cornell-box-volume.pbrt has no Integrator line to replace" >&2; exit 1; }

# seconds BINARY SCENE TRACER SPP MODE: one render's own time
seconds() {
  "$1" "$2" --tracer "$3" --spp "$4" --width 128 --height 128 --threads 2 --seed 1 "$5" --quiet \
    --stats "$out/s.json" -o "$out/o.pfm" >/dev/null
  grep -o '"seconds": [0-9.eE+-]*' "$out/s.json" | head -1 | grep -o '[0-9.eE+-]*$'
}
median() { sort -g | awk '{ a[NR] = $1 } END { print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2 }'; }

echo "render seconds, 128 x 128, 2 threads, medians of $reps interleaved runs; new = $(git rev-parse --short HEAD)${old:+, old = $old}"
printf '%-12s %-5s %5s %10s %10s %9s' scene tracer spp rgb spectral spec/rgb
[ -n "$old" ] && printf ' %10s %9s' "old rgb" new/old
echo
for scene in cornell-box fog; do
  file=$box/cornell-box.pbrt
  [ "$scene" = fog ] && file=$fog
  tracers="pt:256 bpt:32 mmlt:256"  # (about a second each; the fog's about two)
  [ "$scene" = fog ] && tracers="pt:64 bpt:8 mmlt:64"
  for ts in $tracers; do
    tracer=${ts%:*} spp=${ts#*:}
    : > "$out/rgb" && : > "$out/spec" && : > "$out/old"
    for _ in $(seq 1 "$reps"); do
      seconds build/wavemmlt "$file" "$tracer" "$spp" --rgb >> "$out/rgb"
      seconds build/wavemmlt "$file" "$tracer" "$spp" --spectral >> "$out/spec"
      [ -n "$oldBin" ] && seconds "$oldBin" "$file" "$tracer" "$spp" --rgb >> "$out/old"
    done
    echo "  $scene $tracer: rgb $(tr '\n' ' ' < "$out/rgb")| spectral $(tr '\n' ' ' < "$out/spec")${oldBin:+| old rgb $(tr '\n' ' ' < "$out/old")}" >&2
    r=$(median < "$out/rgb") s=$(median < "$out/spec")
    printf '%-12s %-5s %5s %10.3f %10.3f %9.2f' "$scene" "$tracer" "$spp" "$r" "$s" "$(awk -v a="$s" -v b="$r" 'BEGIN { print a / b }')"
    if [ -n "$oldBin" ]; then
      o=$(median < "$out/old")
      printf ' %10.3f %9.2f' "$o" "$(awk -v a="$r" -v b="$o" 'BEGIN { print a / b }')"
    fi
    echo
  done
done
