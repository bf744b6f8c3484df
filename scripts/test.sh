#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (ctest, 2 jobs) three ways:
#   1. the Release build in build/ (scripts/setup.sh);
#   2. the same suite built with AddressSanitizer and UndefinedBehaviorSanitizer (gcc, -O1 -g1)
#      in build-asan/, where any sanitizer report fails the test that caused it, without the
#      statistical renders tagged [stat] (K = 16-32 renders per side, 5-10 times slower under
#      the sanitizers; the same code runs in the other tests at smaller sizes) and the wall-time
#      bound of --time tagged [walltime] (under the sanitizers a process's exit scans its memory
#      for leaks: that measures the sanitizer, not the renderer), and without the Python module
#      (a sanitized module loads into an unsanitized python3 only with libasan preloaded; the
#      code it calls is the suite's, and its own tests run in the Release pass); test files
#      whose every test is [stat] or [walltime] are not even compiled there;
#   3. scripts/fuzz.sh: the libFuzzer targets (fuzz/) for about a minute in all.
# Every part runs even if an earlier one failed; the exit status is non-zero if any failed.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
failed=()
times=()
part() {  # part NAME COMMAND...: runs it, records its time and whether it failed
  local name=$1 start=$SECONDS
  shift
  echo "== test.sh: $name" >&2
  if "$@"; then times+=("$name: $((SECONDS - start)) s"); else failed+=("$name"); times+=("$name: $((SECONDS - start)) s, FAILED"); fi
}

release() {
  # (set -e is off inside a function called as an if-condition: chain with &&)
  scripts/setup.sh &&
  ctest --test-dir "${BUILD_DIR:-build}" -j"$jobs" --output-on-failure --timeout 900
}

sanitizers() {
  local dir=build-asan flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
  # The release build's RGB-to-spectrum table, not fitted again (the same sources: 18 s).
  local table="$PWD/${BUILD_DIR:-build}/rgb_sigmoid_srgb.bin"
  [ -f "$table" ] || table=""
  # -O1 -g1 (line tables: enough for the sanitizers' stack traces) builds in about half the
  # time of -O2 -g, and ASan recommends -O1.
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG -DWMLT_DCHECKS" \
        -DWAVEMMLT_RGB_SIGMOID_TABLE="$table" \
        -DWAVEMMLT_BENCH=OFF -DWAVEMMLT_PYTHON=OFF -DWAVEMMLT_UNITY=ON -DWAVEMMLT_TEST_SPEC="~[stat]~[walltime]" -DWAVEMMLT_TEST_SKIP_TAGS="stat;walltime" \
        -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null &&
  cmake --build "$dir" -j"$jobs" &&
  ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_leaks=1:print_stacktrace=1 \
  UBSAN_OPTIONS=halt_on_error=1:abort_on_error=1:print_stacktrace=1 \
    ctest --test-dir "$dir" -j"$jobs" --output-on-failure --timeout 900
}

part "release build + tests" release
part "ASan/UBSan build + tests (build-asan)" sanitizers
part "fuzzing (scripts/fuzz.sh)" scripts/fuzz.sh

printf 'test.sh: %s\n' "${times[@]}" >&2
if [ ${#failed[@]} -gt 0 ]; then
  echo "test.sh: FAILED: ${failed[*]}" >&2
  exit 1
fi
