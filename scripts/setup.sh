#!/usr/bin/env bash
# Installs what a fresh Debian 12 machine lacks (idempotent), then configures and builds
# wavemmlt in ./build (Release, -O3 -march=native -ffp-contract=off -fno-math-errno
# -fno-trapping-math). Extra arguments go to cmake's configure.
set -euo pipefail
cd "$(dirname "$0")/.."

# clang and libclang-rt-14-dev (libFuzzer, the sanitizer runtimes) are for scripts/fuzz.sh;
# libsdl2-dev is for the --view window and libimgui-dev (Dear ImGui) for --interactive's panel; xvfb, xdotool and x11-apps (xwd) are for its tests;
# libopenmpi-dev and openmpi-bin (mpirun) are for one render across many ranks (docs/mpi.md);
# zlib1g-dev (zlib's inflate) is for Mitsuba's compressed serialized meshes (load_serialized.cpp);
# colord-data has the CIE 1931 observer and D65 tables that spectra are projected with (scene/spectrum.h);
# python3-dev, pybind11-dev and python3-numpy are for the Python module (docs/python.md), python3-pytest
# for its tests and python3-matplotlib for the plots bench/ draws with it.
packages=(build-essential cmake pkg-config libembree-dev libtbb-dev libopenexr-dev
          libtinyobjloader-dev libpugixml-dev catch2 libstb-dev clang libclang-rt-14-dev
          libsdl2-dev libimgui-dev xvfb xdotool x11-apps libopenmpi-dev openmpi-bin zlib1g-dev colord-data
          python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)"
