#!/usr/bin/env bash
# How long a tileset takes to open in headless Chromium (SwiftShader): the
# page the program writes beside it (view.html: three.js, 3d-tiles-renderer)
# against the minimal CesiumJS page as the baseline, run in turns on the same
# machine, from opening the page to a frame with every tile in view loaded.
# Prints each run and the medians, and the ratio CesiumJS / own page
# (docs/report.md, "The batch in a web map"). Needs tests/js/node_modules.
#
#   bash scripts/bench_tileset_view.sh OUT/3dtiles [RUNS]   # default 5 runs each
set -euo pipefail
cd "$(dirname "$0")/.."
DIR="$(realpath "$1")"
RUNS="${2:-5}"
[ -f "$DIR/tileset.json" ] && [ -f "$DIR/view.html" ] ||
  { echo "bench_tileset_view: $DIR has no tileset.json and view.html (export --formats 3dtiles)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load_ms() {  # page options -> load_ms, or fails with the page's output
  local out
  out=$(node tests/js/tileset_view.js "$DIR" "$tmp/view.png" "$@") ||
    { echo "bench_tileset_view: the page failed: $out" >&2; return 1; }
  python3 -c 'import json,sys; print(json.load(sys.stdin)["load_ms"])' <<<"$out"
}
own=() cesium=()
for ((i = 1; i <= RUNS; ++i)); do
  c=$(load_ms --lit)
  o=$(load_ms --own --lit)
  cesium+=("$c") own+=("$o")
  echo "run $i: CesiumJS ${c} ms, own page ${o} ms"
done
python3 - "${cesium[*]}" "${own[*]}" <<'PY'
import statistics, sys
cesium, own = ([int(v) for v in arg.split()] for arg in sys.argv[1:3])
c, o = statistics.median(cesium), statistics.median(own)
print(f"median: CesiumJS {c:.0f} ms, own page {o:.0f} ms; CesiumJS / own page = {c / o:.2f}")
PY
