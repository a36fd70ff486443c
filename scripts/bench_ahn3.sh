#!/usr/bin/env bash
# The AHN3 town's batch (CityJSON only, one thread), two binaries interleaved:
# min-of-N user+sys CPU seconds of each, their ratio, and each stage's CPU
# (summary.json's stages_cpu) of the fastest run. CPU time, not wall time,
# because the cores may be shared.
#   bash scripts/bench_ahn3.sh BASE_BINARY NEW_BINARY [RUNS=3] [DATA_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
BASE="${1:?baseline binary}"; NEW="${2:?new binary}"; RUNS="${3:-3}"
D="${4:-../shared/data/ahn3}"
[ -d "$D" ] || { echo "bench_ahn3: no data at $D" >&2; exit 1; }
WORK="$(mktemp -d)"; trap 'rm -rf "$WORK"' EXIT

for i in $(seq 1 "$RUNS"); do
  for who in base new; do
    bin="$BASE"; [ "$who" = new ] && bin="$NEW"
    out="$WORK/$who-$i"
    /usr/bin/time -f "%U %S" -o "$out.time" "$bin" batch --cloud "$D/cloud.las" \
      --parcels "$D/parcels.gpkg" --dtm "$D/dtm.tif" --out "$out" \
      --formats cityjson --quiet --jobs 1 > "$out.log" 2>&1 || true
    echo "$who run $i: $(tail -1 "$out.time" | awk "{printf \"%.2f s CPU\", \$1+\$2}")"
  done
done

/usr/bin/python3 - "$WORK" "$RUNS" <<'EOF'
import json, sys
work, runs = sys.argv[1], int(sys.argv[2])
def cpu(who, i):
    u, s = open(f"{work}/{who}-{i}.time").read().split()[-2:]
    return float(u) + float(s)
best = {}
for who in ("base", "new"):
    i = min(range(1, runs + 1), key=lambda i: cpu(who, i))
    summary = json.load(open(f"{work}/{who}-{i}/summary.json"))
    best[who] = (cpu(who, i), summary["timings_s"].get("stages_cpu", {}))
stages = sorted(set(best["base"][1]) | set(best["new"][1]))
print(f"{'stage (CPU s, fastest run)':28s} {'base':>8s} {'new':>8s} {'new/base':>9s}")
for k in stages:
    b, n = best["base"][1].get(k, 0.0), best["new"][1].get(k, 0.0)
    print(f"{k:28s} {b:8.2f} {n:8.2f} {n / b if b else float('nan'):9.2f}")
b, n = best["base"][0], best["new"][0]
print(f"{'total user+sys (min of %d)' % runs:28s} {b:8.2f} {n:8.2f} {n / b:9.2f}")
EOF
