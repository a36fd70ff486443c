#!/usr/bin/env bash
# Batch speed and memory: the Cimahi data (when ../shared is there) and sample
# towns of growing size. Prints the batch's own timing line and peak RSS.
#   bash scripts/bench_batch.sh [BUILD_DIR] [SIZES...]     (default sizes: 100 1000)
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${1:-build}"; shift || true
SIZES=("$@"); [ ${#SIZES[@]} -gt 0 ] || SIZES=(100 1000)
C3D="$BUILD_DIR/cli/cadastre3d"
[ -x "$C3D" ] || { echo "bench: build $C3D first (cmake --build $BUILD_DIR --target cadastre3d)" >&2; exit 1; }
WORK="$(mktemp -d)"; trap 'rm -rf "$WORK"' EXIT

run() {  # label, batch arguments...
  local label="$1"; shift
  /usr/bin/time -f "%e s wall, %M KB peak RSS" -o "$WORK/time" "$C3D" batch "$@" > "$WORK/log" 2>&1 || true
  echo "$label: $(grep '^timing:' "$WORK/log" | sed 's/^timing: //'); $(cat "$WORK/time")"
}

D=../shared/data/cimahi
if [ -d "$D" ]; then
  run "cimahi 30 parcels (reconstruction+store only)" --cloud "$D/cimahi.las" --parcels "$D/parcels.shp" --dtm "$D/dtm.tif" --out "$WORK/cim0" --formats obj
  run "cimahi 30 parcels (all outputs)" --cloud "$D/cimahi.las" --parcels "$D/parcels.shp" --dtm "$D/dtm.tif" --out "$WORK/cim" --formats gml,cityjson,ifc,obj
fi
for n in "${SIZES[@]}"; do
  "$C3D" sample --out "$WORK/town$n" --parcels "$n" --seed 7 > /dev/null
  pts=$(python3 -c "import struct;d=open('$WORK/town$n/cloud.las','rb').read(255);print(struct.unpack('<Q',d[247:255])[0])")
  run "sample town $n parcels ($pts points)" --cloud "$WORK/town$n/cloud.las" --parcels "$WORK/town$n/parcels.gpkg" --dtm "$WORK/town$n/dtm.tif" --out "$WORK/out$n" --formats gml,cityjson,ifc,obj
  rm -rf "$WORK/town$n" "$WORK/out$n"
done
