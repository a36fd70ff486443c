#!/usr/bin/env bash
# What `batch --mesh` costs (issue 50): the AHN3 town's batch (default
# outputs, one thread) with and without --mesh, interleaved; min-of-N
# user+sys CPU seconds and peak memory of each, the ladder's cost as a share
# of the batch's own ((mesh - plain) / plain), and the "mesh" stage against
# the other stages (summary.json's stages_cpu) of the fastest runs.
#   bash scripts/bench_mesh.sh BINARY [RUNS=3] [DATA_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${1:?binary}"; RUNS="${2:-3}"
D="${3:-../shared/data/ahn3}"
[ -d "$D" ] || { echo "bench_mesh: no data at $D" >&2; exit 1; }
WORK="$(mktemp -d)"; trap 'rm -rf "$WORK"' EXIT

for i in $(seq 1 "$RUNS"); do
  for who in plain mesh; do
    flag=""; [ "$who" = mesh ] && flag="--mesh"
    out="$WORK/$who-$i"
    /usr/bin/time -f "%U %S %M" -o "$out.time" "$BIN" batch --cloud "$D/cloud.las" \
      --parcels "$D/parcels.gpkg" --dtm "$D/dtm.tif" --out "$out" $flag \
      --quiet --jobs 1 > "$out.log" 2>&1 || true
    echo "$who run $i: $(tail -1 "$out.time" | awk '{printf "%.2f s CPU, %.0f MB peak", $1+$2, $3/1024}')"
  done
done

/usr/bin/python3 - "$WORK" "$RUNS" <<'PY'
import json, sys
work, runs = sys.argv[1], int(sys.argv[2])
def measured(who, i):
    u, s, m = open(f"{work}/{who}-{i}.time").read().split()[-3:]
    return float(u) + float(s), float(m) / 1024
best = {}
for who in ("plain", "mesh"):
    i = min(range(1, runs + 1), key=lambda i: measured(who, i)[0])
    stages = json.load(open(f"{work}/{who}-{i}/summary.json"))["timings_s"].get("stages_cpu", {})
    best[who] = (*measured(who, i), stages)
plain, mesh = best["plain"], best["mesh"]
print(f"whole process, min of {runs}: plain {plain[0]:.2f} s, --mesh {mesh[0]:.2f} s CPU; "
      f"peak {plain[1]:.0f} / {mesh[1]:.0f} MB")
print(f"ladder cost / batch's own (whole process): {(mesh[0] - plain[0]) / plain[0]:.2f}")
own = sum(v for k, v in mesh[2].items() if k != "mesh")
print(f"stage 'mesh' {mesh[2].get('mesh', 0):.2f} s / other stages {own:.2f} s CPU: "
      f"{mesh[2].get('mesh', 0) / own:.2f}")
PY
