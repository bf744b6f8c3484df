#!/usr/bin/env bash
# Error-versus-time plots from wavemmlt_bench_error's CSV.
#
#   bench/plot_error.sh bench-error.csv OUTDIR
#
# Writes OUTDIR/<scene>.png: two log-log panels, RMSE and relative MSE against the measured
# seconds, one line per tracer (and param value, when the CSV has a sweep), with the spread
# of the repetitions (least and greatest run) as bars when the CSV has it (--reps > 1).
# Needs gnuplot; installs Debian's gnuplot-nox with apt-get when it is missing (sudo when
# not root), and says so.
set -euo pipefail

if [ $# -ne 2 ]; then
    echo "usage: $0 CSV OUTDIR" >&2
    exit 2
fi
csv=$1
outdir=$2
[ -r "$csv" ] || { echo "$0: cannot read $csv" >&2; exit 2; }

if ! command -v gnuplot >/dev/null 2>&1; then
    echo "$0: gnuplot is missing; installing the Debian package gnuplot-nox with apt-get" >&2
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq >/dev/null
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends gnuplot-nox >/dev/null
fi

mkdir -p "$outdir"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# One data file per (scene, tracer, param): seconds rmse rmse_min rmse_max relmse relmse_min
# relmse_max, sorted by seconds (a CSV without the spread columns: the means as their own
# spread; without relmse: RMSE relative to the mean, squared, in its place).
# Columns: scene,tracer,param,budget_s,seconds,spp,rmse,rel_rmse[,rmse_min,rmse_max,relmse,relmse_min,relmse_max,...].
tail -n +2 "$csv" | awk -F, -v dir="$tmp" '
    NF >= 8 {
        key = $2 ($3 == "-" ? "" : " " $3)
        file = dir "/" $1 ".series"
        if (!((file, key) in seen)) { seen[file, key] = 1; print key >> (dir "/" $1 ".keys") }
        gsub(/[^A-Za-z0-9_.=-]/, "_", key)
        if (NF >= 13) print $5, $7, $9, $10, $11, $12, $13 >> (dir "/" $1 "@" key ".dat")
        else print $5, $7, $7, $7, $8 * $8, $8 * $8, $8 * $8 >> (dir "/" $1 "@" key ".dat")
    }'

shopt -s nullglob
scenes=()
for k in "$tmp"/*.keys; do scenes+=("$(basename "$k" .keys)"); done
if [ ${#scenes[@]} -eq 0 ]; then
    echo "$0: no rows in $csv" >&2
    exit 1
fi

for scene in "${scenes[@]}"; do
    rmse=(); rel=()
    while IFS= read -r key; do
        safe=$(printf '%s' "$key" | sed 's/[^A-Za-z0-9_.=-]/_/g')
        dat="$tmp/$scene@$safe.dat"
        sort -g -k1,1 "$dat" -o "$dat"
        rmse+=("'$dat' using 1:2:3:4 with yerrorlines lw 2 pt 7 title '$key'")
        rel+=("'$dat' using 1:5:6:7 with yerrorlines lw 2 pt 7 title '$key'")
    done < "$tmp/$scene.keys"
    out="$outdir/$scene.png"
    {
        echo "set terminal pngcairo size 1400,600 noenhanced font 'sans,11'"
        echo "set output '$out'"
        echo "set multiplot layout 1,2 title '$scene: error against render time (bars: least and greatest run)'"
        echo "set logscale xy"
        echo "set xlabel 'render time (s)'"
        echo "set grid xtics ytics mxtics mytics"
        echo "set key top right"
        echo "set ylabel 'RMSE'"
        printf 'plot '
        (IFS=,; echo "${rmse[*]}")
        echo "set ylabel 'relative MSE: mean (x - ref)^2 / (ref^2 + 0.01)'"
        printf 'plot '
        (IFS=,; echo "${rel[*]}")
        echo "unset multiplot"
    } > "$tmp/plot.gp"
    if ! gnuplot "$tmp/plot.gp" 2>"$tmp/err"; then
        # pngcairo is absent from some gnuplot builds: fall back to the gd png terminal.
        sed -i "1s/.*/set terminal png size 1400,600 noenhanced/" "$tmp/plot.gp"
        gnuplot "$tmp/plot.gp" || { cat "$tmp/err" >&2; exit 1; }
    fi
    echo "$out"
done
