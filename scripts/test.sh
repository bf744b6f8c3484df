#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (ctest, 2 jobs).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
ctest --test-dir "${BUILD_DIR:-build}" -j"$(nproc)" --output-on-failure --timeout 900
