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
# The same files through laz-perf (scripts/setup.sh installs it into tests/js),
# on this machine now: the reference the figures above are read against.
if [ -f "$root/tests/js/node_modules/laz-perf/package.json" ]; then
  (cd "$root/tests/js" && node laz_reference.js "$@")
fi
