#!/usr/bin/env bash
# Builds build/wavemmlt_bench_pbrt_blocks (not part of the default build) and runs it with
# these arguments: a pbrt-v4 file against pbrt-v4's render of it, block by block; with none,
# the caustic glass three ways (bench/bench_pbrt_blocks.cpp says how; docs/pbrt.md has the
# figures).
#
#   bench/pbrt_blocks.sh [FILE.pbrt REFERENCE.exr] [--tracer T] [--spp N] [--runs K] [--block B] [--coat ours|pbrt|pbrt-bdpt] [--rgb]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build -j"$(nproc)" --target wavemmlt_bench_pbrt_blocks >/dev/null
exec build/wavemmlt_bench_pbrt_blocks "$@"
