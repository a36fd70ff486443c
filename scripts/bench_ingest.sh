#!/usr/bin/env bash
# LAS ingest speed in points/s: builds c3d_bench_ingest and reads a LAS file
# repeatedly (default: the Cimahi cloud, 20 reads).
# Usage: scripts/bench_ingest.sh [FILE.las] [repeats] [build dir]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
file="${1:-$root/../shared/data/cimahi/cimahi.las}"
repeats="${2:-20}"
build="${3:-$root/build-bench}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
ninja -C "$build" -j"${JOBS:-1}" c3d_bench_ingest >/dev/null
"$build/core/c3d_bench_ingest" "$file" "$repeats"
