#!/usr/bin/env bash
# The estimator suite of issue 44: MMLT's equal-time relative MSE on five scenes, the previous
# revision's binary (OLD) against this build (NEW) and against NEW with each of its levers
# flipped from its default, all in one run. Each scene is rendered at two time budgets with
# 3 seeds per variant by wavemmlt_bench_error (MMLT, its own defaults and the scene's
# settings), and every run's relMSE (mean over pixels and channels of (x - ref)^2 /
# (ref^2 + 0.01)) is taken against one cached reference per scene. The runs are interleaved
# per (scene, budget, seed), the variants' order rotating with the seed, so that every
# variant sees the same machine load; one uncounted 1 s run of each binary per scene first.
#
#   bench/estimator.sh [--old REV] [--budgets 2,6] [--seeds N] [--scenes a,b,...]
#                      [--levers a,b,...] [--quick] [--out DIR]
#
#   --old REV      the revision OLD is built from (bench/old_build.sh, in build-bench-old/)
#                  [6ee952b]; it runs with its defaults and is never given a lever's option
#   --budgets B,B  seconds per run, for every scene [each scene's own, below: 2,6]
#   --seeds N      seeds 1..N per (scene, budget, variant) [3]
#   --scenes LIST  a subset by name: seed-room, cornell, veach-bidir, caustic, veach-ajar [all]
#   --levers LIST  a subset of the levers below by label (mmlt-film-steps=off, ...), or
#                  "none" for OLD against NEW alone [all]
#   --quick        a smoke run: the first budget and one seed
#   --out DIR      where the outputs go [build/bench-estimator]
#
# The scenes are read from ../shared/scenes beside the checkout (when it is missing the script
# says so and exits 0): the seed room (the thesis' kind of door room, lit only indirectly, from
# above a drop ceiling), Bitterli's Cornell box, veach-bidir (the thesis-format file), the
# volumetric caustic of pbrt-v4's Cornell box (its integrator made "volpath" in a copy written
# to OUT/scenes/, as bench/media.sh does: with the file's "path" the fog is not rendered), and
# pbrt's Veach Ajar; sizes and budgets in the table below. A reference per scene is rendered
# once by this build's wavemmlt_bench_error (BPT at kRefSpp's spp, bench/bench_error.cpp) and
# cached in build/bench-cache, shared with the other bench scripts; its own noise (relMSE of
# the mean of two halves) is printed, and the script warns when it is not at least 10 times
# below NEW's relMSE at the largest budget (a run's relMSE includes the reference's noise).
#
# Prints per scene and budget each variant's mean relMSE over the seeds, its spread (least and
# greatest run) and its ratio to OLD's mean; "WORSE" marks a variant whose least run is above
# OLD's greatest (worse by more than the seeds' spread), "better" one whose greatest run is
# below OLD's least; then the per-seed ratios to OLD's run of the same seed (geometric mean,
# least..greatest) and the mean spp (mutations per pixel in the budget). Writes OUT/runs.csv
# (one row per run), OUT/summary.csv (the printed table), OUT/table.md (the table for
# docs/benchmarks.md), OUT/ratios.png (relMSE / OLD's per scene and variant; only when gnuplot
# is installed) and OUT/logs/ (every run's output). A run that fails, that reports no result or
# a non-finite one, or that renders a reference of its own instead of reading the cached one
# stops the script with its log (exit 1). It takes about 10 minutes on 2 cores with the
# references cached (the first time: plus the references, 4 to 10 minutes each on a quiet
# machine). Not part of the tests.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

