#!/usr/bin/env bash
# Error-versus-time plots from wavemmlt_bench_error's CSV.
#
#   bench/plot_error.sh bench-error.csv OUTDIR
#
# Writes OUTDIR/<scene>-rmse.png and OUTDIR/<scene>-relrmse.png: log-log, RMSE (relative RMSE)
# against the measured seconds, one line per tracer (and param value, when the CSV has
# a sweep). Needs gnuplot; installs Debian's gnuplot-nox with apt-get when it is missing
# (sudo when not root), and says so.
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

# One data file per (scene, tracer, param): columns seconds rmse rel_rmse, sorted by seconds.
# Columns: scene,tracer,param,budget_s,seconds,spp,rmse,rel_rmse.
tail -n +2 "$csv" | awk -F, -v dir="$tmp" '
    NF >= 8 {
        key = $2 ($3 == "-" ? "" : " " $3)
        file = dir "/" $1 ".series"
        if (!((file, key) in seen)) { seen[file, key] = 1; print key >> (dir "/" $1 ".keys") }
        gsub(/[^A-Za-z0-9_.=-]/, "_", key)
        print $5, $7, $8 >> (dir "/" $1 "@" key ".dat")
    }'

shopt -s nullglob
scenes=()
for k in "$tmp"/*.keys; do scenes+=("$(basename "$k" .keys)"); done
if [ ${#scenes[@]} -eq 0 ]; then
    echo "$0: no rows in $csv" >&2
    exit 1
fi

for scene in "${scenes[@]}"; do
    for metric in rmse relrmse; do
        col=2; ylabel="RMSE"
        [ "$metric" = relrmse ] && { col=3; ylabel="relative RMSE (RMSE / mean of the reference)"; }
        plots=()
        while IFS= read -r key; do
            safe=$(printf '%s' "$key" | sed 's/[^A-Za-z0-9_.=-]/_/g')
            dat="$tmp/$scene@$safe.dat"
            sort -g -k1,1 "$dat" -o "$dat"
            plots+=("'$dat' using 1:$col with linespoints lw 2 pt 7 title '$key'")
        done < "$tmp/$scene.keys"
        out="$outdir/$scene-$metric.png"
        {
            echo "set terminal pngcairo size 900,650 noenhanced font 'sans,11'"
            echo "set output '$out'"
            echo "set title '$scene: error against time'"
            echo "set logscale xy"
            echo "set xlabel 'render time (s)'"
            echo "set ylabel '$ylabel'"
            echo "set grid xtics ytics mxtics mytics"
            echo "set key top right"
            printf 'plot '
            (IFS=,; echo "${plots[*]}")
        } > "$tmp/plot.gp"
        if ! gnuplot "$tmp/plot.gp" 2>"$tmp/err"; then
            # pngcairo is absent from some gnuplot builds: fall back to the gd png terminal.
            sed -i "1s/.*/set terminal png size 900,650 noenhanced/" "$tmp/plot.gp"
            gnuplot "$tmp/plot.gp" || { cat "$tmp/err" >&2; exit 1; }
        fi
        echo "$out"
    done
done
