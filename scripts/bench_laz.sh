#!/usr/bin/env bash
# LAZ decoding speed in points/s per core (CPU time of the one decoding
# thread): builds c3d_bench_laz (Release) and decodes each LAZ file given
# (default: every .laz in ../shared/data/laz) repeatedly.
# Usage: scripts/bench_laz.sh [FILE.laz ...]   (REPEATS=10, BUILD=build-bench)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD:-$root/build-bench}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
ninja -C "$build" -j"${JOBS:-1}" c3d_bench_laz >/dev/null
if [ $# -eq 0 ]; then set -- "$root"/../shared/data/laz/*.laz; fi
for f in "$@"; do "$build/core/c3d_bench_laz" "$f" "${REPEATS:-10}"; done