# name|file under ../shared/scenes|WxH|MaxPathLength (-: the scene's)|budgets in s (-: 2,6)
sceneTable=(
  "seed-room|seed-room/seed-room.xml|128x128|-|-"
  "cornell|bitterli-cornell/bitterli-cornell-256.xml|128x128|-|-"
  "veach-bidir|veach-bidir/veach-bidir-256.xml|128x128|-|-"
  "caustic|pbrt-v4/cornell-box/volumetric-caustic.pbrt|128x128|-|-"
  "veach-ajar|pbrt-v4/veach-ajar/veach-ajar.pbrt|160x90|-|-"
)
defaultBudgets=2,6
# NEW's levers (issue 44): each is run once with its value flipped from NEW's default, as
# "label|wavemmlt_bench_error options". A new lever is one more entry; when a lever becomes
# NEW's default, its entry flips to the other value. OLD never gets these options.
levers=(
  "mmlt-target=relative|--mmlt-target relative"
  "mmlt-steps=learned|--mmlt-steps learned"
  "mmlt-delayed-rejection=on|--mmlt-delayed-rejection on"
  "mmlt-target-exponent=0.5|--mmlt-target-exponent 0.5"
  "mmlt-film-steps=off|--mmlt-film-steps off"
  "mis-beta=2|--mis-beta 2"
)

old=6ee952b budgets="" seeds=3 only="" onlyLevers="" quick=0 out=build/bench-estimator
while [ $# -gt 0 ]; do
  case $1 in
    --old) old=$2; shift 2 ;; --budgets) budgets=$2; shift 2 ;; --seeds) seeds=$2; shift 2 ;;
    --scenes) only=$2; shift 2 ;; --levers) onlyLevers=$2; shift 2 ;; --quick) quick=1; shift ;;
    --out) out=$2; shift 2 ;;
    *) echo "estimator.sh: unknown option $1 (see the comment at the top of bench/estimator.sh)" >&2; exit 2 ;;
  esac
done
[[ $seeds =~ ^[1-9][0-9]*$ ]] || { echo "estimator.sh: --seeds wants a positive count" >&2; exit 2; }
[ $quick = 1 ] && seeds=1
shared=../shared/scenes
if [ ! -d "$shared" ]; then
  echo "estimator.sh: $shared is missing (the shared scenes folder beside the checkout): nothing to measure"
  exit 0
fi

# the scenes to run: name, file, size, max-length, budgets
names=() files=() sizes=() lengths=() sceneBudgets=()
known=" "
for row in "${sceneTable[@]}"; do
  IFS='|' read -r name file size len b <<< "$row"
  known+="$name "
  if [ -n "$only" ] && [[ ",$only," != *",$name,"* ]]; then continue; fi
  if [ ! -f "$shared/$file" ]; then echo "estimator.sh: $shared/$file is missing; $name skipped"; continue; fi
  [ "$b" = - ] && b=$defaultBudgets
  [ -n "$budgets" ] && b=$budgets
  [ $quick = 1 ] && b=${b%%,*}
  names+=("$name") files+=("$shared/$file") sizes+=("$size") lengths+=("$len") sceneBudgets+=("$b")
