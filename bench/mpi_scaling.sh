#!/usr/bin/env bash
# Strong scaling on one machine (docs/mpi.md): the same render (the same seed and work) as
#   1 process x 1 thread   (the baseline),
#   1 process x 2 threads  (what TBB gets from the second core),
#   mpirun -np 2 x 1 thread per rank (what MPI gets from it, over shared memory),
# for PT, BPT and MMLT. Prints per run the wall seconds (mpirun's start, the scene's load and
# build included), the render's seconds (--stats "seconds"), the speedup of the render over
# the baseline, and for the MPI runs the bytes exchanged (all ranks) and the largest seconds
# a rank spent in exchanges (waiting for the others included), in all and per boundary
# (per pass for PT and BPT, per round for MMLT). Medians of RUNS runs.
#   RUNS   runs per configuration (default 3)
#   SIZE   image size WxH (default 256x256)
#   SCENE  scene file (default the Cornell box test copy)
# Needs python3; runs mpirun as root when it has to (the environment below).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/wavemmlt
runs=${RUNS:-3}
size=${SIZE:-256x256}
scene=${SCENE:-tests/data/scenes/bitterli-cornell/bitterli-cornell-256.xml}
width=${size%x*}
height=${size#*x}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader \
       OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1

field() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get(sys.argv[2], 0))' "$1" "$2"; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

# one TRACER SPP MODE: a render; prints "wall render bytes mpi_seconds boundaries".
one() {
  local tracer=$1 spp=$2 mode=$3 stats="$work/stats.json"
  rm -f "$stats"
  local args=(--tracer "$tracer" --width "$width" --height "$height" --spp "$spp" --seed 1 -q
              -o "$work/out.pfm" --stats "$stats")
  local t0 t1
  t0=$(date +%s.%N)
  case $mode in
    1x1) nice -n 19 "$bin" "$scene" "${args[@]}" --threads 1 ;;
    1x2) nice -n 19 "$bin" "$scene" "${args[@]}" --threads 2 ;;
    2x1) nice -n 19 mpirun -q -np 2 "$bin" "$scene" "${args[@]}" --threads 1 ;;
  esac
  t1=$(date +%s.%N)
  echo "$(echo "$t1 - $t0" | bc) $(field "$stats" seconds) $(field "$stats" mpi_bytes) $(field "$stats" mpi_seconds_max) $(field "$stats" mpi_boundaries)"
}

printf '%-5s %-28s %8s %8s %8s %12s %9s %10s %12s %10s\n' tracer config wall_s render_s speedup mpi_bytes mpi_s boundaries bytes/bound ms/bound
for spec in pt:64 bpt:16 mmlt:64; do
  tracer=${spec%:*}
  spp=${spec#*:}
  base=""
  for mode in 1x1 1x2 2x1; do
    : > "$work/runs"
    for _ in $(seq "$runs"); do one "$tracer" "$spp" "$mode" >> "$work/runs"; done
    col() { awk -v c="$1" '{print $c}' "$work/runs" | median; }
    wall=$(col 1); rs=$(col 2); bytes=$(col 3); ms=$(col 4); nb=$(col 5)
    [ -z "$base" ] && base=$rs
    case $mode in
      1x1) name="1 process x 1 thread" ;;
      1x2) name="1 process x 2 threads" ;;
      2x1) name="mpirun -np 2 x 1 thread" ;;
    esac
    speedup=$(echo "scale=2; $base / $rs" | bc)
    if [ "$mode" = 2x1 ] && [ "$nb" != 0 ]; then
      perb=$(echo "scale=0; $bytes / $nb" | bc); permsb=$(echo "scale=3; 1000 * $ms / $nb" | bc)
    else
      perb=-; permsb=-
    fi
    printf '%-5s %-28s %8.2f %8.2f %8s %12s %9.3f %10s %12s %10s\n' "$tracer" "$name" "$wall" "$rs" "$speedup" "$bytes" "$ms" "$nb" "$perb" "$permsb"
  done
done
