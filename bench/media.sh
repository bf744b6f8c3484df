#!/usr/bin/env bash
# Issue 27's media figures with build/wavemmlt, measured in this run (docs/media.md):
#   1. speed on the shared volumetric caustic (../shared/scenes/pbrt-v4/cornell-box/
#      volumetric-caustic.pbrt: a glass sphere in homogeneous fog under a light), 256 x 256:
#      PT, BPT (SPP samples per pixel) and MMLT (SPP mutations per pixel) with the fog (the
#      file's integrator made "volpath") and PT without it (the file as it is: pbrt's "path"
#      ignores media): wall and CPU seconds, rays per second (MMLT: mutations per second); medians of REPS runs;
#   2. a heterogeneous medium: a 32^3 grid of a smooth random density (a blob of smoke, sparse
#      at the edges) behind an interface sphere in a Cornell-like box written here, 128 x 128:
#      the same figures for PT, BPT and MMLT;
#   3. equal-time error on the volumetric caustic with its fog: PT, BPT and MMLT against a BPT
#      reference (build/wavemmlt_bench_error: RMSE at budgets of BUDGETS seconds, 2 seeds
#      each, 128 x 128; the reference of REFSPP samples per pixel is rendered once and cached
#      in build/bench-cache, about 4 minutes on 2 cores), then the equal-time ratios
#      RMSE(MMLT) / RMSE(PT) and RMSE(MMLT) / RMSE(BPT) per budget.
# Says so and skips parts 1 and 3 when the shared scene is missing.
#
#   bench/media.sh [--reps N] [--spp N] [--budgets 4,8,16] [--ref-spp 2048]
set -euo pipefail
cd "$(dirname "$0")/.."
reps=3
spp=16
budgets=4,8,16
refspp=2048
while [ $# -gt 0 ]; do
  case $1 in
    --reps) reps=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --budgets) budgets=$2; shift 2 ;;
    --ref-spp) refspp=$2; shift 2 ;;
    *) echo "media.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x /usr/bin/time ] || { echo "media.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
cmake --build build -j"$(nproc)" --target wavemmlt wavemmlt_bench_error >/dev/null
bin=build/wavemmlt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
json() { { grep -o "\"$2\": [0-9.e+-]*" "$1" || true; } | head -1 | awk "{print \$2}"; }

# run NAME ARGS...: REPS renders; prints the medians of wall s, CPU s, Mrays/s (MMLT: and
# mutations per second)
run() {
  local name=$1; shift
  local walls=() cpus=() rays=() muts=()
  for r in $(seq "$reps"); do
    /usr/bin/time -f "%e %U %S" -o "$tmp/time" "$bin" "$@" --seed "$r" -o "$tmp/out.exr" --stats "$tmp/stats.json" >/dev/null 2>&1
    read -r wall user sys < "$tmp/time"
    walls+=("$wall")
    cpus+=("$(echo "$user + $sys" | bc -l)")
    rays+=("$(json "$tmp/stats.json" mrays_per_second)")
    muts+=("$(json "$tmp/stats.json" mmlt_mutations_per_second)")
  done
  local extra=""
  [ -n "${muts[0]}" ] && extra=$(printf '  %6.3f M mutations/s' "$(echo "$(median "${muts[@]}") / 1000000" | bc -l)")
  printf '%-44s wall %6.2f s  cpu %6.2f s  %6.2f Mrays/s%s\n' "$name" "$(median "${walls[@]}")" "$(median "${cpus[@]}")" "$(median "${rays[@]}")" "$extra"
}

scene=../shared/scenes/pbrt-v4/cornell-box/volumetric-caustic.pbrt
echo "== 1. volumetric caustic, 256 x 256, $spp samples (MMLT: mutations) per pixel, medians of $reps runs"
if [ -f "$scene" ]; then
  sed 's/Integrator "path"/Integrator "volpath"/' "$scene" > "$tmp/volpath.pbrt"
  for t in pt bpt mmlt; do
    run "$t, fog (volpath)" "$tmp/volpath.pbrt" --tracer $t --width 256 --height 256 --spp "$spp"
  done
  run "pt, no fog (path)" "$scene" --tracer pt --width 256 --height 256 --spp "$spp"
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
echo "== 2. smoke blob (32^3 grid), 128 x 128, $spp samples (MMLT: mutations) per pixel, medians of $reps runs"
for t in pt bpt mmlt; do
  run "$t, smoke blob" "$tmp/smoke.pbrt" --tracer $t --spp "$spp"
done

echo "== 3. equal-time error, volumetric caustic with its fog, 128 x 128"
if [ -f "$scene" ]; then
  build/wavemmlt_bench_error "$tmp/volpath.pbrt" --tracers pt,bpt,mmlt --budgets "$budgets" --size 128x128 \
    --reps 2 --ref-spp "$refspp" --cache build/bench-cache --csv "$tmp/error.csv" | grep -v "^equal-time\|^  -\|^wrote"
  echo "equal-time ratios (RMSE, root of the mean squared error over the 2 seeds):"
  awk -F, 'NR > 1 { r[$2 "," $4] = $7; b[$4] = 1 }
    END { for (x in b) printf "  %4ss: MMLT / PT %.3f   MMLT / BPT %.3f   BPT / PT %.3f\n", x,
          r["mmlt," x] / r["pt," x], r["mmlt," x] / r["bpt," x], r["bpt," x] / r["pt," x] }' "$tmp/error.csv" | sort -n
else
  echo "(skipped: $scene is missing)"
fi