done
for n in ${only//,/ }; do
  [[ $known == *" $n "* ]] || { echo "estimator.sh: unknown scene '$n' (one of:$known)" >&2; exit 2; }
done
[ ${#names[@]} -gt 0 ] || { echo "estimator.sh: no scene to run"; exit 0; }

# the variants: label|binary (old, new)|options
variants=("old|old|" "new|new|")
knownLevers=" "
for l in "${levers[@]}"; do
  knownLevers+="${l%%|*} "
  if [ -n "$onlyLevers" ] && [[ ",$onlyLevers," != *",${l%%|*},"* ]]; then continue; fi
  variants+=("new:${l%%|*}|new|${l#*|}")
done
for n in ${onlyLevers//,/ }; do
  [ "$n" = none ] || [[ $knownLevers == *" $n "* ]] || { echo "estimator.sh: unknown lever '$n' (one of:$knownLevers)" >&2; exit 2; }
done

[ -f build/CMakeCache.txt ] || { echo "estimator.sh: build/ is not configured: run scripts/setup.sh first" >&2; exit 2; }
cmake --build build -j"$(nproc)" --target wavemmlt_bench_error >/dev/null
newBin=build/wavemmlt_bench_error
. bench/old_build.sh
echo "building OLD ($old) in build-bench-old/ ..."
buildOld "$old" wavemmlt_bench_error
oldBin=$oldBuild/wavemmlt_bench_error
cache=build/bench-cache  # shared with wavemmlt_bench_error's default and the other bench scripts
mkdir -p "$out/logs" "$out/scenes" "$cache"
rm -f "$out"/logs/*.log

# the volumetric caustic with its fog: the file's "path" integrator made "volpath"
for i in "${!names[@]}"; do
  if [ "${names[$i]}" = caustic ]; then
    fog=$out/scenes/volumetric-caustic-volpath.pbrt
    sed 's/^Integrator "path"/Integrator "volpath"/' "${files[$i]}" > "$fog"
    grep -q '^Integrator "volpath"' "$fog" || { echo "estimator.sh: ${files[$i]} has no Integrator \"path\" line to make volpath" >&2; exit 1; }
    files[$i]=$fog
  fi
done

sceneArgs() {  # index -> the options every run of that scene gets
  local a=(--size "${sizes[$1]}" --cache "$cache")
  [ "${lengths[$1]}" != - ] && a+=(--max-length "${lengths[$1]}")
  echo "${a[@]}"
}

nRuns=0 planned=0
for i in "${!names[@]}"; do
  for b in ${sceneBudgets[$i]//,/ }; do
    nRuns=$((nRuns + seeds * ${#variants[@]}))
    planned=$(awk -v p=$planned -v b=$b -v n=$((seeds * ${#variants[@]})) 'BEGIN { print p + n * (b + 1) }')
  done
done
echo "== estimator suite: ${#names[@]} scene(s), $nRuns runs (${#variants[@]} variants x $seeds seed(s) x budgets), about $planned s"
echo "   OLD = $old, NEW = $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src include bench/bench_error.cpp || echo ' with uncommitted changes'); $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)"

# references: made (or read) by NEW, then read by every run; their spp is passed to both
# binaries (OLD's kRefSpp may not know these scenes)
refSpp=() refNoise=() refLine=()
echo "references (BPT; one not yet in $cache is rendered now by NEW, 4 to 10 minutes on a quiet machine):"
for i in "${!names[@]}"; do
  log=$out/logs/${names[$i]}-reference.log
  # shellcheck disable=SC2046
  if ! $newBin "${files[$i]}" --ref-only $(sceneArgs "$i") > "$log" 2>&1; then
    echo "estimator.sh: the reference of ${names[$i]} failed:" >&2; cat "$log" >&2; exit 1
  fi
  line=$(grep '^reference: .*spp, ' "$log" | tail -1)
  [ -n "$line" ] || { echo "estimator.sh: no reference line in $log" >&2; cat "$log" >&2; exit 1; }
  refSpp[$i]=$(sed -E 's/.*, ([0-9]+) spp, .*/\1/' <<< "$line")
  refNoise[$i]=$(sed -E 's/.*, relMSE ([^ ]+)$/\1/' <<< "$line")
  refLine[$i]=${line#reference: }
  lengths[$i]=$(sed -nE 's/^== .*MaxPathLength (\(the scene.s\) )?([0-9]+).*/\2/p' "$log")  # the length run, as a number
  [ -n "${lengths[$i]}" ] || { echo "estimator.sh: no MaxPathLength in $log" >&2; exit 1; }
  echo "reference ${names[$i]}: ${refLine[$i]}"
done

# runOne SCENE-INDEX BUDGET SEED VARIANT LOG: one MMLT run of wavemmlt_bench_error; sets row to its
# CSV row, or stops the script with the run's log when it failed, read no cached reference or
# gave no finite relMSE
runOne() {
  local i=$1 b=$2 seed=$3 label which args bin status=0 csv=$out/logs/run.csv rows relmse
  IFS='|' read -r label which args <<< "$4"
  bin=$newBin; [ "$which" = old ] && bin=$oldBin
  rm -f "$csv"
  # shellcheck disable=SC2046,SC2086  # the scene's options and the lever's, split into words
  "$bin" "${files[$i]}" --tracers mmlt --budgets "$b" --seed "$seed" --reps 1 $(sceneArgs "$i") \
    --ref-spp "${refSpp[$i]}" --csv "$csv" $args > "$5" 2>&1 || status=$?
  if [ $status != 0 ]; then
    echo "estimator.sh: FAILED: ${names[$i]} ${b}s seed $seed $label (exit status $status); its log, $5:" >&2
    cat "$5" >&2; exit 1
  fi
  if ! grep -q '^reference: .*, cached, ' "$5"; then
    echo "estimator.sh: FAILED: ${names[$i]} ${b}s seed $seed $label did not read the cached reference; $5:" >&2
    cat "$5" >&2; exit 1
  fi
  rows=$(tail -n +2 "$csv" 2>/dev/null | wc -l)
  row=$(tail -n +2 "$csv" 2>/dev/null | head -1)
  relmse=$(cut -d, -f11 <<< "$row")
  if [ "$rows" != 1 ] || ! awk -v x="$relmse" 'BEGIN { exit !(x ~ /^[0-9.eE+-]+$/ && x + 0 >= 0) }'; then
    echo "estimator.sh: FAILED: ${names[$i]} ${b}s seed $seed $label gave no finite relMSE ($rows row(s): $row); $5:" >&2
    cat "$5" >&2; exit 1
  fi
  rm -f "$csv"
}

# a warm-up run of each binary per scene, 1 s, not counted: in a trial the first run of a
# scene was 10-20% slower than the next ones
for i in "${!names[@]}"; do
  for v in "${variants[@]:0:2}"; do
    runOne "$i" 1 1000 "$v" "$out/logs/${names[$i]}-warmup-${v%%|*}.log"
  done
done
echo "  warm-up runs done ($((SECONDS - start)) s)"

runs=$out/runs.csv
echo "scene,budget_s,seed,variant,seconds,spp,rmse,relmse,samples_per_s,accept_small,accept_large" > "$runs"
done=0
for i in "${!names[@]}"; do
  for b in ${sceneBudgets[$i]//,/ }; do
    for ((seed = 1; seed <= seeds; ++seed)); do
      nv=${#variants[@]}
      for ((k = 0; k < nv; ++k)); do
        v=${variants[$(((k + seed - 1) % nv))]}
        label=${v%%|*}
        runOne "$i" "$b" "$seed" "$v" "$out/logs/${names[$i]}-${b}s-seed$seed-${label//[:=]/_}.log"
        IFS=, read -r _ _ _ _ secs spp rmse _ _ _ rel _ _ sps accS accL <<< "$row"
        echo "${names[$i]},$b,$seed,$label,$secs,$spp,$rmse,$rel,$sps,$accS,$accL" >> "$runs"
        done=$((done + 1))
        printf '  %3d/%d %-12s %4ss seed %-2d %-28s relMSE %-10.4g %6.2f s, %s spp  (%d s)\n' "$done" "$nRuns" "${names[$i]}" "$b" \
          "$seed" "$label" "$rel" "$secs" "${spp%.*}" $((SECONDS - start))
      done
    done
  done
done

# per (scene, budget, variant): mean, least and greatest relMSE; the ratio of the mean to
# OLD's; WORSE when the least run is above OLD's greatest, better when the greatest is below
# OLD's least; the per-seed ratios to OLD's run of the same seed (their geometric mean, least
# and greatest: the seed decides much of a run's error, so these are steadier) and the mean
# spp (mutations per pixel done in the budget: the machine's load shows there)
summary=$out/summary.csv
awk -F, 'NR > 1 { seen[$1 SUBSEP $2 SUBSEP $3 SUBSEP $4] = $8 }
  NR > 1 {
    k = $1 SUBSEP $2 SUBSEP $4
    if (!(k in n)) { order[++m] = k; mn[k] = $8; mx[k] = $8 }
    n[k]++; s[k] += $8; spp[k] += $6
    if ($8 < mn[k]) mn[k] = $8
    if ($8 > mx[k]) mx[k] = $8
    run[k, n[k]] = $3
  }
  END {
    print "scene,budget_s,variant,runs,relmse_mean,relmse_min,relmse_max,ratio_to_old,mark,seed_ratio_geomean,seed_ratio_min,seed_ratio_max,spp_mean"
    for (j = 1; j <= m; ++j) {
      k = order[j]; split(k, f, SUBSEP); o = f[1] SUBSEP f[2] SUBSEP "old"
      mean = s[k] / n[k]; om = s[o] / n[o]
      mark = ""  # (not with one seed: no spread)
      if (f[3] != "old" && n[k] > 1 && n[o] > 1 && mn[k] > mx[o]) mark = "WORSE"
      if (f[3] != "old" && n[k] > 1 && n[o] > 1 && mx[k] < mn[o]) mark = "better"
      lg = 0; c = 0; rmin = 1e300; rmax = 0
      for (r = 1; r <= n[k]; ++r) {
        seed = run[k, r]; x = seen[f[1] SUBSEP f[2] SUBSEP seed SUBSEP f[3]]; y = seen[f[1] SUBSEP f[2] SUBSEP seed SUBSEP "old"]
        if (x > 0 && y > 0) { q = x / y; lg += log(q); ++c; if (q < rmin) rmin = q; if (q > rmax) rmax = q }
      }
      printf "%s,%s,%s,%d,%.6g,%.6g,%.6g,%.4f,%s,%.4f,%.4f,%.4f,%.1f\n", f[1], f[2], f[3], n[k], mean, mn[k], mx[k],
             (om > 0 ? mean / om : 0), mark, (c ? exp(lg / c) : 0), (c ? rmin : 0), (c ? rmax : 0), spp[k] / n[k]
    }
  }' "$runs" > "$summary"
# ... in the order of the table: scene, budget, then the variants as listed
sorted=$out/logs/sorted.csv
head -1 "$summary" > "$sorted"
for i in "${!names[@]}"; do
  for b in ${sceneBudgets[$i]//,/ }; do
    for v in "${variants[@]}"; do
      awk -F, -v s="${names[$i]}" -v b="$b" -v l="${v%%|*}" '$1 == s && $2 == b && $3 == l' "$summary" >> "$sorted"
    done
  done
done
mv "$sorted" "$summary"

newRev=$(git rev-parse --short HEAD)
for i in "${!names[@]}"; do
  echo
  echo "== ${names[$i]}: ${sizes[$i]}, MaxPathLength ${lengths[$i]}, MMLT, $seeds seed(s); relMSE against the reference:"
  echo "   ${refLine[$i]}"
  for b in ${sceneBudgets[$i]//,/ }; do
    printf '  %5ss  %-28s %11s  %-24s %6s %-6s  %-22s %8s\n' "$b" "variant" "relMSE" "(seeds: least..greatest)" "/ OLD" "" \
      "per seed / OLD" "mean spp"
    awk -F, -v s="${names[$i]}" -v b="$b" -v old="$old" -v new="$newRev" '$1 == s && $2 == b {
        label = $3 == "old" ? "OLD " old : $3 == "new" ? "NEW " new : "NEW " substr($3, 5)
        paired = $3 == "old" ? "" : sprintf("%.3f (%.3f..%.3f)", $10, $11, $12)
        printf "         %-28s %11.4g  %-24s %6.3f %-6s  %-22s %8.0f\n", label, $5, sprintf("(%.4g..%.4g)", $6, $7), $8, $9, paired, $13
      }' "$summary"
  done
  # the reference's noise against NEW's relMSE at the largest budget
  last=${sceneBudgets[$i]##*,}
  newMean=$(awk -F, -v s="${names[$i]}" -v b="$last" '$1 == s && $2 == b && $3 == "new" { print $5 }' "$summary")
  awk -v r="${refNoise[$i]}" -v n="$newMean" -v b="$last" 'BEGIN {
      if (r !~ /^[0-9.eE+-]+$/) { print "  the reference'"'"'s own relMSE is not recorded (cached by an older bench_error): delete it to re-render"; exit }
      f = r > 0 ? n / r : 1e9
      printf "  the reference'"'"'s own relMSE %.3g is 1/%.0f of NEW'"'"'s at %ss%s\n", r, f, b,
             f < 10 ? "  ** WARNING: less than 10x: the reference is too noisy for this comparison **" : ""
    }'
done

# the table for docs/benchmarks.md
md=$out/table.md
{
  echo "relMSE (mean over $seeds seed(s); least..greatest) and the ratio to OLD's mean, MMLT at equal time;"
  echo "OLD = $old, NEW = $newRev, $(nproc) cores, $(date -u +%Y-%m-%d). **WORSE**: the least run above OLD's greatest."
  echo
  header="| scene | budget |" rule="|---|---|"
  for v in "${variants[@]}"; do
    l=${v%%|*}
    case $l in old) l="OLD ($old)" ;; new) l="NEW ($newRev)" ;; *) l="NEW ${l#new:}" ;; esac
    header+=" $l |" rule+="---|"
  done
  echo "$header"; echo "$rule"
  for i in "${!names[@]}"; do
    for b in ${sceneBudgets[$i]//,/ }; do
      awk -F, -v s="${names[$i]}" -v b="$b" -v size="${sizes[$i]}, MaxPathLength ${lengths[$i]}" '$1 == s && $2 == b {
          cell = $4 > 1 ? sprintf("%.4g (%.4g..%.4g)", $5, $6, $7) : sprintf("%.4g", $5)
          if ($3 != "old") cell = cell sprintf(", x%.2f", $8)
          if ($9 == "WORSE") cell = cell " **WORSE**"
          if ($9 == "better") cell = cell " better"
          row = row " " cell " |"
        }
        END { printf "| %s %s | %s s |%s\n", s, size, b, row }' "$summary"
    done
  done
  echo
  echo "References (own noise as relMSE):"
  for i in "${!names[@]}"; do echo "- ${names[$i]}: ${refLine[$i]}"; done
} > "$md"

# the plot: relMSE / OLD's mean per (scene, budget) and variant, bars from the least to the
# greatest run
if command -v gnuplot >/dev/null 2>&1; then
  gp=$out/logs/ratios.gp
  tics="" nclusters=0
  for i in "${!names[@]}"; do
    for b in ${sceneBudgets[$i]//,/ }; do
      tics+="${tics:+, }'${names[$i]} ${b}s' $nclusters"
      nclusters=$((nclusters + 1))
    done
  done
  plots="" j=0 nv=${#variants[@]}
  for v in "${variants[@]}"; do
    l=${v%%|*}
    dat=$out/logs/ratios-${l//[:=]/_}.dat
    c=0
    : > "$dat"
    for i in "${!names[@]}"; do
      for b in ${sceneBudgets[$i]//,/ }; do
        awk -F, -v s="${names[$i]}" -v b="$b" -v l="$l" -v x="$(awk -v c=$c -v j=$j -v n=$nv 'BEGIN { print c + (j - (n - 1) / 2) * 0.8 / n }')" '
            $1 == s && $2 == b && $3 == "old" { om = $5 }
            $1 == s && $2 == b && $3 == l { m = $5; lo = $6; hi = $7 }
            END { if (om > 0) print x, m / om, lo / om, hi / om }' "$summary" >> "$dat"
        c=$((c + 1))
      done
    done
    case $l in old) t="OLD $old" ;; new) t="NEW $newRev" ;; *) t="NEW ${l#new:}" ;; esac
    plots+="${plots:+, }'$dat' using 1:2:3:4 with yerrorbars lw 2 pt 7 ps 1.2 title '$t'"
    j=$((j + 1))
  done
  {
    echo "set terminal pngcairo size 1400,600 noenhanced font 'sans,11'"
    echo "set output '$out/ratios.png'"
    echo "set title 'MMLT at equal time: relMSE / OLD ($old) mean relMSE ($seeds seed(s); bars: least and greatest run)'"
    echo "set logscale y"
    echo "set ylabel 'relMSE / OLD mean (below 1: better than OLD)'"
    echo "set xtics ($tics) rotate by 30 right"
    echo "set xrange [-0.6:$nclusters - 0.4]"
    echo "set grid ytics mytics"
    echo "set key outside right top"
    echo "plot $plots, 1 with lines lc rgb 'black' dt 2 notitle"
  } > "$gp"
  if ! gnuplot "$gp" 2> "$out/logs/gnuplot.err"; then
    sed -i "1s/.*/set terminal png size 1400,600 noenhanced/" "$gp"  # pngcairo is absent from some builds
    gnuplot "$gp" || { cat "$out/logs/gnuplot.err" >&2; exit 1; }
  fi
  plotted="$out/ratios.png"
else
  plotted="no plot (gnuplot is not installed: apt-get install gnuplot-nox)"
fi

echo
echo "wrote $runs, $summary, $md, $plotted; logs in $out/logs"
echo "took $((SECONDS - start)) s; load average $(cut -d' ' -f1-3 /proc/loadavg)"
