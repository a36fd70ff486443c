#!/usr/bin/env bash
# The README's main-job command on a fresh Debian 12 machine: installs what is
# missing (scripts/setup.sh), builds the cadastre3d program (build/, Release,
# ccache), generates the sample town, runs the parcel batch on it and compares
# its models with the town's truth (scripts/compare_truth.py).
#
#   bash scripts/demo.sh            # sample town -> out/demo
#   bash scripts/demo.sh --cimahi   # also the real Cimahi data (../shared/data/cimahi) -> out/cimahi
#
# Environment: BUILD_DIR (default build), JOBS (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"

CIMAHI=0
for arg in "$@"; do
  case "$arg" in
    --cimahi) CIMAHI=1 ;;
    -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "demo: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done

BUILD_DIR="${BUILD_DIR:-build}"
JOBS="${JOBS:-$(nproc)}"

bash scripts/setup.sh

echo "demo: building cadastre3d in $BUILD_DIR (Release)"
export CCACHE_BASEDIR="$ROOT"
LAUNCHER=()
if command -v ccache >/dev/null; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "${LAUNCHER[@]}" >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS" --target cadastre3d
C3D="$ROOT/$BUILD_DIR/cli/cadastre3d"
[ -x "$C3D" ] || C3D="$BUILD_DIR/cli/cadastre3d"  # BUILD_DIR given as an absolute path

echo
echo "demo: generating the sample town (24 parcels, seed 1) in out/sample"
rm -rf out/sample out/demo
"$C3D" sample --out out/sample --parcels 24 --seed 1

echo
echo "demo: parcel batch -> out/demo"
rc=0
"$C3D" batch --cloud out/sample/cloud.las --parcels out/sample/parcels.gpkg \
  --dtm out/sample/dtm.tif --out out/demo --formats gml,cityjson,ifc,obj || rc=$?
# Exit code 3: the batch finished but some parcels failed (listed in the report).
if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
  echo "demo: batch failed (exit code $rc)" >&2
  exit "$rc"
fi

echo
echo "demo: the sample town's models against its exact truth (scripts/compare_truth.py)"
python3 scripts/compare_truth.py --quiet out/sample/truth.json out/demo/summary.json

cimahi_rc=0
if [ "$CIMAHI" -eq 1 ]; then
  DATA="$ROOT/../shared/data/cimahi"
  if [ -d "$DATA" ]; then
    echo
    echo "demo: Cimahi batch -> out/cimahi"
    rm -rf out/cimahi
    args=(--parcels "$DATA/parcels.shp" --out out/cimahi --formats gml,cityjson,ifc,obj)
    # cimahi.las holds both classes (6 roof, 64 exterior wall); else the two PLYs.
    if [ -f "$DATA/cimahi.las" ]; then
      args+=(--cloud "$DATA/cimahi.las")
    else
      args+=(--cloud "$DATA/roof.ply" --walls "$DATA/walls.ply")
    fi
    [ -f "$DATA/dtm.tif" ] && args+=(--dtm "$DATA/dtm.tif")
    "$C3D" batch "${args[@]}" || cimahi_rc=$?
    if [ "$cimahi_rc" -ne 0 ] && [ "$cimahi_rc" -ne 3 ]; then
      echo "demo: Cimahi batch failed (exit code $cimahi_rc)" >&2
    fi
  else
    echo "demo: --cimahi given but $DATA is missing; skipped" >&2
  fi
fi

show() {
  local dir="$1"
  echo "  report (open in a browser): $ROOT/$dir/report.html"
  echo "  report table:               $ROOT/$dir/report.csv"
  echo "  store (open in QGIS):       $ROOT/$dir/cadastre.gpkg"
  echo "  summary:                    $ROOT/$dir/summary.json"
  local f
  for f in buildings.gml buildings.city.json buildings.ifc; do
    [ -e "$dir/$f" ] && printf '  export:                     %s\n' "$ROOT/$dir/$f"
  done
  [ -d "$dir/obj" ] && echo "  export (OBJ, one per parcel): $ROOT/$dir/obj/"
  return 0
}

echo
echo "demo: done. Sample town batch$([ "$rc" -eq 3 ] && echo ' (some parcels failed, see the report)'):"
show out/demo
echo "  sample inputs and truth:    $ROOT/out/sample/"
if [ "$CIMAHI" -eq 1 ] && [ -f out/cimahi/summary.json ]; then
  echo "Cimahi batch$([ "$cimahi_rc" -eq 3 ] && echo ' (some parcels failed, see the report)'):"
  show out/cimahi
fi
