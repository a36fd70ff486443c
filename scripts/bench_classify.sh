#!/usr/bin/env bash
# Classification speed in points per CPU-second (issue 51's target: 250,000 for
# the whole `classify`, ground filter included). Lays COPIES x COPIES of the
# labelled tiles side by side (default 3: 3 million points), prints each stage's
# CPU time from inside (c3d_bench_classify), then times the whole process,
# one thread: read, terrain, features, forest, write.
# Usage: scripts/bench_classify.sh [build dir] [copies] [model]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build=${1:-$root/build}
copies=${2:-3}
model=${3:-$root/models/classifier.yml.gz}
tiles=("$root"/../shared/data/labelled/*.laz)
[ -f "${tiles[0]}" ] || { echo "bench_classify: no labelled tiles in ../shared/data/labelled" >&2; exit 1; }
cmake --build "$build" --target c3d_bench_classify cadastre3d >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/core/c3d_bench_classify" "$model" "$work/survey.las" "$copies" "${tiles[@]}"
OMP_NUM_THREADS=1 /usr/bin/time -f "%U %S %M" -o "$work/time" \
  "$build/cli/cadastre3d" classify --cloud "$work/survey.las" --out "$work/classified.las" --model "$model" \
  > "$work/log"
read -r user sys rss < "$work/time"
points=$(awk '/^classify:/ {print $2}' "$work/log")
awk -v p="$points" -v u="$user" -v s="$sys" -v m="$rss" 'BEGIN {
  printf "whole process: %d points, %.2f CPU s (user %.2f, system %.2f), %.0f points per CPU-second, peak %.0f MB\n",
         p, u + s, u, s, p / (u + s), m / 1024 }'
