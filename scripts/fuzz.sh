#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang++, -fsanitize=fuzzer,address,undefined) in
# build-fuzz/ and runs each for a bounded time on a copy of its seed corpus
# (tests/fuzz/corpus/<target>/ plus the saved regressions tests/fuzz/regressions/<target>/).
# Prints the inputs each target ran; exits non-zero on any finding (crash, sanitizer report,
# uncaught exception other than wmlt::InputError, timeout, out-of-memory) and keeps the input
# in build-fuzz/findings/<target>/ (copy it to tests/fuzz/regressions/<target>/ once fixed).
#   FUZZ_SECONDS   fuzzing time per target (default 8; 12 targets: about a minute and a half in all)
#   FUZZ_TARGETS   the targets to run (default: scene pbrt pbrtgz obj ply serialized png jpeg tga exr hdr pfm)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${FUZZ_SECONDS:-8}
targets=(${FUZZ_TARGETS:-scene pbrt pbrtgz obj ply serialized png jpeg tga exr hdr pfm})
out=build-fuzz

if ! command -v clang++ >/dev/null; then
  echo "fuzz: clang++ is missing (scripts/setup.sh installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi
if [ ! -f "$out/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S fuzz -B "$out" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build "$out" -j"$(nproc)" >/dev/null

# Any sanitizer report is fatal; leaks too (LeakSanitizer runs at exit of each process).
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:abort_on_error=1:detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:abort_on_error=1:print_stacktrace=1}

status=0
total=0
summary=()
for t in "${targets[@]}"; do
  work="$out/corpus/$t"
  findings="$out/findings/$t"
  rm -rf "$work"
  mkdir -p "$work" "$findings"
  cp tests/fuzz/corpus/"$t"/* "$work"/
  [ -d tests/fuzz/regressions/"$t" ] && cp tests/fuzz/regressions/"$t"/* "$work"/ 2>/dev/null || true
  rm -f "$work"/README* 
  log="$out/fuzz-$t.log"
  dict=()
  [ -f tests/fuzz/dict/"$t".dict ] && dict=(-dict=tests/fuzz/dict/"$t".dict)
  set +e
  # -max_len: a 64 KiB input reaches every bound the loaders set (nesting: 100 levels of
  # a 22-byte element, 2.2 KiB; the dictionaries' tokens help mutations get there).
  "$out/fuzz_$t" "$work" "${dict[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=4096 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^Done \([0-9]*\) runs.*/\1/p' "$log" | tail -1)
  [ -n "$runs" ] || runs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\)/\1/p' "$log" | tail -1)
  runs=${runs:-0}
  total=$((total + runs))
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -1 || true)
  if [ "$rc" -ne 0 ]; then
    status=1
    summary+=("fuzz_$t: FINDING after $runs runs (exit $rc); input(s): $(ls "$findings" | tr '\n' ' ')")
    echo "---- fuzz_$t: finding; the end of $log:" >&2
    grep -vE '^#[0-9]+' "$log" | tail -40 >&2
  else
    summary+=("fuzz_$t: $runs runs in ${seconds} s, ${cov:-cov: ?}, no findings")
  fi
done
printf '%s\n' "${summary[@]}"
echo "fuzz: $total inputs run in all"
exit $status
