#!/usr/bin/env bash
# Configures, builds and runs the whole test suite (the README's test command),
# then prints how many tests ran, skipped and failed (scripts/test_summary.py).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"
export CCACHE_BASEDIR="$PWD"
bash scripts/check_requirements.sh
# C3D_FUZZ_SANITIZE=ON (scripts/ci-test.sh) adds the reader fuzzer under ASan + UBSan.
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DC3D_FUZZ_SANITIZE="${C3D_FUZZ_SANITIZE:-OFF}" >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
root="$PWD"
cd "$BUILD_DIR"
rc=0
ctest --output-on-failure -j "$JOBS" --timeout 900 --output-junit "$PWD/ctest-results.xml" || rc=$?
/usr/bin/python3 "$root/scripts/test_summary.py" "$PWD/ctest-results.xml" || rc=1
exit "$rc"
