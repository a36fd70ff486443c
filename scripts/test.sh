#!/usr/bin/env bash
# Configures, builds and runs the whole test suite (the README's test command).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"
export CCACHE_BASEDIR="$PWD"
# C3D_FUZZ_SANITIZE=ON (scripts/ci-test.sh) adds the reader fuzzer under ASan + UBSan.
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DC3D_FUZZ_SANITIZE="${C3D_FUZZ_SANITIZE:-OFF}" >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
cd "$BUILD_DIR"
ctest --output-on-failure -j "$JOBS" --timeout 900
