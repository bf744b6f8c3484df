#!/usr/bin/env bash
# Issue 27's media figures with build/wavemmlt, measured in this run (docs/media.md):
#   1. the path tracer on the shared volumetric caustic (../shared/scenes/pbrt-v4/cornell-box/
#      volumetric-caustic.pbrt: a glass sphere in homogeneous fog under a light), 256 x 256,
#      SPP samples per pixel: with the fog (the file's integrator made "volpath") and without
#      it (the file as it is: pbrt's "path" ignores media): wall and CPU seconds, rays per
#      second, samples per second; medians of REPS runs, interleaved;
#   2. a heterogeneous medium: a 32^3 grid of a smooth random density (a blob of smoke, sparse
#      at the edges) in a Cornell-like box written here, PT at 128 x 128: the same figures.
# The other tracers do not render media yet (issue 27): no equal-time comparison of them.
# Says so and skips part 1 when the shared scene is missing.
#
#   bench/media.sh [--reps N] [--spp N]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=3
spp=16
while [ $# -gt 0 ]; do
  case $1 in
    --reps) reps=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    *) echo "media.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "media.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
cmake --build build -j"$(nproc)" --target wavemmlt >/dev/null
bin=build/wavemmlt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
json() { grep -o "\"$2\": [0-9.e+-]*" "$1" | head -1 | awk '{print $2}'; }

# run NAME ARGS...: REPS renders; prints the medians of wall s, CPU s, Mrays/s
run() {
  local name=$1; shift
  local walls=() cpus=() rays=()
  for r in $(seq "$reps"); do
    /usr/bin/time -f "%e %U %S" -o "$tmp/time" "$bin" "$@" --seed "$r" -o "$tmp/out.exr" --stats "$tmp/stats.json" >/dev/null 2>&1
    read -r wall user sys < "$tmp/time"
    walls+=("$wall")
    cpus+=("$(echo "$user + $sys" | bc -l)")
    rays+=("$(json "$tmp/stats.json" mrays_per_second)")
  done
  printf '%-44s wall %6.2f s  cpu %6.2f s  %6.2f Mrays/s\n' "$name" "$(median "${walls[@]}")" "$(median "${cpus[@]}")" "$(median "${rays[@]}")"
}

scene=../shared/scenes/pbrt-v4/cornell-box/volumetric-caustic.pbrt
echo "== PT, $spp spp, medians of $reps runs"
if [ -f "$scene" ]; then
  sed 's/Integrator "path"/Integrator "volpath"/' "$scene" > "$tmp/volpath.pbrt"
  run "volumetric caustic, fog (volpath)" "$tmp/volpath.pbrt" --tracer pt --width 256 --height 256 --spp "$spp"
  run "volumetric caustic, no fog (path)" "$scene" --tracer pt --width 256 --height 256 --spp "$spp"
else
  echo "(skipped: $scene is missing)"
fi

# a smoke blob: density exp(-r^2 / 0.08) from the cube's centre, times a smooth ripple
awk 'BEGIN { n = 32; printf "MakeNamedMedium \"smoke\" \"string type\" \"uniformgrid\" \"rgb sigma_a\" [ 0.5 0.5 0.5 ] \"rgb sigma_s\" [ 8 8 8 ] \"float g\" 0.4\n";
  printf "  \"integer nx\" %d \"integer ny\" %d \"integer nz\" %d \"point3 p0\" [ -1 0 -1 ] \"point3 p1\" [ 1 2 1 ] \"float density\" [", n, n, n;
  for (z = 0; z < n; ++z) for (y = 0; y < n; ++y) for (x = 0; x < n; ++x) {
    u = (x + 0.5) / n - 0.5; v = (y + 0.5) / n - 0.5; w = (z + 0.5) / n - 0.5; r2 = u * u + v * v + w * w;
    printf " %.4f", exp(-r2 / 0.08) * (0.75 + 0.25 * sin(20 * u) * sin(17 * v) * sin(13 * w)) }
  print " ]" }' > "$tmp/smoke.pbrt"
cat >> "$tmp/smoke.pbrt" <<'PBRT'
LookAt 0 1 -3.2  0 1 0  0 1 0
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" [ 128 ] "integer yresolution" [ 128 ]
Integrator "volpath" "integer maxdepth" [ 20 ]
WorldBegin
AttributeBegin
AreaLightSource "diffuse" "rgb L" [ 12 12 12 ]
Shape "trianglemesh" "point3 P" [ -0.3 1.99 -0.3  0.3 1.99 -0.3  0.3 1.99 0.3  -0.3 1.99 0.3 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.7 0.7 0.7 ]
Shape "trianglemesh" "point3 P" [ -1 0 -1  1 0 -1  1 0 1  -1 0 1  -1 2 -1  1 2 -1  1 2 1  -1 2 1 ]
  "integer indices" [ 0 1 2 0 2 3  4 6 5 4 7 6  3 2 6 3 6 7  0 3 7 0 7 4  1 5 6 1 6 2 ]
AttributeBegin
Material "interface"
MediumInterface "smoke" ""
Translate 0 1 0
Scale 0.6 0.6 0.6
Shape "sphere" "float radius" 1
AttributeEnd
PBRT
run "smoke blob (32^3 grid), 128 x 128" "$tmp/smoke.pbrt" --tracer pt --spp "$spp"
